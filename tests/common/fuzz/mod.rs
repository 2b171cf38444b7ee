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
//! - [`config`]: the configurations a sequence runs under ([`Config`]);
//! - [`ops`]: the operations ([`Op`], [`Ty`], [`Who`], [`Call`], [`Second`]) and the
//!   grid they are placed on;
//! - [`apply`]: [`Harness::apply`], what each world and layer operation does;
//! - [`apply_user`]: the user's own Rapier calls, steps the layer does not see, the
//!   second layer;
//! - [`check`]: [`Harness::step`], one step and every check after it;
//! - [`contract`]: our own checker of the listener contract, and subscription filters;
//! - [`derived`]: the part of a graph derived from Rapier's state alone, compared
//!   with a fresh layer's;
//! - [`oracle`]: the touching pairs Rapier's narrow phase has, against the graph's;
//! - [`twin`]: the plain Rapier world given the same operations, for observe-only
//!   configurations;
//! - `strategies`, `runner` (tests only): the proptest generator, and the runner that
//!   minimises and reports a failure.

use std::collections::{BTreeMap, HashMap, HashSet};

use crossbeam_channel::Receiver;
use rapier_contact_graph::events::SubscriptionId;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Event, Filter, NodeId};

mod apply;
mod apply_layer;
mod apply_user;
mod check;
mod config;
mod contract;
mod derived;
mod ops;
mod oracle;
#[cfg(test)]
pub mod runner;
#[cfg(test)]
pub mod strategies;
mod twin;

#[allow(unused_imports)] // not every binary that includes the harness names them all
pub use config::{Config, Preset};
use contract::Contract;
pub use ops::{Call, Op, Second, Ty, Who};

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
    /// Sequences run.
    pub cases: u64,
    pub ops: u64,
    /// Steps analysed by the layer under test.
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
    /// Touching collider pairs of Rapier's narrow phase checked against the graph
    /// (both layers).
    pub touching_pairs: u64,
    /// Steps after which the world was compared bit for bit with its plain twin.
    pub twin_steps: u64,
    /// Body-steps held by the speed-ups (fixated), and of those, parked.
    pub held_seen: u64,
    pub parked_seen: u64,
    /// The user's own Rapier calls, and those on a held (or parked) body.
    pub user_calls: u64,
    pub user_calls_held: u64,
    /// Steps of Rapier the layer did not see, and steps of the second layer.
    pub unseen_steps: u64,
    pub second_steps: u64,
}

impl Counters {
    /// Adds a sequence's counters to a run's.
    pub fn add(&mut self, c: &Counters) {
        self.cases += c.cases;
        self.ops += c.ops;
        self.steps += c.steps;
        self.events += c.events;
        self.max_nodes = self.max_nodes.max(c.max_nodes);
        self.kinds_seen |= c.kinds_seen;
        self.sleeping_seen += c.sleeping_seen;
        self.refused += c.refused;
        self.touching_steps += c.touching_steps;
        self.touching_pairs += c.touching_pairs;
        self.twin_steps += c.twin_steps;
        self.held_seen += c.held_seen;
        self.parked_seen += c.parked_seen;
        self.user_calls += c.user_calls;
        self.user_calls_held += c.user_calls_held;
        self.unseen_steps += c.unseen_steps;
        self.second_steps += c.second_steps;
    }
}

/// What was last asked of a body's enabled state: by the layer
/// (`set_body_disabled`) or by the user's own `RigidBody::set_enabled`.
#[derive(Clone, Copy, Debug)]
struct Asked {
    handle: RigidBodyHandle,
    disabled: bool,
    by_layer: bool,
}

/// A world, a layer, and the checks.
pub struct Harness {
    pub world: PhysicsWorld,
    pub layer: ContactLayer,
    pub config: Config,
    rx: Receiver<Event>,
    /// What the base subscriber asked for ([`Config::base`]).
    base: Filter,
    contract: Contract,
    subs: Vec<Sub>,
    rules: Vec<NodeId>,
    timers: Vec<NodeId>,
    composites: Vec<NodeId>,
    /// What was last asked of each body's enabled state (see [`Asked`]).
    passive: BTreeMap<(u32, u32), Asked>,
    /// Bodies `set_body_disabled` was called on since the last step, with what was
    /// asked of them before: the layer applies the request at its next pre-step,
    /// after any call the user makes meanwhile, so the layer's request is the last
    /// word, unless the pre-step refuses it (then nothing changes).
    pending: HashMap<(u32, u32), Option<Asked>>,
    pub counters: Counters,
    pub trace: bool,
    /// Bodies Rapier's quarantine disabled (non-finite state) at some step: they
    /// are disabled whatever `set_body_disabled` asked.
    quarantined: HashSet<(u32, u32)>,
    /// Bodies or colliders added / removed since the last step.
    added: bool,
    removed: bool,
    /// The plain Rapier world given the same world operations, stepped by Rapier
    /// alone, while the layer only observes (dropped at the first operation that
    /// lets the layer change motion: a rule, a passive body, the speed-ups).
    twin: Option<PhysicsWorld>,
    /// The second layer on the same world, if attached, and the sensors' collision
    /// types after its last step.
    second: Option<ContactLayer>,
    second_types: Vec<(ColliderHandle, ActiveCollisionTypes)>,
    /// The colliders the second layer flagged, in collider order (as its own map).
    second_flagged: BTreeMap<(u32, u32), ColliderHandle>,
    /// Whether the twin is given the accesses of the second layer's `detach` (off to
    /// replay the limit they stand for).
    pub mirror_detach: bool,
    /// Whether the operations steer clear of the open bugs (each place names its
    /// regression test); off to replay a bug.
    pub steer: bool,
    /// The shared contract checker of `tests/common`.
    #[cfg(test)]
    log: crate::common::contract::ContractLog,
}

impl Default for Harness {
    fn default() -> Self {
        Self::new()
    }
}

/// The arena: a fixed floor body (top at y = 0), four walls and a ceiling as
/// parentless colliders, a 6 m × 4 m × 6 m box.
pub fn arena() -> PhysicsWorld {
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
    world
}

impl Harness {
    /// The arena under proximity tracking (the legacy mode of [`run`]).
    pub fn new() -> Self {
        Self::with_config(Config::Legacy { touching: false })
    }

    /// The arena under the legacy modes of [`run`] (see [`Config::Legacy`]).
    pub fn with_mode(touching: bool) -> Self {
        Self::with_config(Config::Legacy { touching })
    }

    /// The arena and a layer set up as `config` says: tracking, trigger widening, the
    /// base subscriber, the speed-ups and the monitor; the twin for observe-only
    /// configurations.
    pub fn with_config(config: Config) -> Self {
        let world = arena();
        let twin = config.observe_only().then(arena);
        let mut layer = ContactLayer::new();
        layer.logic_mut().set_trigger_widening(config.widening());
        if let Some(t) = config.tracking() {
            layer.set_tracking(t);
        }
        if let Some(s) = config.speedups() {
            layer
                .speedups_mut()
                .set(Some(s))
                .expect("a preset's speed-ups are valid");
        }
        if config.monitor() {
            layer
                .monitor_mut()
                .set(
                    MonitorMode::Repair,
                    MonitorConfig::default(),
                    RepairConfig::default(),
                )
                .expect("the default monitor is valid");
        }
        let base = Filter::kinds(config.base());
        let rx = layer.subscribe(base.clone());
        #[cfg(test)]
        let log = crate::common::contract::ContractLog::attach_with(&mut layer, base.clone());
        Self {
            world,
            layer,
            config,
            rx,
            contract: Contract::new(&base, config.monitor()),
            base,
            subs: Vec::new(),
            rules: Vec::new(),
            timers: Vec::new(),
            composites: Vec::new(),
            passive: BTreeMap::new(),
            pending: HashMap::new(),
            counters: Counters::default(),
            trace: false,
            added: false,
            removed: false,
            quarantined: HashSet::new(),
            twin,
            second: None,
            second_types: Vec::new(),
            second_flagged: BTreeMap::new(),
            mirror_detach: true,
            steer: true,
            #[cfg(test)]
            log,
        }
    }
}

/// Runs a sequence under a legacy mode (the regression tests written before the
/// configurations): touching mode if it starts with `Op::Touching(true)`, proximity
/// mode otherwise (see [`Config::Legacy`]).
pub fn run(ops: &[Op], trace: bool) -> Result<Counters, String> {
    let touching = matches!(ops.first(), Some(Op::Touching(true)));
    run_in(Config::Legacy { touching }, ops, trace)
}

/// Runs a sequence on a fresh harness set up as `config` says; the first failed
/// check is the error.
pub fn run_in(config: Config, ops: &[Op], trace: bool) -> Result<Counters, String> {
    run_harness(Harness::with_config(config), ops, trace)
}

/// [`run_in`] without steering clear of the open bugs (see [`Harness::steer`]): how
/// the regression tests replay them.
pub fn run_unsteered(config: Config, ops: &[Op], trace: bool) -> Result<Counters, String> {
    let mut h = Harness::with_config(config);
    h.steer = false;
    run_harness(h, ops, trace)
}

/// Runs a sequence on a harness set up by the caller (its switches set).
pub fn run_harness(mut h: Harness, ops: &[Op], trace: bool) -> Result<Counters, String> {
    h.trace = trace;
    h.counters.cases = 1;
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
