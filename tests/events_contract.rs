//! The event layer: the listener contract holds, streams are deterministic, and
//! subscriptions never block or break a step.

mod common;

use common::contract::ContractLog;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, Error};
use rcg_scenes as scenes;

#[test]
fn the_contract_holds_in_a_settling_pile_with_removals() {
    let mut scene = scenes::sphere_pile(200, 5);
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    for step in 0..500u64 {
        if step == 250 {
            let victims: Vec<_> = scene
                .world
                .bodies
                .iter()
                .filter(|(_, b)| b.is_dynamic())
                .map(|(h, _)| h)
                .step_by(9)
                .collect();
            for h in victims {
                scene.world.remove_body(h);
            }
        }
        common::run_validated(&mut scene, &mut layer, step, 1);
        log.drain();
        log.agrees_with(&layer);
    }
    let kinds: std::collections::BTreeSet<_> = log.events.iter().map(|e| e.kind).collect();
    for k in [
        EventKind::ProximityStarted,
        EventKind::ContactStarted,
        EventKind::ContactPersisted,
        EventKind::ContactStopped,
        EventKind::ProximityStopped,
    ] {
        assert!(kinds.contains(&k), "no {k:?} in a settling pile");
    }
}

fn ball_on_box_stream() -> String {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    let mut names = common::Names::default();
    common::run_validated(&mut scene, &mut layer, 0, 1);
    names.learn(&scene, &layer);
    log.drain();
    common::run_validated(&mut scene, &mut layer, 1, 249);
    log.drain();
    log.agrees_with(&layer);
    // Persist events are many; the snapshot keeps the transitions.
    let transitions: Vec<_> = log
        .events
        .iter()
        .copied()
        .filter(|e| {
            !matches!(
                e.kind,
                EventKind::ProximityPersisted | EventKind::ContactPersisted
            )
        })
        .collect();
    common::format_events(&transitions, &names)
}

#[test]
fn ball_dropped_on_a_box_event_stream() {
    insta::assert_snapshot!("ball_on_box_events", ball_on_box_stream());
}

#[test]
fn two_identical_runs_give_identical_event_streams() {
    let run = || {
        let mut scene = scenes::sphere_pile(120, 9);
        let mut layer = ContactLayer::new();
        let rx = layer.subscribe(Filter::all());
        for step in 0..300 {
            scene.before_step(step);
            layer.step(&mut scene.world);
        }
        rx.try_iter().collect::<Vec<_>>()
    };
    let (a, b) = (run(), run());
    assert!(a.len() > 1000);
    assert_eq!(a, b);
}

#[test]
fn a_dropped_receiver_is_pruned_and_the_step_goes_on() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let keep = layer.subscribe(Filter::kinds(KindSet::CONTACT));
    let dropped = layer.subscribe(Filter::all());
    common::run_validated(&mut scene, &mut layer, 0, 10);
    drop(dropped);
    common::run_validated(&mut scene, &mut layer, 10, 100);
    assert_eq!(layer.analysis().event_bus().pruned(), 1);
    assert_eq!(layer.analysis().event_bus().len(), 1);
    assert!(keep.try_iter().any(|e| e.kind == EventKind::ContactStarted));
}

#[test]
fn a_full_bounded_channel_drops_the_newest_and_counts() {
    let mut scene = scenes::sphere_pile(100, 2);
    let mut layer = ContactLayer::new();
    let rx = layer.subscribe_bounded(Filter::all(), 16).unwrap();
    assert!(matches!(
        layer.subscribe_bounded(Filter::all(), 0),
        Err(Error::InvalidParameter { .. })
    ));
    let mut total = 0usize;
    for step in 0..200 {
        scene.before_step(step);
        total += layer.step(&mut scene.world).events;
    }
    let received = rx.try_iter().count();
    assert_eq!(received, 16, "the first 16 are kept");
    assert_eq!(layer.analysis().event_bus().dropped() as usize, total - 16);
}

#[test]
fn filters_by_kind_and_by_node() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 1);
    let ball = layer
        .graph()
        .try_node_of_body(scene.body("ball").unwrap())
        .unwrap();
    let ball_only = layer.subscribe(Filter::kinds(KindSet::CONTACT).with_nodes(&[ball]));
    let begins = layer.subscribe(Filter::kinds(KindSet::of(&[EventKind::ContactStarted])));
    common::run_validated(&mut scene, &mut layer, 1, 100);
    let got: Vec<_> = ball_only.try_iter().collect();
    assert!(!got.is_empty());
    assert!(got.iter().all(|e| e.node1 == ball || e.node2 == Some(ball)));
    assert!(got.iter().all(|e| KindSet::CONTACT.contains(e.kind)));
    assert!(begins
        .try_iter()
        .all(|e| e.kind == EventKind::ContactStarted));
}

#[test]
fn removing_a_body_ends_its_spans() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    common::run_validated(&mut scene, &mut layer, 0, 120);
    log.drain();
    assert_eq!(log.open_touch(), 2);
    let bx = scene.body("box").unwrap();
    let node = layer.graph().try_node_of_body(bx).unwrap();
    scene.world.remove_body(bx);
    common::run_validated(&mut scene, &mut layer, 120, 1);
    log.drain();
    let ends: Vec<_> = log.events.iter().filter(|e| e.step == 121).collect();
    assert!(
        ends.iter()
            .any(|e| e.kind == EventKind::ContactStopped
                && (e.node1 == node || e.node2 == Some(node)))
    );
    assert!(ends
        .iter()
        .any(|e| e.kind == EventKind::ProximityStopped && e.body1.is_some()));
    log.agrees_with(&layer);
}

#[test]
fn a_container_in_a_node_filter_matches_its_members_events() {
    let mut scene = scenes::pendulum_wall();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 1);
    let (mb, _) = layer
        .graph()
        .nodes_of_kind(rapier_contact_graph::NodeKind::Multibody)
        .next()
        .expect("the pendulum is a multibody");
    let links: Vec<_> = layer.graph().neighbors(mb).map(|(n, _, _)| n).collect();
    let rx = layer.subscribe(Filter::kinds(KindSet::CONTACT).with_nodes(&[mb]));
    common::run_validated(&mut scene, &mut layer, 1, 150);
    let got: Vec<_> = rx.try_iter().collect();
    assert!(
        got.iter().any(|e| e.kind == EventKind::ContactStarted),
        "the links hit the wall"
    );
    assert!(got
        .iter()
        .all(|e| links.contains(&e.node1) || e.node2.is_some_and(|b| links.contains(&b))));
}
