//! Steps the layer did not see: the user's own `world.step()` between two
//! `ContactLayer::step`s, and two layers taking turns on one world. Touching
//! tracking (the default) learns what changed from Rapier's collision events, which
//! such a step sends elsewhere; the layer notices the step at its next pre-step and
//! reads the world in full once (`StepStats::walk.unseen_step`). Checked after every
//! step the layer analyses: `validate()`, and every body's touching set equal to
//! Rapier's.

mod common;

use common::build::{box_at, ground, rapier_touching};
use rapier3d::prelude::*;
use rapier_contact_graph::events::KindSet;
use rapier_contact_graph::{ContactLayer, EventKind, Filter};

/// A stack of `n` cubes (half extent 0.25) over the ground, 0.1 m apart: they fall
/// onto each other over the first steps, so that contacts begin throughout.
fn stack(n: usize) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld::new();
    ground(&mut world);
    let cubes = (0..n)
        .map(|i| box_at(&mut world, [0.0, 0.85 + 0.6 * i as f32, 0.0], 0.25).0)
        .collect();
    (world, cubes)
}

/// `validate()` holds, and every body touches what Rapier says it touches.
fn agrees(layer: &ContactLayer, world: &PhysicsWorld, step: usize) {
    layer
        .validate(&*world)
        .unwrap_or_else(|e| panic!("step {step}: {e}"));
    for (h, _) in world.bodies.iter() {
        let mine: std::collections::BTreeSet<String> = layer
            .touching_body(&world.bodies, h)
            .unwrap()
            .iter()
            .map(|t| format!("{t:?}"))
            .collect();
        assert_eq!(mine, rapier_touching(world, h), "step {step}, body {h:?}");
    }
}

#[test]
fn a_step_the_user_took_directly_is_read_at_the_next_layer_step() {
    let (mut world, _) = stack(10);
    let mut layer = ContactLayer::new();
    let mut unseen = 0;
    let mut reported = 0;
    for step in 0..300 {
        if step % 7 == 6 {
            world.step();
            unseen += 1;
            continue;
        }
        let stats = layer.step(&mut world);
        assert!(
            layer.analysis().touching_in_effect(),
            "step {step}: touching tracking"
        );
        reported += usize::from(stats.walk.unseen_step);
        agrees(&layer, &world, step);
    }
    // Every missed step while something moved is noticed (the stack settles and
    // sleeps late in the run: a step of a sleeping world changes nothing to notice).
    assert!(reported > 0 && reported <= unseen, "{reported} of {unseen}");
}

#[test]
fn a_layer_that_sees_every_step_reports_none_unseen() {
    let (mut world, cubes) = stack(10);
    let mut layer = ContactLayer::new();
    for step in 0..200 {
        // The user's own writes between steps are no step: a push on one cube, a
        // wake-up of another.
        if step % 5 == 0 {
            world.bodies[cubes[3]].apply_impulse(Vector::new(0.2, 0.0, 0.0), true);
            world.bodies[cubes[7]].wake_up(true);
        }
        let stats = layer.step(&mut world);
        assert!(!stats.walk.unseen_step, "step {step}");
        agrees(&layer, &world, step);
    }
}

#[test]
fn a_contact_that_began_in_an_unseen_step_is_reported_at_the_next() {
    let mut world = PhysicsWorld::new();
    ground(&mut world);
    // A cube 0.5 m above the ground, falling onto it.
    let (cube, _) = box_at(&mut world, [0.0, 1.25, 0.0], 0.25);
    let mut layer = ContactLayer::new();
    let rx = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS));
    layer.step(&mut world);
    assert!(layer.touching_body(&world.bodies, cube).unwrap().is_empty());
    // Steps the layer does not see until the cube lands.
    while rapier_touching(&world, cube).is_empty() {
        world.step();
    }
    let stats = layer.step(&mut world);
    assert!(stats.walk.unseen_step);
    agrees(&layer, &world, 1);
    let started: Vec<_> = rx
        .try_iter()
        .filter(|e| e.kind == EventKind::ContactStarted)
        .collect();
    assert_eq!(started.len(), 1, "{started:?}");
    assert!([started[0].body1, started[0].body2].contains(&Some(cube)));
}

#[test]
fn two_layers_taking_turns_on_one_world_each_stay_exact() {
    let (mut world, _) = stack(10);
    let mut a = ContactLayer::new();
    let mut b = ContactLayer::new();
    for step in 0..300 {
        let layer = if step % 2 == 0 { &mut a } else { &mut b };
        layer.step(&mut world);
        agrees(layer, &world, step);
    }
}

/// Proximity tracking reads the pairs of every body awake now or at the last
/// analysis, but not those of a body the user woke and put back to sleep around a
/// missed step: it reads the world once after a missed step too.
#[test]
fn proximity_tracking_reads_the_world_once_after_an_unseen_step() {
    let (mut world, _) = stack(10);
    let mut layer = ContactLayer::new();
    layer.set_tracking(rapier_contact_graph::coherence::Tracking::Proximity);
    let mut reported = 0;
    for step in 0..150 {
        if step % 7 == 6 {
            world.step();
            continue;
        }
        let stats = layer.step(&mut world);
        reported += usize::from(stats.walk.unseen_step);
        agrees(&layer, &world, step);
    }
    assert!(reported > 0);
}
