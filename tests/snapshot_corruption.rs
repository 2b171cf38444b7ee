//! Corrupted snapshot bytes: `restore` either refuses them with a clear error or gives
//! a layer that validates after every step; it never panics. One-bit flips and
//! four-byte overwrites at deterministic pseudo-random places of the snapshot of a
//! scene with rules, a timer, a trigger, a passive body and the monitor.
//! `CORRUPTION_TRIALS=30000 cargo test --test snapshot_corruption -- --nocapture` runs
//! more and prints the tally.
#![cfg(feature = "serde")]

mod common;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::{ContactLayer, Error, LayerSnapshot, Rule};

use common::audit::xorshift;
use common::build::*;

/// A pile of balls on a ground, a rule, two timers, a sensor and a passive ball.
fn scene() -> (PhysicsWorld, ContactLayer) {
    let (mut world, _) = world_with_ground();
    let mut balls = Vec::new();
    for i in 0..12 {
        let (x, y) = ((i % 4) as f32 * 0.9 - 1.4, 0.6 + (i / 4) as f32 * 1.0);
        balls.push(ball_at(&mut world, [x, y, 0.0], 0.4).0);
    }
    let sensor =
        world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.5, 0.0)));
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.5, 1.0).sensor(true),
        Some(sensor),
    );
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let n = |l: &ContactLayer, h| l.node_of_body(h).unwrap();
    let (a, b) = (n(&layer, balls[0]), n(&layer, balls[1]));
    layer.add_rule(Rule::ignore_pair(a, b)).unwrap();
    layer.add_timer(0.07).unwrap();
    layer.add_timer(0.25).unwrap();
    layer.set_passive(balls[11], true).unwrap();
    let (c, r) = (MonitorConfig::default(), RepairConfig::default());
    layer.set_monitor(MonitorMode::Report, c, r).unwrap();
    for _ in 0..40 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    (world, layer)
}

/// What became of one corrupted snapshot.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Undecodable,
    Refused,
    Accepted,
    /// Accepted, then `validate()` failed at a step after: the message's first words.
    Invalid(String),
}

fn try_corruption(bad: &[u8], world_bytes: &[u8]) -> Outcome {
    let Ok(snap) = bincode::deserialize::<LayerSnapshot>(bad) else {
        return Outcome::Undecodable;
    };
    let mut world: PhysicsWorld = bincode::deserialize(world_bytes).unwrap();
    match ContactLayer::restore(&snap, &world) {
        Err(Error::Invariant(_)) | Err(Error::SnapshotMismatch(_)) => Outcome::Refused,
        Err(e) => panic!("unexpected error {e}"),
        Ok(mut layer) => {
            if let Err(e) = layer.validate(&world) {
                return Outcome::Invalid(format!("at restore: {e}"));
            }
            for _ in 0..3 {
                layer.step(&mut world);
                if let Err(e) = layer.validate(&world) {
                    return Outcome::Invalid(e.to_string());
                }
            }
            Outcome::Accepted
        }
    }
}

#[test]
fn corrupted_snapshots_are_refused_or_restore_a_layer_that_validates() {
    let (world, layer) = scene();
    let world_bytes = bincode::serialize(&world).unwrap();
    let bytes = bincode::serialize(&layer.snapshot(&world)).unwrap();
    let trials: usize = std::env::var("CORRUPTION_TRIALS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut tally: BTreeMap<Outcome, usize> = BTreeMap::new();
    for t in 0..trials {
        let mut bad = bytes.clone();
        let pos = (xorshift(&mut seed) % bad.len() as u64) as usize;
        if t % 2 == 0 {
            bad[pos] ^= 1 << (xorshift(&mut seed) % 8);
        } else {
            let word = xorshift(&mut seed).to_le_bytes();
            for (k, b) in word[..4].iter().enumerate() {
                if let Some(slot) = bad.get_mut(pos + k) {
                    *slot = *b;
                }
            }
        }
        let outcome = catch_unwind(AssertUnwindSafe(|| try_corruption(&bad, &world_bytes)))
            .unwrap_or_else(|_| panic!("corruption {t} (byte {pos}) panicked"));
        *tally.entry(outcome).or_default() += 1;
    }
    println!("{trials} corruptions of {} bytes: {tally:?}", bytes.len());
    let invalid: Vec<_> = tally
        .iter()
        .filter(|(o, _)| matches!(o, Outcome::Invalid(_)))
        .collect();
    assert!(invalid.is_empty(), "accepted but invalid: {invalid:?}");
    assert!(tally.get(&Outcome::Refused).copied().unwrap_or(0) > 0);
}
