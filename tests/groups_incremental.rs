//! Contact groups kept incrementally (paper §3.5): merges keep the larger group's id,
//! a body leaving is split off in the same step by the bounded local search, and a
//! split the search cannot settle is deferred, the group meanwhile holding whole
//! components only, until its full split (one per step) or `settle_groups`.

mod common;

use std::collections::{BTreeMap, BTreeSet};

use common::groups::components;
use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, GroupId, NodeId};
use rcg_scenes as scenes;

/// Checks the groups against the components: every component lies in one group, and a
/// group whose split is not deferred is exactly one component. Returns the number of
/// deferred groups holding more than one component.
fn check_against_components(layer: &ContactLayer, at: &str) -> usize {
    let parts = components(layer);
    let mut of: BTreeMap<NodeId, GroupId> = BTreeMap::new();
    for (gid, g) in layer.groups().iter() {
        for &n in &g.bodies {
            of.insert(n, gid);
        }
    }
    let mut per_group: BTreeMap<GroupId, usize> = BTreeMap::new();
    for part in &parts {
        let gids: BTreeSet<Option<&GroupId>> = part.iter().map(|n| of.get(n)).collect();
        assert_eq!(gids.len(), 1, "{at}: a component spans groups {gids:?}");
        if let Some(Some(&gid)) = gids.into_iter().next() {
            *per_group.entry(gid).or_default() += 1;
        }
    }
    let mut unions = 0;
    for (gid, g) in layer.groups().iter() {
        let count = per_group.get(&gid).copied().unwrap_or(0);
        if layer.groups().is_deferred(gid) {
            unions += (count > 1) as usize;
        } else {
            assert_eq!(
                count,
                1,
                "{at}: group {gid:?} ({} members) holds {count} components",
                g.bodies.len()
            );
        }
    }
    unions
}

#[test]
fn groups_stay_whole_components_at_every_step_of_a_settling_pile() {
    let mut scene = scenes::sphere_pile(300, 3);
    let mut layer = ContactLayer::new();
    let mut changed = 0;
    for step in 0..400 {
        let stats = common::step_validated(&mut scene, &mut layer, step);
        check_against_components(&layer, &format!("step {step}"));
        // 300 bodies: a local search of 1,024 expansions always finishes.
        assert_eq!(stats.groups.deferred, 0, "step {step}");
        changed += stats.groups.rebuilt;
    }
    assert!(changed > 100, "the groups changed {changed} times");
}

#[test]
fn without_a_budget_splits_are_deferred_then_settled() {
    let mut scene = scenes::sphere_pile(300, 3);
    let mut layer = ContactLayer::new();
    layer.analysis_mut().set_group_split_budget(0);
    let (mut most_deferred, mut unions_seen) = (0, 0);
    for step in 0..400 {
        let stats = common::step_validated(&mut scene, &mut layer, step);
        unions_seen += check_against_components(&layer, &format!("step {step}"));
        most_deferred = most_deferred.max(stats.groups.deferred);
    }
    assert!(
        most_deferred >= 2,
        "several splits waited at once: {most_deferred}"
    );
    assert!(
        unions_seen > 0,
        "a deferred group held two components at some step"
    );
    layer.analysis_mut().settle_groups();
    assert!(layer.groups().deferred().is_empty());
    assert_eq!(layer.analysis().stats().groups.deferred, 0);
    assert_eq!(check_against_components(&layer, "settled"), 0);
    layer.validate(&scene.world).unwrap();
    // The settled groups are those of a layer that never deferred.
    let mut exact = ContactLayer::new();
    let mut twin = scenes::sphere_pile(300, 3);
    common::run_validated(&mut twin, &mut exact, 0, 400);
    let members = |l: &ContactLayer| -> BTreeSet<BTreeSet<NodeId>> {
        l.groups()
            .iter()
            .map(|(_, g)| g.bodies.iter().copied().collect())
            .collect()
    };
    assert_eq!(members(&layer), members(&exact));
}

/// The group of a body, by the graph.
fn gid(layer: &ContactLayer, h: RigidBodyHandle) -> Option<GroupId> {
    let n = layer.graph().node_of_body(h)?;
    layer.graph().node(n)?.group()
}

/// A stack of five spheres, settled and asleep; returns the layer and the top sphere.
fn settled_stack() -> (rcg_scenes::Scene, ContactLayer, RigidBodyHandle) {
    let mut scene = scenes::sphere_stack(5);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 300);
    assert_eq!(layer.groups().len(), 1, "one stack, one group");
    let top = scene.body("s4").unwrap();
    (scene, layer, top)
}

#[test]
fn a_body_lifted_off_a_stack_leaves_in_the_same_step_and_merges_back() {
    let (mut scene, mut layer, top) = settled_stack();
    let stack = gid(&layer, top).unwrap();
    let s0 = scene.body("s0").unwrap();
    // Lift the top sphere 2 m: its touch with s3 ends in the next step.
    let rb = scene.world.bodies.get_mut(top).unwrap();
    let p = rb.translation();
    rb.set_translation(p + Vector::new(0.0, 2.0, 0.0), true);
    let mut step = 300;
    loop {
        common::step_validated(&mut scene, &mut layer, step);
        step += 1;
        let apart = gid(&layer, top) != gid(&layer, s0);
        if apart {
            break;
        }
        assert!(step < 310, "the lifted sphere never left the stack's group");
    }
    assert!(
        layer.groups().deferred().is_empty(),
        "split locally, not deferred"
    );
    assert_eq!(
        gid(&layer, s0),
        Some(stack),
        "the stack keeps its id (the search finished on the lifted side)"
    );
    let alone = gid(&layer, top).unwrap();
    assert_eq!(layer.groups().get(alone).unwrap().bodies.len(), 1);
    assert_eq!(layer.groups().get(stack).unwrap().bodies.len(), 4);
    // It falls back: the merge keeps the larger group's id and drops the small one.
    for _ in 0..200 {
        common::step_validated(&mut scene, &mut layer, step);
        step += 1;
        if gid(&layer, top) == Some(stack) {
            break;
        }
    }
    assert_eq!(gid(&layer, top), Some(stack), "merged into the stack");
    assert!(
        layer.groups().get(alone).is_none(),
        "the lone group is gone"
    );
    assert_eq!(layer.groups().get(stack).unwrap().bodies.len(), 5);
}

#[test]
fn a_group_sleeps_and_wakes_with_its_members_without_a_rebuild() {
    let (mut scene, mut layer, top) = settled_stack();
    let stack = gid(&layer, top).unwrap();
    assert!(layer.groups().get(stack).unwrap().asleep);
    scene.world.bodies.get_mut(top).unwrap().wake_up(true);
    common::step_validated(&mut scene, &mut layer, 300);
    let g = layer
        .groups()
        .get(stack)
        .expect("same group after the wake-up");
    assert!(!g.asleep, "a woken member wakes its group");
    assert_eq!(layer.analysis().stats().groups.awake_groups, 1);
}

#[test]
fn settling_with_nothing_deferred_changes_nothing() {
    let (scene, mut layer, top) = settled_stack();
    let before = gid(&layer, top);
    layer.analysis_mut().settle_groups();
    assert_eq!(gid(&layer, top), before);
    layer.validate(&scene.world).unwrap();
}
