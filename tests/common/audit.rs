//! Helpers of the bad-input audit: the `tests/bad_input_*.rs` files,
//! one test per row of the table in `docs/audit.md`,
//! named as the table names it, split by the entry point (or family of entry points)
//! the rows cover.
//!
//! Every test feeds one public entry point the five kinds of bad input the table has
//! columns for: a stale id or handle, a foreign one (from another world or layer, or
//! never issued), a non-finite value, an out-of-range parameter, and a call at the
//! wrong time. Each call runs under [`no_panic`], so a panic is reported as what it is.
//!
//! Tests named `bug_*` are the audit's findings (the table marks their cells
//! "PANICS", "HANGS", "LOSES STATE", "NO ERROR", "WRONG ERROR" or "WRONG ANSWER", bug
//! Bn); all are fixed and run as regression tests. The two that hung are run in a
//! child process under a time and memory limit (`tests/bad_input_timers.rs`), so that
//! a regression fails instead of taking the machine down.

use std::panic::{catch_unwind, AssertUnwindSafe};

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, NodeId};

use super::build::{ball_at, box_at, world_with_ground};

/// The audit's time step.
pub const DT: Real = 0.01;

/// A fixed ground and a ball resting on it (dt = 0.01, gravity -9.81); returns the
/// world, the ground and the ball.
pub fn ball_on_ground() -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle) {
    let (mut world, ground) = world_with_ground();
    world.integration_parameters.dt = DT;
    let (ball, _) = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5);
    (world, ground, ball)
}

/// [`ball_on_ground`] stepped `n` times with a layer.
pub fn stepped(n: usize) -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle, ContactLayer) {
    stepped_with(n, ContactLayer::new())
}

/// [`stepped`] with a layer tracking proximity, whose edges keep the contact details
/// (normals) that the graph's own support queries read.
#[allow(dead_code)]
pub fn stepped_proximity(
    n: usize,
) -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle, ContactLayer) {
    stepped_with(
        n,
        ContactLayer::with_tracking(rapier_contact_graph::coherence::Tracking::Proximity),
    )
}

fn stepped_with(
    n: usize,
    mut layer: ContactLayer,
) -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle, ContactLayer) {
    let (mut world, ground, ball) = ball_on_ground();
    for _ in 0..n {
        layer.step(&mut world);
    }
    (world, ground, ball, layer)
}

/// A world no layer has seen: `n` dynamic balls (radius 0.6) in a row along x,
/// overlapping, stepped once by Rapier alone.
pub fn foreign_world(n: usize) -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    for i in 0..n {
        ball_at(&mut world, [i as Real, 0.0, 0.0], 0.6);
    }
    world.step();
    world
}

/// Runs `f`; a panic fails the test with what panicked and its message.
pub fn no_panic<R>(what: &str, f: impl FnOnce() -> R) -> R {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(e) => {
            let msg = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("{what} panicked: {msg}");
        }
    }
}

/// Handles no world the layer saw ever issued for this slot: the next generation of
/// the same slot, a slot far past the end, and Rapier's invalid handle.
pub fn foreign_bodies(h: RigidBodyHandle) -> [RigidBodyHandle; 3] {
    let (i, g) = h.into_raw_parts();
    [
        RigidBodyHandle::from_raw_parts(i, g + 1),
        RigidBodyHandle::from_raw_parts(1_000_000, 0),
        RigidBodyHandle::invalid(),
    ]
}

/// As [`foreign_bodies`], for colliders.
pub fn foreign_colliders(c: ColliderHandle) -> [ColliderHandle; 3] {
    let (i, g) = c.into_raw_parts();
    [
        ColliderHandle::from_raw_parts(i, g + 1),
        ColliderHandle::from_raw_parts(1_000_000, 0),
        ColliderHandle::invalid(),
    ]
}

/// Node ids this layer never issued: the next generation of a live slot and a slot
/// far past the end.
pub fn foreign_nodes(n: NodeId) -> [NodeId; 3] {
    [
        NodeId::from_raw_parts(n.index(), n.generation() + 1),
        NodeId::from_raw_parts(1_000_000, 0),
        NodeId::from_raw_parts(u32::MAX, u32::MAX),
    ]
}

/// A node id that was live and is stale now: a box inserted, analysed, removed and
/// analysed again. Returns the node and the removed body.
pub fn stale_node(layer: &mut ContactLayer, world: &mut PhysicsWorld) -> (NodeId, RigidBodyHandle) {
    let (h, _) = box_at(world, [3.0, 1.0, 0.0], 0.5);
    layer.step(world);
    let n = layer.graph().try_node_of_body(h).unwrap();
    world.remove_body(h);
    layer.step(world);
    assert!(layer.graph().node(n).is_none(), "{n:?} is stale");
    (n, h)
}

/// Fingerprint of what a call must not change when it refuses its input.
pub fn fingerprint(layer: &ContactLayer) -> (usize, usize, usize, usize) {
    (
        layer.graph().node_count(),
        layer.graph().edge_count(),
        layer.analysis().flagged_colliders(),
        layer.analysis().event_bus().len(),
    )
}

/// A small deterministic generator (xorshift64) for corruption places and values.
pub fn xorshift(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}
