//! Corrupted snapshot bytes: `restore` either refuses them with a clear error or gives
//! a layer that validates after every step; it never panics. One-bit flips and
//! four-byte overwrites at deterministic pseudo-random places of the snapshot of a
//! scene with rules, a timer, a trigger, a passive body and the monitor.
//! `CORRUPTION_TRIALS=30000 cargo test --test snapshot_corruption -- --nocapture` runs
//! more and prints the tally.
//!
//! Structural corruptions too: the snapshot as a CBOR value tree, one node of it
//! changed (a number set to an extreme, an element of a sequence or map dropped or
//! repeated, two siblings swapped), decoded again.
#![cfg(feature = "serde")]

mod common;

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::{ContactLayer, Error, LayerSnapshot, Rule};

use ciborium::Value;

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
    let n = |l: &ContactLayer, h| l.graph().try_node_of_body(h).unwrap();
    let (a, b) = (n(&layer, balls[0]), n(&layer, balls[1]));
    layer.logic_mut().add_rule(Rule::ignore_pair(a, b)).unwrap();
    layer.logic_mut().add_timer(0.07).unwrap();
    layer.logic_mut().add_timer(0.25).unwrap();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, balls[11], true)
        .unwrap();
    let (c, r) = (MonitorConfig::default(), RepairConfig::default());
    layer.monitor_mut().set(MonitorMode::Report, c, r).unwrap();
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
    try_snapshot(&snap, world_bytes)
}

fn try_snapshot(snap: &LayerSnapshot, world_bytes: &[u8]) -> Outcome {
    let mut world: PhysicsWorld = bincode::deserialize(world_bytes).unwrap();
    match ContactLayer::restore(snap, &world) {
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

/// Every node of a CBOR value tree, by path (indices into arrays and maps).
fn paths(v: &Value, at: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
    out.push(at.clone());
    let children: Vec<&Value> = match v {
        Value::Array(a) => a.iter().collect(),
        Value::Map(m) => m.iter().map(|(_, v)| v).collect(),
        Value::Tag(_, v) => vec![&**v],
        _ => Vec::new(),
    };
    for (i, c) in children.into_iter().enumerate() {
        at.push(i);
        paths(c, at, out);
        at.pop();
    }
}

fn node_at<'a>(v: &'a mut Value, path: &[usize]) -> &'a mut Value {
    let Some((&i, rest)) = path.split_first() else {
        return v;
    };
    let child = match v {
        Value::Array(a) => &mut a[i],
        Value::Map(m) => &mut m[i].1,
        Value::Tag(_, v) => &mut **v,
        _ => unreachable!("paths lead through containers"),
    };
    node_at(child, rest)
}

/// Changes one node of the tree, chosen by `r`: numbers to extremes, sequences and maps
/// shortened, lengthened or reordered.
fn mutate(v: &mut Value, r: u64) {
    let k = (r >> 8) % 6;
    match v {
        Value::Integer(i) => {
            let n: i128 = (*i).into();
            let to: i128 = match k {
                0 => 0,
                1 => u64::MAX.into(),
                2 => i64::MIN.into(),
                3 => n.saturating_add(1),
                4 => n.saturating_mul(1 << 32),
                _ => -1,
            };
            if let Ok(to) = ciborium::value::Integer::try_from(to) {
                *i = to;
            }
        }
        Value::Float(f) => {
            *f = [f64::NAN, f64::INFINITY, -*f, 0.0, f64::MAX, 1e-300][k as usize];
        }
        Value::Bool(b) => *b = !*b,
        Value::Array(a) if !a.is_empty() => {
            let i = (r as usize >> 16) % a.len();
            match k % 3 {
                0 => {
                    a.remove(i);
                }
                1 => {
                    let x = a[i].clone();
                    a.insert(i, x);
                }
                _ => {
                    let j = (i + 1) % a.len();
                    a.swap(i, j);
                }
            }
        }
        Value::Map(m) if !m.is_empty() => {
            let i = (r as usize >> 16) % m.len();
            match k % 3 {
                0 => {
                    m.remove(i);
                }
                1 => {
                    let x = m[i].clone();
                    m.insert(i, x);
                }
                _ => {
                    let j = (i + 1) % m.len();
                    let (a, b) = (m[i].1.clone(), m[j].1.clone());
                    m[i].1 = b;
                    m[j].1 = a;
                }
            }
        }
        _ => *v = Value::Null,
    }
}

#[test]
fn structurally_corrupted_snapshots_are_refused_or_restore_a_layer_that_validates() {
    let (world, layer) = scene();
    let world_bytes = bincode::serialize(&world).unwrap();
    let tree = Value::serialized(&layer.snapshot(&world)).unwrap();
    let mut all = Vec::new();
    paths(&tree, &mut Vec::new(), &mut all);
    let trials: usize = std::env::var("CORRUPTION_TRIALS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3000);
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut tally: BTreeMap<Outcome, usize> = BTreeMap::new();
    for t in 0..trials {
        let mut bad = tree.clone();
        let path = &all[(xorshift(&mut seed) % all.len() as u64) as usize];
        mutate(node_at(&mut bad, path), xorshift(&mut seed));
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            match bad.deserialized::<LayerSnapshot>() {
                Err(_) => Outcome::Undecodable,
                Ok(snap) => try_snapshot(&snap, &world_bytes),
            }
        }))
        .unwrap_or_else(|_| panic!("structural corruption {t} (node {path:?}) panicked"));
        if matches!(outcome, Outcome::Invalid(_)) {
            let mut names = Vec::new();
            let mut v = &tree;
            for &i in path.iter() {
                v = match v {
                    Value::Array(a) => {
                        names.push(format!("[{i}]"));
                        &a[i]
                    }
                    Value::Map(m) => {
                        names.push(format!("{:?}", m[i].0).chars().take(40).collect());
                        &m[i].1
                    }
                    Value::Tag(_, x) => &**x,
                    _ => v,
                };
            }
            eprintln!(
                "INVALID {t}: {} -> was {:?}",
                names.join("."),
                format!("{v:?}").chars().take(200).collect::<String>()
            );
        }
        *tally.entry(outcome).or_default() += 1;
    }
    println!(
        "{trials} structural corruptions of {} nodes: {tally:?}",
        all.len()
    );
    let invalid: Vec<_> = tally
        .iter()
        .filter(|(o, _)| matches!(o, Outcome::Invalid(_)))
        .collect();
    assert!(invalid.is_empty(), "accepted but invalid: {invalid:?}");
    assert!(tally.get(&Outcome::Refused).copied().unwrap_or(0) > 0);
}
