//! Proximity and touching marks (paper Figs. 3 and 5) and the §3.1 obsolete test.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::{Tracking, OBSOLETE_EVERY};
use rapier_contact_graph::{ContactLayer, EdgeKind, Transition};

/// A dynamic ball flying past a fixed ball without gravity: it approaches, touches,
/// bounces off and leaves.
fn fly_by() -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle) {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    world.integration_parameters.dt = 0.01;
    let (fixed, _) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::ball(0.5).restitution(1.0),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-3.0, 0.0, 0.0))
            .linvel(Vector::new(5.0, 0.0, 0.0))
            .can_sleep(false),
        ColliderBuilder::ball(0.5).restitution(1.0),
    );
    (world, fixed, ball)
}

#[test]
fn a_fly_by_goes_through_every_mark_in_order_and_the_edge_goes_when_obsolete() {
    let (mut world, fixed, ball) = fly_by();
    // The proximity marks (paper §3.2) need every pair read: proximity tracking.
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut prox_log = Vec::new();
    let mut touch_log = Vec::new();
    let mut removed_at = None;
    let mut last_vanish_step = None;
    for _ in 0..300 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        let step = layer.analysis().current_step();
        let (nf, nb) = (
            layer.graph().try_node_of_body(fixed).unwrap(),
            layer.graph().try_node_of_body(ball).unwrap(),
        );
        match layer.graph().edge_between(nf, nb) {
            Some(eid) => {
                let e = layer.graph().edge(eid).unwrap();
                assert_eq!(e.kind(), EdgeKind::Physical);
                if let Some(m) = e.proximity_mark(step) {
                    if prox_log.last() != Some(&m) {
                        prox_log.push(m);
                    }
                    if m == Transition::Vanished {
                        last_vanish_step = Some(step);
                    }
                }
                if let Some(m) = e.touching_mark(step) {
                    if touch_log.last() != Some(&m) {
                        touch_log.push(m);
                    }
                }
                // While the edge lives, the AABB gap is at most twice the largest edge,
                // plus the distance covered while the test waits its turn (it runs
                // every OBSOLETE_EVERY steps; the ball moves 0.05 per step).
                let x = world.bodies[ball].translation().x;
                let gap = (x.abs() - 1.0).max(0.0);
                let slack = OBSOLETE_EVERY as f32 * 0.05 + 0.06;
                assert!(gap <= 2.0 + slack, "edge kept at gap {gap}");
            }
            None => {
                if removed_at.is_none() && !prox_log.is_empty() {
                    removed_at = Some(step);
                    // Removed only after the vanishing was reported, and for a reason.
                    assert!(last_vanish_step.unwrap() < step);
                    let x = world.bodies[ball].translation().x;
                    let gap = x.abs() - 1.0;
                    assert!(gap > 2.0, "removed at gap {gap}: too early");
                }
            }
        }
    }
    use Transition::*;
    assert_eq!(prox_log, vec![New, Persistent, Vanished]);
    assert_eq!(touch_log, vec![New, Persistent, Vanished]);
    assert!(removed_at.is_some(), "obsolete edge never removed");
}

#[test]
fn removing_a_body_removes_its_node_and_reports_its_edges_vanished() {
    let mut scene = rcg_scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 80);
    let bx = scene.body("box").unwrap();
    let ball = scene.body("ball").unwrap();
    let node = layer.graph().try_node_of_body(bx).unwrap();
    assert_eq!(layer.graph().node(node).unwrap().degree(), 2);

    scene.world.remove_body(bx);
    common::run_validated(&mut scene, &mut layer, 80, 1);
    assert!(layer.graph().node(node).is_none(), "node removed");
    assert_eq!(
        layer.graph().try_node_of_body(bx),
        Err(rapier_contact_graph::Error::UnknownBody(bx))
    );
    assert_eq!(layer.analysis().removed_nodes().len(), 1);
    assert_eq!(layer.analysis().removed_nodes()[0].id, node);
    let step = layer.analysis().current_step();
    let removed = layer.analysis().removed_edges();
    assert_eq!(removed.len(), 2, "ground–box and box–ball");
    for e in removed {
        assert_eq!(e.proximity_mark(step), Some(Transition::Vanished));
        assert_eq!(e.touching_mark(step), Some(Transition::Vanished));
    }
    // The ball falls on; nothing else is lost.
    let nb = layer.graph().try_node_of_body(ball).unwrap();
    assert!(layer.graph().node(nb).unwrap().is_awake());
    common::run_validated(&mut scene, &mut layer, 81, 100);
    assert!(layer.analysis().removed_edges().is_empty(), "reported once");
}

#[test]
fn stale_ids_and_foreign_handles_are_errors_not_panics() {
    use rapier_contact_graph::{Error, NodeId};
    let mut scene = rcg_scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 2);
    let foreign = RigidBodyHandle::from_raw_parts(999, 0);
    assert_eq!(
        layer.graph().try_node_of_body(foreign),
        Err(Error::UnknownBody(foreign))
    );
    let bogus = NodeId::from_raw_parts(12345, 0);
    assert_eq!(
        layer.graph().try_node(bogus).map(|x| x.kind()),
        Err(Error::StaleNode(bogus))
    );
    assert_eq!(
        layer.analysis().is_supported(bogus),
        Err(Error::StaleNode(bogus))
    );
    assert!(layer.graph().try_body_of(bogus).is_err());
    assert_eq!(layer.graph().neighbors(bogus).count(), 0);
    let ground = layer
        .graph()
        .try_node_of_body(scene.body("ground").unwrap())
        .unwrap();
    assert!(matches!(
        layer.graph().try_edge_between(ground, bogus),
        Err(Error::StaleNode(_))
    ));
    let bad_collider = ColliderHandle::from_raw_parts(777, 3);
    assert_eq!(
        layer.node_of_collider(&scene.world, bad_collider),
        Err(Error::UnknownCollider(bad_collider))
    );
}

#[test]
fn a_non_finite_body_does_not_poison_the_graph() {
    let mut scene = rcg_scenes::sphere_stack(3);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 30);
    let top = scene.body("s2").unwrap();
    let mid = scene.body("s1").unwrap();
    let (n_top, n_mid) = (
        layer.graph().try_node_of_body(top).unwrap(),
        layer.graph().try_node_of_body(mid).unwrap(),
    );

    // A NaN velocity: Rapier quarantines the body (disables it, resets its pose); the
    // graph keeps the node, its contact vanishes, and everything stays valid.
    scene.world.bodies[top].set_linvel(Vector::new(f32::NAN, 0.0, 0.0), true);
    let mut quarantined = false;
    for step in 30..40 {
        scene.before_step(step);
        layer.step(&mut scene.world);
        quarantined |= scene.world.quarantine().bodies().contains(&top);
        layer.validate(&scene.world).unwrap();
    }
    assert!(quarantined, "Rapier quarantined the body");
    assert!(layer.graph().node(n_top).is_some(), "the node is kept");
    let e = layer.graph().edge_between(n_mid, n_top);
    assert!(e.is_none_or(|e| !layer.graph().edge(e).unwrap().is_touching()));

    // A NaN pose seen by the analysis (a user who corrupts a body and analyses before
    // Rapier's next step): flagged, no NaN cached, no edge dropped for it.
    scene.world.bodies[top].set_enabled(true);
    common::run_validated(&mut scene, &mut layer, 40, 5);
    let edges = layer.graph().edge_count();
    scene.world.bodies[mid].set_translation(Vector::new(f32::NAN, f32::NAN, 0.0), true);
    layer.analyze((&scene.world).into());
    layer.graph().validate().unwrap();
    assert!(layer.graph().node(n_mid).unwrap().is_non_finite());
    assert_eq!(
        layer.graph().edge_count(),
        edges,
        "no edge dropped for a NaN pose"
    );
    for (_, e) in layer.graph().edges() {
        let c = e.cache();
        assert!(c.relative_pose.translation.is_finite(), "no NaN cached");
        assert!(!c.max_penetration.is_nan() && !c.normal_impulse.is_nan());
    }
    let s0 = layer
        .graph()
        .try_node_of_body(scene.body("s0").unwrap())
        .unwrap();
    let ground = layer
        .graph()
        .try_node_of_body(scene.body("ground").unwrap())
        .unwrap();
    let e = layer.graph().edge_between(ground, s0).unwrap();
    assert!(
        layer.graph().edge(e).unwrap().is_touching(),
        "the rest is intact"
    );
}
