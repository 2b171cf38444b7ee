//! Held (fixated) bodies leave Rapier's active set: a settled pile under fixation is
//! as quiet in Rapier as a sleeping one, holds its pose bit for bit, reports fixation
//! and release as sleep and wake, and is restored exactly on release and on detach.
//! Its idle steps (nothing awake, nothing changed) change nothing, and what the user
//! changes meanwhile is still seen.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;
use rcg_scenes as scenes;

fn held_config() -> SpeedUps {
    SpeedUps {
        cache: true,
        insulate_sleepy: true,
        hold: true,
        ..SpeedUps::contact_graph()
    }
}

fn held_layer() -> ContactLayer {
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(held_config())).unwrap();
    layer
}

#[test]
fn a_settled_held_pile_leaves_rapiers_active_set() {
    let mut scene = scenes::box_pile(60, 3);
    let mut layer = held_layer();
    let stats = common::run_validated(&mut scene, &mut layer, 0, 300);
    let s = layer.speedups().unwrap().stats();
    assert_eq!(s.fixated, 60, "every box held");
    assert_eq!(s.parked, 60, "every held box out of Rapier's active set");
    assert_eq!(stats.awake_bodies, 0);
    // Rapier itself integrates nothing and keeps nothing in its active set.
    assert_eq!(scene.world.islands.active_bodies().count(), 0);
    for (_, rb) in scene.world.bodies.iter() {
        assert!(rb.is_enabled(), "parking leaves every body enabled");
    }
}

#[test]
fn parking_keeps_every_pose_bit_for_bit() {
    let mut scene = scenes::box_pile(30, 5);
    let mut layer = held_layer();
    // Until every box is held (fixed in Rapier, parked or not)...
    let mut step = 0;
    while layer.speedups().unwrap().stats().fixated < 30 {
        common::step_validated(&mut scene, &mut layer, step);
        step += 1;
        assert!(step < 400, "the pile was held");
    }
    let before = common::pose_bits(&scene.world);
    // ...then through parking and long after: nothing moves.
    common::run_validated(&mut scene, &mut layer, step, 100);
    assert_eq!(layer.speedups().unwrap().stats().parked, 30);
    assert_eq!(common::pose_bits(&scene.world), before);
}

#[test]
fn fixation_and_release_are_reported_as_sleep_and_wake() {
    let mut scene = scenes::ball_on_box();
    let bx = scene.body("box").unwrap();
    let mut layer = held_layer();
    let rx = layer.subscribe(Filter::kinds(KindSet::of(&[
        EventKind::FellAsleep,
        EventKind::WokeUp,
    ])));
    let bx_node = {
        common::run_validated(&mut scene, &mut layer, 0, 1);
        layer.graph().try_node_of_body(bx).unwrap()
    };
    let mut held_at = None;
    for step in 1..300 {
        common::step_validated(&mut scene, &mut layer, step);
        if held_at.is_none() && layer.speedups().unwrap().is_fixated(bx) {
            held_at = Some(step);
        }
    }
    let held_at = held_at.expect("the resting box was fixated");
    let slept: Vec<_> = rx
        .try_iter()
        .filter(|e| e.node1 == bx_node)
        .map(|e| (e.kind, e.step))
        .collect();
    assert_eq!(
        slept.first().map(|&(k, _)| k),
        Some(EventKind::FellAsleep),
        "{slept:?}"
    );
    // Held, released when the falling ball is about to reach it (as the ball's
    // landing wakes a sleeping box in Rapier), held again: sleep and wake alternate,
    // and it ends held.
    for (i, &(k, _)) in slept.iter().enumerate() {
        let want = if i % 2 == 0 {
            EventKind::FellAsleep
        } else {
            EventKind::WokeUp
        };
        assert_eq!(k, want, "{slept:?}");
    }
    assert_eq!(slept.len() % 2, 1, "ends held: {slept:?}");
    assert!(
        slept[0].1 <= held_at as u64 + 1,
        "{slept:?}, held at {held_at}"
    );
    assert_eq!(
        layer.analysis().stats().awake_bodies,
        0,
        "held and asleep: nothing integrated"
    );

    // A fast body hits it: released (dynamic again, back in Rapier's active set) and
    // reported awake.
    common::build::hammer(&mut scene.world);
    let mut released = false;
    for step in 300..400 {
        common::step_validated(&mut scene, &mut layer, step);
        if !layer.speedups().unwrap().is_fixated(bx) {
            released = true;
            break;
        }
    }
    assert!(released, "released when hit");
    common::run_validated(&mut scene, &mut layer, 400, 2);
    assert!(scene.world.bodies[bx].is_dynamic());
    assert!(scene.world.islands.active_bodies().any(|h| h == bx));
    let woke: Vec<_> = rx
        .try_iter()
        .filter(|e| e.node1 == bx_node)
        .map(|e| e.kind)
        .collect();
    assert_eq!(woke.first(), Some(&EventKind::WokeUp), "{woke:?}");
}

#[test]
fn detaching_restores_parked_bodies_exactly() {
    let mut scene = scenes::box_pile(20, 7);
    let mut layer = held_layer();
    common::run_validated(&mut scene, &mut layer, 0, 300);
    assert_eq!(layer.speedups().unwrap().stats().parked, 20);
    let poses = common::pose_bits(&scene.world);
    layer.speedups_mut().set(None).unwrap();
    common::run_validated(&mut scene, &mut layer, 300, 1);
    for (_, rb) in scene.world.bodies.iter().filter(|(_, rb)| !rb.is_fixed()) {
        assert!(rb.is_dynamic() && rb.is_enabled());
    }
    assert_eq!(
        scene
            .world
            .bodies
            .iter()
            .filter(|(_, rb)| rb.is_fixed())
            .count(),
        1,
        "only the ground is fixed"
    );
    // Restored at rest, where they were held.
    let after = common::pose_bits(&scene.world);
    for (a, b) in poses.iter().zip(&after) {
        let y = |p: &[u32; 7]| f32::from_bits(p[1]);
        assert!((y(a) - y(b)).abs() < 1e-3, "{} vs {}", y(a), y(b));
    }
}

#[test]
fn a_held_body_with_a_joint_stays_in_the_active_set() {
    // Disabling a body disables its joints: a held body with one is never parked.
    let (mut world, _) = common::build::world_with_ground();
    let (a, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let (b, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    world
        .impulse_joints
        .insert(a, b, RopeJointBuilder::new(5.0).build(), true);
    let mut layer = held_layer();
    for _ in 0..300 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    let s = layer.speedups().unwrap();
    assert!(s.is_fixated(a) && s.is_fixated(b));
    assert_eq!(s.stats().parked, 0);
    assert!(world.bodies[a].is_enabled() && world.bodies[b].is_enabled());
}

/// Settles a held pile until every box is held and parked; returns the next step.
fn settle_parked(scene: &mut scenes::Scene, layer: &mut ContactLayer, n: usize) -> u64 {
    let mut step = 0;
    while layer.speedups().unwrap().stats().parked < n {
        common::step_validated(scene, layer, step);
        step += 1;
        assert!(step < 600, "the pile was held and parked");
    }
    // Two more steps: the last parking's follow-up is done.
    common::run_validated(scene, layer, step, 2);
    step + 2
}

/// The graph's nodes (kind, awake, group, degree) and edge count.
fn graph_state(layer: &ContactLayer) -> String {
    let g = layer.graph();
    let nodes: Vec<String> = g
        .nodes()
        .map(|(id, n)| {
            format!(
                "{id:?} {:?} {} {:?} {}",
                n.kind(),
                n.is_awake(),
                n.group(),
                n.degree()
            )
        })
        .collect();
    format!("{} edges; {}", g.edge_count(), nodes.join(", "))
}

#[test]
fn idle_steps_of_a_held_pile_change_nothing() {
    // Nothing awake, nothing changed: the analysis of each step finds nothing to do
    // (the layer's idle path), and the graph, groups, poses and events stay as they
    // are, step after step.
    let mut scene = scenes::box_pile(60, 3);
    let mut layer = held_layer();
    let step = settle_parked(&mut scene, &mut layer, 60);
    let rx = layer.subscribe(Filter::kinds(KindSet::ALL));
    let graph = graph_state(&layer);
    let groups = layer.groups().stats();
    let poses = common::pose_bits(&scene.world);
    let stats = common::run_validated(&mut scene, &mut layer, step, 200);
    assert_eq!(stats.awake_bodies, 0);
    assert_eq!(stats.walk.bodies, 0, "no body refreshed");
    assert_eq!(rx.try_iter().count(), 0, "no event");
    assert_eq!(graph_state(&layer), graph);
    assert_eq!(layer.groups().stats(), groups);
    assert_eq!(common::pose_bits(&scene.world), poses);
}

#[test]
fn the_ground_moved_in_place_under_an_idle_held_pile_is_seen() {
    // The user moves the ground (a fixed body: no contact of it is computed with the
    // held boxes, which are fixed too) while every box is held and parked: the next
    // step finds the boxes on it unsupported and gives them back at its end.
    let mut scene = scenes::box_pile(20, 3);
    let ground = scene.body("ground").unwrap();
    let mut layer = held_layer();
    let step = settle_parked(&mut scene, &mut layer, 20);
    let s = layer.speedups().unwrap();
    assert_eq!(s.unsupported_fixated().count(), 0, "held on the ground");
    let rb = &mut scene.world.bodies[ground];
    let down = rb.translation() - Vector::new(0.0, 1.0, 0.0);
    rb.set_translation(down, true);
    common::step_validated(&mut scene, &mut layer, step);
    let s = layer.speedups().unwrap();
    let given_back = layer.analysis().given_back();
    assert!(
        !given_back.is_empty(),
        "the boxes that rested on the ground are released"
    );
    for h in given_back {
        assert!(!s.is_fixated(h) && scene.world.bodies[h].is_dynamic());
    }
}

#[test]
fn a_body_inserted_beside_an_idle_held_pile_is_analysed_at_once() {
    let mut scene = scenes::box_pile(20, 3);
    let mut layer = held_layer();
    let step = settle_parked(&mut scene, &mut layer, 20);
    let rx = layer.subscribe(Filter::kinds(KindSet::of(&[EventKind::ContactStarted])));
    let (ball, _) = scene.world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 8.0, 0.0)),
        ColliderBuilder::ball(0.2),
    );
    common::step_validated(&mut scene, &mut layer, step);
    assert!(
        layer.graph().try_node_of_body(ball).is_ok(),
        "its node at once"
    );
    assert!(layer.analysis().stats().awake_bodies >= 1);
    let ball_node = layer.graph().try_node_of_body(ball).unwrap();
    let mut landed = false;
    for k in 1..300 {
        common::step_validated(&mut scene, &mut layer, step + k);
        if rx
            .try_iter()
            .any(|e| e.node1 == ball_node || e.node2 == Some(ball_node))
        {
            landed = true;
            break;
        }
    }
    assert!(landed, "its landing is a contact event");
}
