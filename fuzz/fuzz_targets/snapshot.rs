//! cargo-fuzz target: corrupted snapshot bytes. The fuzzer's bytes are edits applied
//! to the bincode snapshot of a scene with rules, timers, a trigger, a passive body
//! and the monitor (the scene of `tests/snapshot_corruption.rs`): each edit is three
//! bytes, a position (two bytes, modulo the length) and a value to XOR in; a first
//! byte `0xFF` instead takes the rest of the input as the whole snapshot. Asserts what
//! `restore` promises: it never panics, and a layer it accepts validates at
//! restore and after each of three steps.

#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, LayerSnapshot, Rule};

/// The world's bytes and the layer's snapshot bytes, made once.
fn baseline() -> &'static (Vec<u8>, Vec<u8>) {
    static BASE: OnceLock<(Vec<u8>, Vec<u8>)> = OnceLock::new();
    BASE.get_or_init(|| {
        let mut world = PhysicsWorld::new();
        world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
        let mut balls = Vec::new();
        for i in 0..12 {
            let (x, y) = ((i % 4) as f32 * 0.9 - 1.4, 0.6 + (i / 4) as f32 * 1.0);
            let at = Vector::new(x, y, 0.0);
            let (h, _) = world.insert(
                RigidBodyBuilder::dynamic().translation(at),
                ColliderBuilder::ball(0.4),
            );
            balls.push(h);
        }
        let post = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.5, 0.0)));
        world.insert_collider(ColliderBuilder::cuboid(1.0, 0.5, 1.0).sensor(true), Some(post));
        let mut layer = ContactLayer::new();
        layer.step(&mut world);
        let a = layer.node_of_body(balls[0]).unwrap();
        let b = layer.node_of_body(balls[1]).unwrap();
        layer.add_rule(Rule::ignore_pair(a, b)).unwrap();
        layer.add_timer(0.07).unwrap();
        layer.set_body_disabled(balls[11], true).unwrap();
        for _ in 0..40 {
            layer.step(&mut world);
        }
        let world_bytes = bincode::serialize(&world).unwrap();
        let snap = bincode::serialize(&layer.snapshot(&world)).unwrap();
        (world_bytes, snap)
    })
}

fuzz_target!(|data: &[u8]| {
    let (world_bytes, snap) = baseline();
    let bytes = if data.first() == Some(&0xFF) {
        data[1..].to_vec()
    } else {
        let mut bytes = snap.clone();
        for edit in data.chunks_exact(3) {
            let pos = usize::from(u16::from_le_bytes([edit[0], edit[1]])) % bytes.len();
            bytes[pos] ^= edit[2];
        }
        bytes
    };
    let Ok(snap) = bincode::deserialize::<LayerSnapshot>(&bytes) else {
        return;
    };
    let mut world: PhysicsWorld = bincode::deserialize(world_bytes).unwrap();
    let Ok(mut layer) = ContactLayer::restore(&snap, &world) else {
        return;
    };
    layer.validate(&world).expect("an accepted restore validates");
    for step in 0..3 {
        layer.step(&mut world);
        if let Err(e) = layer.validate(&world) {
            panic!("accepted restore fails validate() after step {step}: {e}");
        }
    }
});
