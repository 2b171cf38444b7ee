//! The fuzz harness of `tests/fuzz_operations.rs`: a world, a layer, the operation
//! language applied to them, and every check after every step (the file's module
//! documentation says what is checked and why).
//!
//! It is no module of `common`: `tests/fuzz_operations.rs` includes it as its module
//! `harness` (`#[path = "common/fuzz/mod.rs"]`), and so does the cargo-fuzz target
//! (`fuzz/fuzz_targets/operations.rs`), which includes that file. So nothing here but
//! the `cfg(test)` parts may use proptest or `crate::common`; the regression binaries
//! that replay sequences include it the same way.
//!
//! - [`ops`]: the operations ([`Op`], [`Ty`]) and the grid they are placed on;
//! - [`apply`]: [`Harness::apply`], what each operation does to the world or the layer;
//! - [`check`]: [`Harness::step`], one step and every check after it;
//! - [`contract`]: our own checker of the listener contract, and subscription filters;
//! - [`derived`]: the part of a graph derived from Rapier's state alone, compared
//!   with a fresh layer's;
//! - `strategies`, `runner` (tests only): the proptest generator, and the runner that
//!   minimises and reports a failure.

use std::collections::{BTreeMap, HashSet};

use crossbeam_channel::Receiver;
use rapier_contact_graph::events::KindSet;
use rapier_contact_graph::events::SubscriptionId;
use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Event, Filter, NodeId};

mod apply;
mod check;
mod contract;
mod derived;
mod ops;
#[cfg(test)]
pub mod runner;
#[cfg(test)]
pub mod strategies;

use contract::Contract;
pub use ops::{Op, Ty};

/// A subscription under test.
struct Sub {
    id: Option<SubscriptionId>,
    rx: Receiver<Event>,
    filter: Filter,
    capacity: usize,
}

/// Counters over a run (for the report of the long run).
#[derive(Clone, Copy, Debug, Default)]
pub struct Counters {
    pub ops: u64,
    pub steps: u64,
    pub events: u64,
    pub max_nodes: usize,
    pub kinds_seen: u16,
    pub sleeping_seen: u64,
    /// `set_body_disabled(true)` calls refused, and passive changes the pre-step refused
    /// or undid.
    pub refused: u64,
    /// Steps analysed with touching tracking in effect (Rapier's events).
    pub touching_steps: u64,
}

/// A world, a layer, and the checks.
pub struct Harness {
    pub world: PhysicsWorld,
    pub layer: ContactLayer,
    rx: Receiver<Event>,
    /// What the base subscriber asked for: every kind, or (touching mode) every kind
    /// that touching tracking can deliver, so that the subscriber does not force
    /// proximity tracking.
    base: Filter,
    contract: Contract,
    subs: Vec<Sub>,
    rules: Vec<NodeId>,
    timers: Vec<NodeId>,
    composites: Vec<NodeId>,
    /// What the user last asked with `set_body_disabled`, per body.
    passive: BTreeMap<(u32, u32), (RigidBodyHandle, bool)>,
    pub counters: Counters,
    pub trace: bool,
    /// Bodies Rapier's quarantine disabled (non-finite state) at some step: they
    /// are disabled whatever `set_body_disabled` asked.
    quarantined: HashSet<(u32, u32)>,
    /// Bodies or colliders added / removed since the last step.
    added: bool,
    removed: bool,
    /// The shared contract checker of `tests/common`.
    #[cfg(test)]
    log: crate::common::contract::ContractLog,
}

impl Default for Harness {
    fn default() -> Self {
        Self::new()
    }
}

impl Harness {
    /// The arena with a subscriber to every event kind: proximity tracking is in
    /// effect throughout (a `Persist` subscriber needs every pair read).
    pub fn new() -> Self {
        Self::with_mode(false)
    }

    /// The arena: a fixed floor body (top at y = 0), four walls and a ceiling as
    /// parentless colliders, a 6 m × 4 m × 6 m box. With `touching`, the layer is
    /// asked for touching tracking and the base subscriber takes every kind but
    /// those only proximity tracking produces (`KindSet::NEEDS_EVERY_PAIR`), so that
    /// touching tracking is in effect until an operation (speed-ups, a subscription
    /// to such a kind) switches it to proximity, and back. Sensors are widened
    /// (`set_trigger_widening`) in proximity mode only.
    pub fn with_mode(touching: bool) -> Self {
        let mut world = PhysicsWorld::new();
        world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.25, 0.0)),
            ColliderBuilder::cuboid(3.0, 0.25, 3.0),
        );
        for (x, z, hx, hz) in [
            (3.25, 0.0, 0.25, 3.0),
            (-3.25, 0.0, 0.25, 3.0),
            (0.0, 3.25, 3.0, 0.25),
            (0.0, -3.25, 3.0, 0.25),
        ] {
            world.insert_collider(
                ColliderBuilder::cuboid(hx, 2.0, hz).translation(Vector::new(x, 2.0, z)),
                None,
            );
        }
        world.insert_collider(
            ColliderBuilder::cuboid(3.0, 0.25, 3.0).translation(Vector::new(0.0, 4.25, 0.0)),
            None,
        );
        let mut layer = ContactLayer::new();
        // Both trigger semantics are fuzzed: Rapier's own sensor collision types
        // (the default) with touching tracking, widened ones with proximity tracking.
        layer.set_trigger_widening(!touching);
        let base = if touching {
            layer.set_tracking(rapier_contact_graph::coherence::Tracking::Touching);
            Filter::kinds(KindSet::ALL.without(KindSet::NEEDS_EVERY_PAIR))
        } else {
            Filter::all()
        };
        let rx = layer.subscribe(base.clone());
        #[cfg(test)]
        let log = crate::common::contract::ContractLog::attach_with(&mut layer, base.clone());
        Self {
            world,
            layer,
            rx,
            contract: Contract::new(!touching),
            base,
            subs: Vec::new(),
            rules: Vec::new(),
            timers: Vec::new(),
            composites: Vec::new(),
            passive: BTreeMap::new(),
            counters: Counters::default(),
            trace: false,
            added: false,
            removed: false,
            quarantined: HashSet::new(),
            #[cfg(test)]
            log,
        }
    }
}

/// Runs a sequence on a fresh harness; the first failed check is the error. A
/// sequence that starts with `Op::Touching(true)` runs in touching mode (see
/// [`Harness::with_mode`]).
pub fn run(ops: &[Op], trace: bool) -> Result<Counters, String> {
    let mut h = Harness::with_mode(matches!(ops.first(), Some(Op::Touching(true))));
    h.trace = trace;
    // The first step makes nodes of the arena.
    h.step().map_err(|e| format!("initial step: {e}"))?;
    for (i, op) in ops.iter().enumerate() {
        h.apply(op).map_err(|e| format!("op #{i} {op:?}: {e}"))?;
    }
    // A few steps at the end so that the last operations are analysed.
    for _ in 0..3 {
        h.step().map_err(|e| format!("final steps: {e}"))?;
    }
    Ok(h.counters)
}
