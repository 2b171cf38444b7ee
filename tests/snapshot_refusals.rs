//! What `restore` refuses, and how: the wrong world, a predicate rule without its
//! predicate, another format, bytes that are not a snapshot, truncated and corrupted
//! bytes (errors, never panics).
#![cfg(feature = "serde")]

mod common;
#[path = "common/twins.rs"]
mod twins;

use std::sync::Arc;

use common::audit::xorshift;
use rapier3d::prelude::*;
use rapier_contact_graph::logic::IgnorePredicate;
use rapier_contact_graph::{ContactLayer, Error, LayerSnapshot, SNAPSHOT_FORMAT};
use rcg_scenes::{self as scenes, Scene};

use twins::*;

// ── What restore refuses ────────────────────────────────────────────────────

fn saved_pile(k: u64) -> (Scene, ContactLayer) {
    let mut scene = scenes::sphere_pile(30, 3);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, k);
    (scene, layer)
}

#[test]
fn restoring_against_the_wrong_world_is_an_error() {
    let (mut scene, mut layer) = saved_pile(40);
    let snap = layer.snapshot(&scene.world);
    let is_mismatch = |r: Result<ContactLayer, Error>| match r {
        Err(Error::SnapshotMismatch(msg)) => msg,
        other => panic!("expected a mismatch, got {other:?}"),
    };
    // Another scene: names a body it lacks.
    let other = scenes::ball_on_box();
    let msg = is_mismatch(ContactLayer::restore(&snap, &other.world));
    assert!(msg.contains("lacks"), "{msg}");
    // The same world, one body removed.
    let mut fewer = load(&save(&scene.world, &layer)).0;
    let (h, _) = fewer.bodies.iter().last().unwrap();
    fewer.remove_body(h);
    let msg = is_mismatch(ContactLayer::restore(&snap, &fewer));
    assert!(msg.contains(&format!("{h:?}")), "{msg}");
    // The same world, one step later.
    let saved = load(&save(&scene.world, &layer)).0;
    common::run_validated(&mut scene, &mut layer, 40, 1);
    let msg = is_mismatch(ContactLayer::restore(&snap, &scene.world));
    assert!(msg.contains("same objects"), "{msg}");
    // The snapshot is intact: the right world restores.
    ContactLayer::restore(&snap, &saved)
        .unwrap()
        .validate(&saved)
        .unwrap();
}

#[test]
fn a_predicate_rule_needs_its_predicate_given_back() {
    let (scene, layer, predicate, _) = logic_scene();
    let bytes = save(&scene.world, &layer);
    let (world, snap) = load(&bytes);
    assert_eq!(snap.predicate_rules().len(), 1);
    assert_eq!(snap.predicate_rules()[0].0, predicate);
    assert_eq!(
        ContactLayer::restore(&snap, &world).unwrap_err(),
        Error::UnboundPredicate(predicate)
    );
    // A resolver that refuses is the same error.
    let r = ContactLayer::restore_with(&snap, &world, &mut |_, _| None);
    assert_eq!(r.unwrap_err(), Error::UnboundPredicate(predicate));
}

#[test]
fn a_snapshot_of_another_format_or_not_a_snapshot_is_an_error() {
    let (scene, layer) = saved_pile(20);
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    // Format: the second u32.
    let mut newer = bytes.clone();
    newer[4..8].copy_from_slice(&(SNAPSHOT_FORMAT + 1).to_le_bytes());
    let err = bincode::deserialize::<LayerSnapshot>(&newer)
        .unwrap_err()
        .to_string();
    let want = Error::SnapshotFormat {
        found: SNAPSHOT_FORMAT + 1,
        expected: SNAPSHOT_FORMAT,
    }
    .to_string();
    assert!(err.contains(&want), "{err}");
    // Magic: the first u32.
    let mut alien = bytes.clone();
    alien[0] ^= 0x20;
    let err = bincode::deserialize::<LayerSnapshot>(&alien)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("not a rapier-contact-graph layer snapshot"),
        "{err}"
    );
    // Rapier's world bytes are not a layer snapshot.
    let world = bincode::serialize(&scene.world).unwrap();
    assert!(bincode::deserialize::<LayerSnapshot>(&world).is_err());
}

#[test]
fn truncated_snapshots_are_errors_not_panics() {
    let (scene, layer) = saved_pile(30);
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    let stride = (bytes.len() / 1_500).max(1);
    for len in (0..bytes.len()).step_by(stride).chain([bytes.len() - 1]) {
        assert!(
            bincode::deserialize::<LayerSnapshot>(&bytes[..len]).is_err(),
            "a snapshot cut to {len} of {} bytes decoded",
            bytes.len()
        );
    }
}

#[test]
fn corrupted_snapshots_are_refused_or_restore_a_layer_that_steps_without_panicking() {
    // Rules, timers, a passive body, containers and a trigger, without speed-ups (their
    // iteration counts are taken as they come, as `speedups_mut().set` takes them, so a
    // corrupted count could make Rapier's step take arbitrarily long).
    let (mut scene, mut layer, _, _) = logic_scene();
    let predicate_of = picky_predicate(
        layer
            .graph()
            .try_node_of_body(scene.body("ground").unwrap())
            .unwrap(),
    );
    let predicate: IgnorePredicate = Arc::new(predicate_of);
    common::run_validated(&mut scene, &mut layer, 1, 60);
    let world_bytes = bincode::serialize(&scene.world).unwrap();
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    let (mut undecodable, mut refused, mut accepted) = (0, 0, 0);
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let trials = 1_500;
    for _ in 0..trials {
        let mut bad = bytes.clone();
        let pos = (xorshift(&mut seed) % bad.len() as u64) as usize;
        let bit = xorshift(&mut seed) % 8;
        bad[pos] ^= 1 << bit;
        let Ok(snap) = bincode::deserialize::<LayerSnapshot>(&bad) else {
            undecodable += 1;
            continue;
        };
        let mut world: PhysicsWorld = bincode::deserialize(&world_bytes).unwrap();
        let restored =
            ContactLayer::restore_with(&snap, &world, &mut |_, _| Some(predicate.clone()));
        match restored {
            Err(Error::Invariant(_)) | Err(Error::SnapshotMismatch(_)) => refused += 1,
            Err(e) => panic!("unexpected error {e}"),
            Ok(mut l) => {
                accepted += 1;
                for _ in 0..5 {
                    l.step(&mut world);
                    let _ = l.validate(&world);
                }
            }
        }
    }
    println!(
        "{trials} one-bit corruptions of {} bytes: {undecodable} undecodable, {refused} refused by restore, {accepted} accepted and stepped",
        bytes.len()
    );
    assert_eq!(undecodable + refused + accepted, trials);
    assert!(refused > 0, "restore's checks never fired");
}
