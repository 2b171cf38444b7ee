//! A held body keeps its contacts as a sleeping one does (paper §7, fixation): holding
//! a pile ends no contact, the queries answer for a held body as before it was held,
//! and a released body that still touches starts no contact again. Rapier keeps a
//! held (fixed) body's pairs with what stands still but computes no contact for them;
//! the graph keeps those contacts frozen (`ContactGraph::is_frozen`). Checked under
//! the default (touching) tracking and under proximity tracking, `validate()` after
//! every step.

mod common;

use std::collections::{HashMap, HashSet};

use rapier3d::prelude::*;
use rapier_contact_graph::events::KindSet;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Event, EventKind, Filter, Touching};
use rcg_scenes as scenes;

/// A pile of 18 boxes, the preset that holds it, and a subscription: contact starts
/// and stops (touching tracking), or every kind (proximity tracking).
fn held_pile(
    proximity: bool,
) -> (
    scenes::Scene,
    ContactLayer,
    crossbeam_channel::Receiver<Event>,
) {
    let scene = scenes::box_pile(18, 3);
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    let kinds = if proximity {
        KindSet::ALL
    } else {
        KindSet::COLLISION_EVENTS
    };
    let rx = layer.subscribe(Filter::kinds(kinds));
    (scene, layer, rx)
}

/// What `h` touches and what holds it up, by the layer's queries.
fn answers(
    layer: &ContactLayer,
    world: &PhysicsWorld,
    h: RigidBodyHandle,
) -> (Vec<Touching>, Vec<Touching>) {
    (
        layer.touching_body(&world.bodies, h).unwrap(),
        layer.supports_of_body(world, h, 0.5).unwrap(),
    )
}

fn step(scene: &mut scenes::Scene, layer: &mut ContactLayer) {
    layer.step(&mut scene.world);
    layer.validate(&scene.world).unwrap();
}

#[test]
fn holding_a_pile_ends_no_contact_and_the_queries_answer_as_before() {
    for proximity in [false, true] {
        let (mut scene, mut layer, rx) = held_pile(proximity);
        let boxes = scene.dynamic_bodies();
        // The answers each box gave at the last step before it was held.
        let mut before: HashMap<RigidBodyHandle, (Vec<Touching>, Vec<Touching>)> = HashMap::new();
        let mut last: HashMap<RigidBodyHandle, (Vec<Touching>, Vec<Touching>)> = HashMap::new();
        let mut stopped_while_held = Vec::new();
        let mut compared = 0;
        for _ in 0..600 {
            step(&mut scene, &mut layer);
            let held: HashSet<RigidBodyHandle> = boxes
                .iter()
                .copied()
                .filter(|&h| layer.speedups().unwrap().is_fixated(h))
                .collect();
            for e in rx.try_iter() {
                let names_held = [e.body1, e.body2]
                    .iter()
                    .flatten()
                    .any(|h| held.contains(h));
                if e.kind == EventKind::ContactStopped && names_held {
                    stopped_while_held.push(e);
                }
            }
            for &h in &boxes {
                let now = answers(&layer, &scene.world, h);
                if held.contains(&h) {
                    let first = before.entry(h).or_insert_with(|| last[&h].clone());
                    assert_eq!(&now, first, "proximity {proximity}: held {h:?}");
                    compared += 1;
                } else {
                    before.remove(&h);
                }
                last.insert(h, now);
            }
        }
        assert!(
            compared > 0,
            "proximity {proximity}: the preset held the pile"
        );
        assert_eq!(stopped_while_held, vec![], "proximity {proximity}");
        // The held boxes rest on something, as they did.
        assert!(before.values().all(|(touching, _)| !touching.is_empty()));
    }
}

#[test]
fn a_held_body_the_user_takes_back_starts_no_contact_it_kept() {
    for proximity in [false, true] {
        let (mut scene, mut layer, rx) = held_pile(proximity);
        let boxes = scene.dynamic_bodies();
        let mut taken = None;
        for _ in 0..600 {
            step(&mut scene, &mut layer);
            rx.try_iter().for_each(drop);
            taken = boxes
                .iter()
                .copied()
                .find(|&h| layer.speedups().unwrap().is_fixated(h));
            if taken.is_some() {
                break;
            }
        }
        let h = taken.expect("the preset held a box");
        let kept = layer.touching_body(&scene.world.bodies, h).unwrap();
        assert!(!kept.is_empty());
        // The user makes it dynamic again (as Rapier's API allows on any body).
        scene.world.bodies[h].set_body_type(RigidBodyType::Dynamic, true);
        for _ in 0..3 {
            step(&mut scene, &mut layer);
            for e in rx.try_iter() {
                let names = [e.body1, e.body2].contains(&Some(h));
                if names && e.kind == EventKind::ContactStarted {
                    let other = if e.body1 == Some(h) { e.body2 } else { e.body1 };
                    let other = other
                        .map(Touching::Body)
                        .or(e.collider2.map(Touching::Collider));
                    assert!(
                        other.is_none_or(|o| !kept.contains(&o)),
                        "proximity {proximity}: a kept contact started again: {e:?}"
                    );
                }
            }
        }
        assert!(!layer.speedups().unwrap().is_fixated(h));
    }
}
