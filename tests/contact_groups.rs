//! Contact groups (Figs. 7–8) equal connected components computed independently with
//! petgraph, with fixed and scripted bodies insulating.

mod common;

use std::collections::BTreeSet;

use common::build::box_at;
use common::groups::components;
use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, NodeId};
use rcg_scenes::{self as scenes, Scene};

fn groups(layer: &ContactLayer) -> BTreeSet<BTreeSet<NodeId>> {
    layer
        .groups()
        .iter()
        .map(|(_, g)| g.bodies.iter().copied().collect())
        .collect()
}

fn check_scene(mut scene: Scene, steps: u64, every: u64) -> ContactLayer {
    let mut layer = ContactLayer::new();
    let mut step = 0;
    while step < steps {
        common::run_validated(&mut scene, &mut layer, step, every);
        step += every;
        assert_eq!(
            groups(&layer),
            components(&layer),
            "{} at step {step}",
            scene.name
        );
        // Each group's counts are the sums over its edges.
        for (_, grp) in layer.groups().iter() {
            let contacts: u32 = grp
                .edges
                .iter()
                .map(|&e| layer.graph().edge(e).unwrap().cache().contact_count)
                .sum();
            assert_eq!(grp.contacts, contacts);
            assert_eq!(grp.variables, 3 * contacts);
        }
    }
    layer
}

#[test]
fn groups_equal_components_in_a_settling_pile() {
    let layer = check_scene(scenes::sphere_pile(300, 3), 600, 20);
    let s = layer.analysis().stats().groups;
    assert!(s.largest_bodies > 10, "the pile forms large groups: {s:?}");
}

#[test]
fn a_fixed_wall_insulates_two_piles() {
    let layer = check_scene(scenes::two_piles_with_wall(), 120, 1);
    assert_eq!(layer.groups().len(), 2);
    for (_, g) in layer.groups().iter() {
        assert_eq!(g.bodies.len(), 4);
        assert_eq!(g.insulators.len(), 2, "ground and wall");
    }
}

#[test]
fn a_scripted_platform_insulates_the_boxes_it_carries() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world.insert(
        RigidBodyBuilder::kinematic_velocity_based().linvel(Vector::new(0.2, 0.0, 0.0)),
        ColliderBuilder::cuboid(3.0, 0.1, 1.0),
    );
    for x in [-2.0, 2.0] {
        box_at(&mut world, [x, 0.36, 0.0], 0.25);
    }
    let scene = Scene {
        name: "platform_two_boxes",
        world,
        bodies: vec![],
        script: None,
    };
    let layer = check_scene(scene, 100, 1);
    assert_eq!(
        layer.groups().len(),
        2,
        "the platform does not join the boxes"
    );
}

#[test]
fn groups_follow_removals_and_wake_ups() {
    let mut scene = scenes::sphere_stack(5);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 300);
    assert_eq!(layer.analysis().stats().awake_bodies, 0, "the stack sleeps");
    assert_eq!(layer.groups().len(), 1);
    let (_, g) = layer.groups().iter().next().unwrap();
    assert!(g.asleep);
    // Removing the middle sphere splits the stack; the top falls onto the rest.
    let mid = scene.body("s2").unwrap();
    scene.world.remove_body(mid);
    let mut seen_two = false;
    for step in 300..500 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        assert_eq!(groups(&layer), components(&layer), "step {step}");
        seen_two |= layer.groups().len() == 2;
    }
    assert!(seen_two, "the stack split while the top fell");
    assert_eq!(layer.groups().len(), 1, "and merged again");
}

#[test]
fn a_settled_scene_costs_no_pair_walk() {
    let mut scene = scenes::sphere_stack(5);
    let mut layer = ContactLayer::new();
    let stats = common::run_validated(&mut scene, &mut layer, 0, 400);
    assert_eq!(stats.awake_bodies, 0);
    assert_eq!(stats.walk.bodies, 0, "{stats:?}");
    assert_eq!(stats.walk.collider_pairs, 0);
    assert_eq!(stats.groups.rebuilt, 0);
    assert_eq!(stats.groups.count, 1);
}

#[test]
fn a_world_built_in_contact_builds_each_group_once() {
    // Every body is new and touches at the first step: one traversal builds the
    // groups, none is built for a single body first and dissolved again.
    let mut scene = scenes::stability::pyramid::pyramid_of(8);
    let mut layer = ContactLayer::new();
    let stats = common::run_validated(&mut scene, &mut layer, 0, 1);
    assert!(stats.groups.count >= 1);
    assert_eq!(
        stats.groups.rebuilt, stats.groups.count,
        "{:?}",
        stats.groups
    );
    assert_eq!(groups(&layer), components(&layer));
}
