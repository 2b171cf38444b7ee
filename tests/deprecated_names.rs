//! The names of 0.1 (the paper's: rigid, scripted, trigger, passive, touch begin / end)
//! still compile as deprecated aliases of Rapier's names, in expressions and match
//! patterns, and behave as the new ones: a user's code written against 0.1 keeps
//! working, with deprecation warnings naming the replacement.
#![allow(deprecated)]

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet, NodeKind};

use common::build::*;

/// A ground and a ball about to land on it.
fn ball_on_ground() -> (PhysicsWorld, RigidBodyHandle, ContactLayer) {
    let (mut world, _) = world_with_ground();
    let (ball, _) = ball_at(&mut world, [0.0, 1.2, 0.0], 0.5);
    (world, ball, ContactLayer::new())
}

#[test]
fn old_event_names_subscribe_and_match_as_the_new_ones() {
    let (mut world, ball, mut layer) = ball_on_ground();
    let old = layer.subscribe(Filter::kinds(KindSet::TOUCH).or_kind(EventKind::TriggerEnter));
    let new = layer.subscribe(Filter::kinds(KindSet::CONTACT).or_kind(EventKind::SensorStarted));
    for _ in 0..60 {
        layer.step(&mut world);
    }
    let (old, new): (Vec<_>, Vec<_>) = (old.try_iter().collect(), new.try_iter().collect());
    assert!(!new.is_empty());
    assert_eq!(old, new);
    let began = new
        .iter()
        .filter(|e| matches!(e.kind, EventKind::TouchBegin))
        .count();
    assert_eq!(began, 1, "the ball lands once");
    let node = layer.node_of_body(ball).unwrap();
    let kind = layer.graph().node(node).unwrap().kind();
    assert!(matches!(kind, NodeKind::Rigid));
    assert_eq!(kind, NodeKind::Dynamic);
}

#[test]
fn set_passive_forwards_to_set_body_disabled() {
    let (mut world, ball, mut layer) = ball_on_ground();
    for _ in 0..60 {
        layer.step(&mut world);
    }
    layer.set_passive(ball, true).unwrap();
    layer.step(&mut world);
    let node = layer.node_of_body(ball).unwrap();
    let n = layer.graph().node(node).unwrap();
    assert!(n.is_passive() && n.is_body_disabled());
    assert_eq!(n.degree(), 0);
    assert!(!world.bodies[ball].is_enabled());
    layer.set_passive(ball, false).unwrap();
    layer.step(&mut world);
    let n = layer.graph().node(node).unwrap();
    assert!(!n.is_passive() && !n.is_body_disabled());
    assert!(world.bodies[ball].is_enabled());
}

#[cfg(feature = "debug-render")]
#[test]
fn the_old_body_state_name_is_the_new_one() {
    use rapier_contact_graph::BodyState;
    assert_eq!(BodyState::Passive, BodyState::Disabled);
    assert_eq!(BodyState::Disabled.name(), "disabled");
}
