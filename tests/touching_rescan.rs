//! Touching tracking's rescan (a body whose colliders changed has its touching pairs
//! counted again) after the step's collision events already changed an edge: the
//! rescan's count wins, and an edge it leaves with no touching pair is gone from the
//! step's touched edges as well as from the graph.

mod common;

use common::build::{arena_floor, dynamic_at, fixed_at};
use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Rule};

/// Steps through the layer `n` times, `validate()` after each (its debug assertions
/// run inside the step).
fn steps(layer: &mut ContactLayer, world: &mut PhysicsWorld, n: usize) {
    for _ in 0..n {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

/// The fuzzer's shrunk sequence: colliders added to the ground; a fixed and a
/// dynamic body; a collider added to the new body; 89 steps; a collider removed and
/// another added; a predicate rule on the body; three bodies added at the origin
/// (overlapping); a collider removed; steps. It tripped the debug assertion that
/// every touched edge exists (the rescan removed an edge the events had touched).
#[test]
fn a_touch_the_events_began_and_the_rescan_ended_leaves_a_valid_step() {
    let mut world = PhysicsWorld::new();
    let (g, _) = arena_floor(&mut world);
    let at = |x: f32, y: f32| Vector::new(x, y, 0.0);
    world.insert_collider(
        ColliderBuilder::cuboid(0.2, 0.2, 0.2).translation(at(1.0, 0.3)),
        Some(g),
    );
    world.insert_collider(
        ColliderBuilder::ball(0.3).translation(at(-1.0, 0.3)),
        Some(g),
    );
    world.insert(
        fixed_at([0.5, 0.5, 0.5]),
        ColliderBuilder::cuboid(0.25, 0.25, 0.25),
    );
    let (d, _) = world.insert(dynamic_at([0.0, 1.0, 0.0]), ColliderBuilder::ball(0.25));
    let extra = world.insert_collider(ColliderBuilder::cuboid(0.2, 0.2, 0.2), Some(d));
    let mut layer = ContactLayer::new();
    steps(&mut layer, &mut world, 89);

    world.remove_collider(extra);
    world.insert_collider(ColliderBuilder::ball(0.2), Some(d));
    let n = layer.graph().node_of_body(d).unwrap();
    layer
        .logic_mut()
        .add_rule(Rule::ignore_if(&[n], |_, _| true))
        .unwrap();
    let added: Vec<_> = (0..3)
        .map(|_| world.insert(dynamic_at([0.0, 0.0, 0.0]), ColliderBuilder::ball(0.25)))
        .collect();
    world.remove_collider(added[0].1);
    steps(&mut layer, &mut world, 20);
    // The rule holds: the body touches nothing, by the layer and by Rapier.
    assert_eq!(layer.touching_body(&world.bodies, d).unwrap(), vec![]);
}
