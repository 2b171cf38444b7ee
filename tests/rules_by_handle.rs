//! Rules and composites named by Rapier handles, as a Rapier user names things:
//! `layer.logic_mut().ignore_pair(&world, a, b)` with body or collider handles, the
//! node forms beside them giving the same rule, and `declare_composite` by bodies.
//! `validate()` after every step.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Rule, RuleMember, Touching};

use common::build::*;

fn run(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

/// A ground and three balls resting on it along x.
fn three_balls() -> (PhysicsWorld, RigidBodyHandle, [RigidBodyHandle; 3]) {
    let (mut world, ground) = world_with_ground();
    let balls = [-2.0, 0.0, 2.0].map(|x| ball_at(&mut world, [x, 1.0, 0.0], 0.5).0);
    (world, ground, balls)
}

#[test]
fn ignoring_a_pair_by_body_handles_lets_a_ball_fall_through_until_removed() {
    let (mut world, ground, balls) = three_balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let rule = layer
        .logic_mut()
        .ignore_pair(&world, ground, balls[1])
        .unwrap();
    // The same rule as its node form names.
    let nodes = |l: &ContactLayer, w: &PhysicsWorld| {
        (
            l.node_of_body(&w.bodies, ground).unwrap(),
            l.node_of_body(&w.bodies, balls[1]).unwrap(),
        )
    };
    let (g, b) = nodes(&layer, &world);
    let stored = layer.logic().rule(rule).expect("a rule node");
    assert!(stored.ignores(g, b) && stored.ignores(b, g));
    run(&mut layer, &mut world, 60);
    assert!(world.bodies[balls[1]].translation().y < 0.0, "fell through");
    for other in [balls[0], balls[2]] {
        assert!(layer.is_grounded(&world, other).unwrap(), "the others stay");
    }
    layer.logic_mut().remove_rule(rule).unwrap();
    assert!(layer.logic().rule(rule).is_none());
    assert!(layer.logic_mut().remove_rule(rule).is_err(), "removed once");
    run(&mut layer, &mut world, 5);
}

#[test]
fn a_collider_handle_names_its_body_and_between_names_groups() {
    let (mut world, ground, balls) = three_balls();
    let ground_collider = world.bodies[ground].colliders()[0];
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    // The ground by its collider, two balls against it.
    layer
        .logic_mut()
        .ignore_between(&world, &[ground_collider], &[balls[0], balls[2]])
        .unwrap();
    run(&mut layer, &mut world, 60);
    assert!(world.bodies[balls[0]].translation().y < 0.0);
    assert!(world.bodies[balls[2]].translation().y < 0.0);
    assert!(layer.is_grounded(&world, balls[1]).unwrap());
    // Members of mixed kinds, by `RuleMember`.
    let n = layer.node_of_body(&world.bodies, balls[1]).unwrap();
    let mixed: [RuleMember; 2] = [RuleMember::Node(n), ground_collider.into()];
    let rule = layer
        .logic_mut()
        .ignore_if(&world, &mixed, |_, _| false)
        .unwrap();
    run(&mut layer, &mut world, 10);
    assert!(
        layer.is_grounded(&world, balls[1]).unwrap(),
        "the predicate ignores nothing"
    );
    layer.logic_mut().remove_rule(rule).unwrap();
}

#[test]
fn a_sensor_named_by_its_collider_stops_seeing_an_ignored_ball() {
    let (mut world, _ground, balls) = three_balls();
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(3.0, 1.0, 1.0)
            .translation(Vector::new(0.0, 1.0, 0.0))
            .sensor(true),
        None,
    );
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let all: Vec<Touching> = balls.iter().map(|&b| Touching::Body(b)).collect();
    assert_eq!(
        layer.sensor_contents(&world.colliders, sensor).unwrap(),
        all
    );
    let rule = layer
        .logic_mut()
        .ignore_pair(&world, sensor, balls[0])
        .unwrap();
    run(&mut layer, &mut world, 5);
    assert_eq!(
        layer.sensor_contents(&world.colliders, sensor).unwrap(),
        all[1..].to_vec()
    );
    // The node form of the same rule.
    let t = layer.node_of_collider(&world, sensor).unwrap();
    let b = layer.node_of_body(&world.bodies, balls[0]).unwrap();
    assert!(layer.logic().rule(rule).unwrap().ignores(t, b));
    layer.logic_mut().remove_rule(rule).unwrap();
    let again = layer.logic_mut().add_rule(Rule::ignore_pair(t, b)).unwrap();
    run(&mut layer, &mut world, 5);
    assert_eq!(
        layer.sensor_contents(&world.colliders, sensor).unwrap(),
        all[1..].to_vec()
    );
    layer.logic_mut().remove_rule(again).unwrap();
    run(&mut layer, &mut world, 5);
    assert_eq!(
        layer.sensor_contents(&world.colliders, sensor).unwrap(),
        all
    );
}

#[test]
fn a_composite_declared_by_bodies_makes_one_group() {
    let mut world = PhysicsWorld::new();
    let (a, _) = ball_at(&mut world, [0.0, 0.0, 0.0], 0.5);
    let (b, _) = ball_at(&mut world, [5.0, 0.0, 0.0], 0.5);
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 1);
    assert_eq!(layer.group_of_body(&world.bodies, a).unwrap(), vec![a]);
    let composite = layer
        .logic_mut()
        .declare_composite(&world, &[a, b])
        .unwrap();
    run(&mut layer, &mut world, 1);
    let group = layer.group_of_body(&world.bodies, a).unwrap();
    assert!(
        group.len() == 2 && group.contains(&a) && group.contains(&b),
        "{group:?}"
    );
    layer.logic_mut().remove_composite(composite).unwrap();
    run(&mut layer, &mut world, 1);
    assert_eq!(layer.group_of_body(&world.bodies, a).unwrap(), vec![a]);
}
