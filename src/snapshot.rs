//! Snapshot and restore of the layer, beside Rapier's own world snapshot (feature
//! `serde`, on by default).
//!
//! A game that saves, rewinds or replicates a Rapier world serialises its
//! `PhysicsWorld` (Rapier derives `Serialize`/`Deserialize` under its
//! `serde-serialize` feature, which this crate's `serde` feature turns on). The layer
//! keeps state of its own — the graph with its caches and marks, the groups, the rules,
//! timers and containers, the speed-ups' rest counters and held bodies, the monitor's
//! timers, episodes and repairs, cursors and counters — and [`ContactLayer::snapshot`]
//! captures all of it as a [`LayerSnapshot`].
//! [`ContactLayer::restore`] rebuilds a layer from it against the restored world, and
//! the pair then continues **bit for bit** as the original pair would: the same poses,
//! the same graph, the same events in the same order (tested on every scene kind,
//! speed-ups, fixation and the repairing monitor included, in
//! `tests/snapshot_restore.rs`).
//!
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{events::Filter, ContactLayer, LayerSnapshot};
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! for _ in 0..50 {
//!     layer.step(&mut world);
//! }
//! // Save: Rapier's world and the layer, with any serde format (bincode here).
//! let bytes = bincode::serialize(&(&world, &layer.snapshot(&world))).unwrap();
//!
//! // Load: the world first, then the layer against it.
//! let (mut world2, snap): (PhysicsWorld, LayerSnapshot) = bincode::deserialize(&bytes).unwrap();
//! let mut layer2 = ContactLayer::restore(&snap, &world2).unwrap();
//!
//! // Subscriptions are not part of a snapshot: subscribe again.
//! let (events, events2) = (layer.subscribe(Filter::all()), layer2.subscribe(Filter::all()));
//! for _ in 0..100 {
//!     layer.step(&mut world);
//!     layer2.step(&mut world2);
//! }
//! let y = |w: &PhysicsWorld| w.bodies[ball].translation().y.to_bits();
//! assert_eq!(y(&world), y(&world2), "bit for bit");
//! assert_eq!(events.try_iter().collect::<Vec<_>>(), events2.try_iter().collect::<Vec<_>>());
//! ```
//!
//! # Why a snapshot type, not `Serialize` on the layer
//! Chosen: [`LayerSnapshot`], a value taken from a layer and turned back into one by
//! [`ContactLayer::restore`], which is where the checks live (the format, the world,
//! the state's consistency, the predicates). Rejected: deriving `Serialize` and
//! `Deserialize` on [`ContactLayer`] itself. A deserialised layer would bypass every
//! one of those checks, and a layer that silently lost its predicates or belongs to
//! another world would only show it by diverging later.
//!
//! # What a snapshot holds, and what it cannot
//! Everything the layer would read in a later step, per-step outputs included (so
//! [`ContactLayer::last_events`], [`LayerAnalysis::touched_edges`](crate::LayerAnalysis::touched_edges) and
//! [`LayerAnalysis::stats`](crate::LayerAnalysis::stats) read the same after a restore), with two exceptions:
//! - **Subscriptions.** A crossbeam `Sender` cannot be serialised: a restored layer
//!   has no subscribers, and the user subscribes again. The bus's counters are kept,
//!   so subscription ids are never issued twice. Events generated after the restore
//!   are the original's, in the same order, for the same filters.
//! - **Predicate rules** ([`crate::Rule::ignore_if`]). A closure cannot be serialised.
//!   The snapshot keeps the rule (its node, its members, its place among the rules) and
//!   drops its predicate; [`ContactLayer::restore`] refuses such a snapshot with
//!   [`Error::UnboundPredicate`] naming the rule, and [`ContactLayer::restore_with`]
//!   takes a resolver that gives each predicate back by rule node and members
//!   ([`LayerSnapshot::predicate_rules`] lists them).
//!
//!   Rejected: refusing to *take* such a snapshot. A layer with a predicate rule could
//!   then never be saved, and removing the rule, saving and adding it again changes
//!   node ids and serial numbers, so the continuation would not be the original's.
//!   Rejected too: restoring the rule with a placeholder predicate (ignore nothing, or
//!   everything): a silent change of behaviour is worse than an error.
//!
//! # Versions
//! A snapshot is written as `(magic, format, world stamp, state)`. The deserialiser
//! reads the magic number and [`SNAPSHOT_FORMAT`] first, and a snapshot of another
//! format is refused there, with [`Error::SnapshotFormat`]'s message (formats such as
//! bincode do not describe themselves, so nothing past a layout this build does not
//! know can be read; the check has to come before). Any incompatible change of the
//! layer's state bumps [`SNAPSHOT_FORMAT`]. Truncated bytes, and corrupted bytes that
//! no longer decode, are errors of the deserialiser (bincode's in the tests), not
//! panics; bytes that decode but describe an inconsistent state are refused by
//! [`ContactLayer::restore`] with [`Error::Invariant`] (the arenas' free lists, the
//! graph's invariants, groups against nodes, rules, timers and composites against
//! their nodes, the speed-up and monitor configurations). A corrupted value that
//! keeps the state consistent (a cached distance, say) cannot be told from a real one:
//! checksum the bytes in transport if that matters.
//!
//! # Which world
//! The snapshot carries a stamp of the world it was taken with: a 64-bit digest of
//! every body (handle, type, enabled, sleeping, pose, velocities), collider (handle,
//! parent, sensor, enabled, pose) and joint (handle, bodies, multibody links), with
//! their counts. [`ContactLayer::restore`] recomputes it from the world it is given
//! and refuses another world with [`Error::SnapshotMismatch`], naming a body or
//! collider the graph stands for and the world lacks when there is one. Rejected:
//! checking only that the handles the graph names exist. The same scene saved at
//! another step passes that test, and the layer would then carry the wrong frozen
//! state for every sleeping pair until it wakes. The stamp also makes "a node whose
//! body the user removed just before saving" legal (the original would drop it at its
//! next step; so does the restored layer).
//!
//! # Determinism of the bytes
//! Hash maps are written as entries sorted by key, so equal states give equal bytes
//! (the tests compare the snapshots of the original and restored layers byte for byte
//! after every step). Their iteration order never leaks into behaviour anyway: the
//! graph's pair map and the rule index are only looked up, the logic layer sorts the
//! keys of its collider maps before using them, and the monitor judges the bodies of
//! its maps one by one and sorts what it finds.
//!
//! # Rapier's own snapshot (0.36.1, verified)
//! `PhysicsWorld` skips, on serialisation, only workspaces that its next step rebuilds
//! before reading: the physics and collision pipelines, the CCD solver (its cached
//! target list), the island manager's solve groups and split/sleep-scan workspaces,
//! the narrow phase's query dispatcher (restored to the default one) and per-step
//! buffers, the previous step's contact clusters (overwritten at the start of the next
//! update: the warm-start source is the current clusters, which are saved), joint
//! assembly epochs (a fresh pipeline reselects). A restored world steps bit-identically
//! to the original (tested alone, then with the layer, on piles, stacks, triggers,
//! joints, kinematic scripts and every speed-up). One caveat is Rapier's own: joints
//! inserted since the last step wait in a `std` `HashSet` drained in hash order, which
//! differs per process (and, after a round trip, per rebuilt set), so take snapshots
//! after a step rather than between inserting a joint and stepping; the same order
//! may make two processes differ there without any snapshot.
//! Rapier's quarantine list (bodies its last step disabled for non-finite state) lives
//! in the skipped pipeline: a restored world reports none until its next step, which
//! refills it, so the layer's analysis after that step reads the same list.
//!
//! # Formats
//! Any serde format that round-trips `f32` bit for bit and infinities: **bincode** (1.x)
//! is the safe choice and what the tests use. JSON cannot hold infinities, and an
//! edge without contact points has a closest distance of `f32::INFINITY`: `serde_json`
//! writes it as `null` and then refuses to read it back ("invalid type: null,
//! expected f32", seen on a 20-sphere pile), so it fails on nearly every layer.
//!
//! # Cost
//! - [`ContactLayer::snapshot`]: a copy of the state, O(nodes + edges + groups + rules
//!   + timers + speed-up records), plus O(bodies + colliders + joints) for the stamp.
//! - [`ContactLayer::restore`]: the same copy and stamp, plus the checks, O(nodes +
//!   edges + group members).
//! - Serialising is linear in the same sizes; hash maps add a sort, O(k log k) for k
//!   entries (edges for the pair map).

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTupleStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::coherence::Coherence;
use crate::events::{Event, EventBus};
use crate::graph::{ContactGraph, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::logic::{IgnorePredicate, Logic, Rule};
use crate::monitor::LayerMonitor;
use crate::speedups::SpeedUpState;
use crate::{ContactLayer, Error, NodeId, Result, StepStats, WorldView};

/// The snapshot format this build writes and reads. Bumped by any change of the
/// layer's state that older builds could not read.
/// Format 2 leaves out the analysis' lookup caches (collider owners, pair slots);
/// format 3 adds whether the layer's event handler reached the last step (touching
/// tracking as the default); format 4 adds the speed-ups' partial support judgement
/// (the bodies resting on computed contacts, each held body's watched supporters with
/// the watch's counts, the records of bodies released since the last judgement);
/// format 6 adds the collider pair each physical and trigger edge names
/// (`Edge::colliders`, the pair its events name) and whether the speed-ups hold a
/// node's body (`Node::is_held`).
pub const SNAPSHOT_FORMAT: u32 = 6;

/// The first field of every snapshot ("RCGL" in little-endian bytes).
const SNAPSHOT_MAGIC: u32 = u32::from_le_bytes(*b"RCGL");

/// The state of a [`ContactLayer`] at one moment, with a stamp of the world it belongs
/// to. Serialise it with any serde format that keeps `f32` bit for bit (see the
/// [module docs](self)); restore it with [`ContactLayer::restore`].
#[derive(Debug, Clone)]
pub struct LayerSnapshot {
    world: WorldStamp,
    /// Whether the layer passed `validate` against the world when the snapshot was
    /// taken (false when the world was edited after the layer's last step).
    in_step: bool,
    state: LayerState,
}

impl LayerSnapshot {
    /// The saved state, to corrupt in tests.
    #[cfg(test)]
    pub(crate) fn state_mut(&mut self) -> &mut LayerState {
        &mut self.state
    }

    /// The index of the last step the layer had analysed. O(1).
    pub fn step(&self) -> u64 {
        self.state.coherence.step()
    }

    /// The predicate rules a restore must give back, as `(rule node, members)` in
    /// node order (see [`ContactLayer::restore_with`]). O(rules).
    pub fn predicate_rules(&self) -> Vec<(NodeId, Vec<NodeId>)> {
        let mut out: Vec<(NodeId, Vec<NodeId>)> = Vec::new();
        let table = self.state.logic.hooks.rules.entries().iter();
        for (n, r) in self
            .state
            .logic
            .rules
            .iter()
            .chain(table.map(|(n, r)| (n, r)))
        {
            if let Rule::Predicate { members, .. } = r {
                if !out.iter().any(|(m, _)| m == n) {
                    out.push((*n, members.clone()));
                }
            }
        }
        out.sort_by_key(|(n, _)| *n);
        out
    }
}

/// A digest of the world a snapshot was taken with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct WorldStamp {
    bodies: u64,
    colliders: u64,
    joints: u64,
    digest: u64,
}

/// A 64-bit mix of words (FxHash's multiply-rotate, with a final avalanche).
struct Digest(u64);

impl Digest {
    fn word(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn floats(&mut self, xs: &[f32]) {
        for x in xs {
            self.word(x.to_bits() as u64);
        }
    }
    fn handle(&mut self, (i, g): (u32, u32)) {
        self.word(((g as u64) << 32) | i as u64);
    }
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^ (x >> 33)
    }
}

fn pose_words(p: &rapier3d::math::Pose) -> [f32; 7] {
    let (t, r) = (p.translation, p.rotation);
    [t.x, t.y, t.z, r.x, r.y, r.z, r.w]
}

impl WorldStamp {
    /// O(bodies + colliders + joints).
    fn of(view: &WorldView) -> Self {
        let mut d = Digest(0);
        for (h, rb) in view.bodies.iter() {
            d.handle(h.into_raw_parts());
            d.word(rb.body_type() as u64);
            d.word(rb.is_enabled() as u64 | (rb.is_sleeping() as u64) << 1);
            d.floats(&pose_words(rb.position()));
            let (v, w) = (rb.linvel(), rb.angvel());
            d.floats(&[v.x, v.y, v.z, w.x, w.y, w.z]);
        }
        for (h, c) in view.colliders.iter() {
            d.handle(h.into_raw_parts());
            d.word(c.parent().map_or(u64::MAX, |p| {
                let (i, g) = p.into_raw_parts();
                ((g as u64) << 32) | i as u64
            }));
            d.word(c.is_sensor() as u64 | (c.is_enabled() as u64) << 1);
            d.floats(&pose_words(c.position()));
        }
        let mut joints = 0u64;
        for (h, j) in view.impulse_joints.iter() {
            joints += 1;
            d.handle(h.into_raw_parts());
            d.handle(j.body1().into_raw_parts());
            d.handle(j.body2().into_raw_parts());
        }
        for mb in view.multibody_joints.multibodies() {
            for l in mb.links() {
                joints += 1;
                d.handle(l.rigid_body_handle().into_raw_parts());
            }
            d.word(u64::MAX);
        }
        Self {
            bodies: view.bodies.len() as u64,
            colliders: view.colliders.len() as u64,
            joints,
            digest: d.finish(),
        }
    }
}

/// Everything a layer holds but its subscriptions. Built by `ContactLayer::to_state`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct LayerState {
    pub(crate) graph: ContactGraph,
    pub(crate) groups: Groups,
    pub(crate) coherence: Coherence,
    pub(crate) logic: Logic,
    pub(crate) bus: SavedBus,
    pub(crate) stats: StepStats,
    pub(crate) gravity: rapier3d::math::Vector,
    pub(crate) colliders_seen: usize,
    pub(crate) ticks: Vec<(NodeId, u64)>,
    pub(crate) events: Vec<Event>,
    pub(crate) speedups: Option<SpeedUpState>,
    pub(crate) monitor: Option<LayerMonitor>,
    pub(crate) monitor_events: Vec<Event>,
    pub(crate) monitor_restore: Option<LayerMonitor>,
}

/// A layer's event bus as a snapshot holds it: no subscriptions, counters kept.
/// (`EventBus::clone` forgets the counters; cloning this keeps them, so
/// `LayerState` can derive `Clone`.)
#[derive(Debug, Serialize, Deserialize)]
#[serde(transparent)]
pub(crate) struct SavedBus(pub(crate) EventBus);

impl Clone for SavedBus {
    fn clone(&self) -> Self {
        SavedBus(self.0.without_subscriptions())
    }
}

impl Serialize for LayerSnapshot {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple_struct("LayerSnapshot", 5)?;
        t.serialize_field(&SNAPSHOT_MAGIC)?;
        t.serialize_field(&SNAPSHOT_FORMAT)?;
        t.serialize_field(&self.world)?;
        t.serialize_field(&self.in_step)?;
        t.serialize_field(&self.state)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for LayerSnapshot {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct SnapshotVisitor;
        impl<'de> Visitor<'de> for SnapshotVisitor {
            type Value = LayerSnapshot;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a rapier-contact-graph layer snapshot")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<LayerSnapshot, A::Error> {
                let magic: u32 = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(0, &self))?;
                if magic != SNAPSHOT_MAGIC {
                    return Err(de::Error::custom(
                        "not a rapier-contact-graph layer snapshot (wrong magic number)",
                    ));
                }
                let found: u32 = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(1, &self))?;
                if found != SNAPSHOT_FORMAT {
                    return Err(de::Error::custom(Error::SnapshotFormat {
                        found,
                        expected: SNAPSHOT_FORMAT,
                    }));
                }
                let world = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(2, &self))?;
                let in_step = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(3, &self))?;
                let state = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(4, &self))?;
                Ok(LayerSnapshot {
                    world,
                    in_step,
                    state,
                })
            }
        }
        d.deserialize_tuple_struct("LayerSnapshot", 5, SnapshotVisitor)
    }
}

/// Resolves the predicate of a predicate rule, given the rule's node and members.
pub type PredicateResolver<'a> = &'a mut dyn FnMut(NodeId, &[NodeId]) -> Option<IgnorePredicate>;

impl ContactLayer {
    /// The layer's state as a [`LayerSnapshot`], stamped with `world` (the world the
    /// layer analysed, at the same moment: serialise both together). Subscriptions and
    /// rule predicates are not part of it (see [`crate::snapshot`]).
    ///
    /// Take it after a step ([`Self::step`], or [`Self::analyze`]); any other moment
    /// between two of the layer's calls works too. Cost: O(nodes + edges + groups +
    /// rules + timers + speed-up records) to copy the state, plus O(bodies + colliders
    /// + joints) for the world's stamp, plus one `validate` against the world (O(nodes
    /// + edges + Rapier pairs)) whose verdict the snapshot keeps: a layer that was in
    /// step with its world must be in step with it again when restored.
    ///
    /// # Example
    /// See [`crate::snapshot`].
    pub fn snapshot<'w>(&self, world: impl Into<WorldView<'w>>) -> LayerSnapshot {
        let view = world.into();
        LayerSnapshot {
            world: WorldStamp::of(&view),
            in_step: self.validate(&view).is_ok(),
            state: self.to_state(),
        }
    }

    /// A layer from a snapshot, against the world saved with it (Rapier's own
    /// snapshot, deserialised). The pair continues exactly as the original pair would.
    /// The restored layer has no subscriptions: subscribe again.
    ///
    /// Errors, with the snapshot left as it was:
    /// - [`Error::SnapshotMismatch`]: `world` is not the world the snapshot was taken
    ///   with (another scene, or the same one at another step);
    /// - [`Error::Invariant`]: the snapshot's state is inconsistent (corrupted bytes
    ///   that still decoded);
    /// - [`Error::UnboundPredicate`]: the snapshot holds a predicate rule; use
    ///   [`Self::restore_with`].
    ///
    /// A snapshot of another format does not get here: its deserialisation fails
    /// with [`Error::SnapshotFormat`]'s message.
    ///
    /// Cost: O(nodes + edges + group members + rules + timers + speed-up records) to
    /// copy and check the state, plus O(bodies + colliders + joints) for the world's
    /// stamp.
    ///
    /// # Example
    /// See [`crate::snapshot`]; a wrong world is refused:
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{ContactLayer, Error};
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let snap = layer.snapshot(&world);
    /// layer.step(&mut world); // the world moves on: it is no longer the saved one
    /// assert!(matches!(ContactLayer::restore(&snap, &world), Err(Error::SnapshotMismatch(_))));
    /// ```
    pub fn restore<'w>(
        snapshot: &LayerSnapshot,
        world: impl Into<WorldView<'w>>,
    ) -> Result<ContactLayer> {
        Self::restore_with(snapshot, world, &mut |_, _| None)
    }

    /// [`Self::restore`], giving back the predicates of the snapshot's predicate rules:
    /// `bind(rule, members)` is called once per predicate rule, in node order, and
    /// returns its predicate, or `None` to refuse (then [`Error::UnboundPredicate`]
    /// names the rule). Rule nodes keep their ids across a snapshot, so a game can key
    /// its predicates by the node `add_rule` returned. Cost: as [`Self::restore`],
    /// plus the calls.
    ///
    /// # Example
    /// ```
    /// use std::sync::Arc;
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{logic::IgnorePredicate, ContactLayer, Error, Rule};
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (ball, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let node = layer.node_of_body(&world.bodies, ball).unwrap();
    /// let rule = layer.logic_mut().add_rule(Rule::ignore_if(&[node], |_, _| true)).unwrap();
    /// let snap = layer.snapshot(&world);
    ///
    /// assert_eq!(ContactLayer::restore(&snap, &world).unwrap_err(), Error::UnboundPredicate(rule));
    /// let ghost: IgnorePredicate = Arc::new(|_, _| true);
    /// let restored = ContactLayer::restore_with(&snap, &world, &mut |n, _members| {
    ///     (n == rule).then(|| ghost.clone())
    /// })
    /// .unwrap();
    /// assert!(restored.logic().rule(rule).unwrap().ignores(node, node));
    /// ```
    pub fn restore_with<'w>(
        snapshot: &LayerSnapshot,
        world: impl Into<WorldView<'w>>,
        bind: PredicateResolver<'_>,
    ) -> Result<ContactLayer> {
        let view = world.into();
        if WorldStamp::of(&view) != snapshot.world {
            return Err(Error::SnapshotMismatch(mismatch(snapshot, &view)));
        }
        let mut state = snapshot.state.clone();
        // The groups' positions and counts are not in the bytes: rebuilt from the
        // groups' lists (on any bytes), then checked with the rest.
        state.groups.reindex(&mut state.graph);
        state.graph.recount_geometric();
        if let Some(s) = &mut state.speedups {
            s.reindex();
        }
        check_state(&state).map_err(|e| Error::Invariant(format!("snapshot: {e}")))?;
        bind_predicates(&mut state.logic, bind)?;
        let mut state = state;
        // What only this process knows (the addresses of shared shapes) is taken from
        // the world restored against.
        state
            .coherence
            .rebind_trigger_shapes(&state.graph, view.colliders);
        let layer = ContactLayer::from_state(state);
        // The state's own checks cannot see everything a corrupted snapshot can hold
        // (a count off by a few, an edge or node dropped): a layer that was in step
        // with its world when saved must pass `validate` against it again, or it is
        // refused. (One saved between a world edit and the next step is behind the
        // world on both sides, and catches up at its next step.) O(nodes + edges +
        // pairs).
        if snapshot.in_step {
            layer
                .validate(&view)
                .map_err(|e| Error::Invariant(format!("snapshot does not match the world: {e}")))?;
        }
        Ok(layer)
    }
}

/// Says how `view` differs from the snapshot's world, as precisely as it can.
fn mismatch(snapshot: &LayerSnapshot, view: &WorldView) -> String {
    for (id, node) in snapshot.state.graph.nodes() {
        match node.source() {
            NodeSource::Body(h) if !view.bodies.contains(h) => {
                return format!("node {id:?} stands for body {h:?}, which the world lacks");
            }
            NodeSource::StaticCollider(h) | NodeSource::Sensor(h)
                if !view.colliders.contains(h) =>
            {
                return format!("node {id:?} stands for collider {h:?}, which the world lacks");
            }
            _ => {}
        }
    }
    let (here, saved) = (WorldStamp::of(view), snapshot.world);
    if (here.bodies, here.colliders, here.joints) != (saved.bodies, saved.colliders, saved.joints) {
        return format!(
            "the world has {} bodies, {} colliders and {} joints; the snapshot's had {}, {} and {}",
            here.bodies, here.colliders, here.joints, saved.bodies, saved.colliders, saved.joints
        );
    }
    "the world has the same objects as the snapshot's but not the same state (poses, \
     velocities, types or sleep): restore against the world saved with the snapshot"
        .into()
}

/// The checks of a deserialised state that later steps rely on (see the module docs).
/// The largest step count a restored layer may hold. The analysis tells steps apart by
/// their number, so the count must have room to grow: 2^62 steps at a million a
/// second take 146,000 years, so only corrupted bytes come near it.
const MAX_RESTORED_STEP: u64 = 1 << 62;

fn check_state(s: &LayerState) -> std::result::Result<(), String> {
    if s.coherence.step() > MAX_RESTORED_STEP {
        return Err(format!(
            "a step count of {} (more than 2^62: corrupted)",
            s.coherence.step()
        ));
    }
    let g = &s.graph;
    // The analysis tells "this step" from "an earlier one" by step numbers: one from
    // the future would make it skip a node or an edge as already done.
    let step = s.coherence.step();
    for (n, node) in g.nodes() {
        if node.seen_step > step || node.born_step > step {
            return Err(format!("node {n:?} carries a step number from the future"));
        }
    }
    for (e, edge) in g.edges() {
        if edge.walk_stamp > step || edge.updated_step > step || edge.created_step > step {
            return Err(format!("edge {e:?} carries a step number from the future"));
        }
    }
    if g.clock > step {
        return Err("the graph's clock is ahead of the step count".into());
    }
    g.nodes.check().map_err(|e| format!("node arena: {e}"))?;
    g.edges.check().map_err(|e| format!("edge arena: {e}"))?;
    g.validate().map_err(|e| e.to_string())?;
    s.groups.check(g)?;
    let live_of = |n: NodeId, kind: NodeKind| g.node(n).is_some_and(|node| node.kind() == kind);
    if let Some(n) = s.logic.rules.keys().find(|&&n| !live_of(n, NodeKind::Rule)) {
        return Err(format!("rule {n:?} has no rule node"));
    }
    if s.logic.rules.len() != g.count_of_kind(NodeKind::Rule) {
        return Err("rule nodes without a rule".into());
    }
    s.logic.timers.check()?;
    if let Some(n) = s
        .logic
        .timers
        .nodes()
        .find(|&n| !live_of(n, NodeKind::Timer))
    {
        return Err(format!("timer {n:?} has no timer node"));
    }
    if s.logic.timers.nodes().count() != g.count_of_kind(NodeKind::Timer) {
        return Err("timer nodes without a timer".into());
    }
    for &c in s.logic.declared.keys() {
        let ok = g.node(c).is_some_and(|n| {
            n.kind() == NodeKind::Composite && matches!(n.source(), NodeSource::Layer(_))
        });
        if !ok {
            return Err(format!("declared composite {c:?} has no composite node"));
        }
    }
    if let Some(s) = &s.speedups {
        s.config().validate().map_err(|e| e.to_string())?;
    }
    for m in s.monitor.iter().chain(&s.monitor_restore) {
        m.monitor.config().validate().map_err(|e| e.to_string())?;
        m.repair_config().validate().map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Gives every predicate rule (in the rule map and in the hooks' table) its predicate.
fn bind_predicates(logic: &mut Logic, bind: PredicateResolver<'_>) -> Result<()> {
    let mut bound: BTreeMap<NodeId, IgnorePredicate> = BTreeMap::new();
    let mut resolve = |n: NodeId, members: &[NodeId]| -> Result<IgnorePredicate> {
        if let Some(p) = bound.get(&n) {
            return Ok(p.clone());
        }
        let p = bind(n, members).ok_or(Error::UnboundPredicate(n))?;
        bound.insert(n, p.clone());
        Ok(p)
    };
    for (&n, rule) in logic.rules.iter_mut() {
        if let Rule::Predicate { members, ignore } = rule {
            *ignore = resolve(n, members)?;
        }
    }
    for (n, rule) in logic.hooks.rules.entries_mut() {
        if let Rule::Predicate { members, ignore } = rule {
            *ignore = resolve(*n, members)?;
        }
    }
    Ok(())
}

// ── Serde helpers for fields of the layer's types ──────────────────────────

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::prelude::{
        ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
    };
    use std::collections::{HashMap, HashSet};

    #[derive(Serialize, Deserialize)]
    struct Maps {
        #[serde(with = "crate::util::serde_maps::sorted_map")]
        map: HashMap<ColliderHandle, u32>,
        #[serde(with = "crate::util::serde_maps::sorted_set")]
        set: HashSet<RigidBodyHandle>,
    }

    fn maps(order: &[u32]) -> Maps {
        let mut m = Maps {
            map: HashMap::new(),
            set: HashSet::new(),
        };
        for &i in order {
            m.map.insert(ColliderHandle::from_raw_parts(i, 1), i * 10);
            m.set.insert(RigidBodyHandle::from_raw_parts(i, 2));
        }
        m
    }

    #[test]
    fn hash_maps_give_the_same_bytes_whatever_their_history() {
        let a = bincode::serialize(&maps(&[5, 1, 9, 3, 7])).unwrap();
        let mut grown = maps(&(0..200).collect::<Vec<_>>());
        for i in 0..200 {
            if ![1, 3, 5, 7, 9].contains(&i) {
                grown.map.remove(&ColliderHandle::from_raw_parts(i, 1));
                grown.set.remove(&RigidBodyHandle::from_raw_parts(i, 2));
            }
        }
        assert_eq!(a, bincode::serialize(&grown).unwrap());
        let back: Maps = bincode::deserialize(&a).unwrap();
        assert_eq!(back.map.len(), 5);
        assert_eq!(back.map[&ColliderHandle::from_raw_parts(9, 1)], 90);
        assert!(back.set.contains(&RigidBodyHandle::from_raw_parts(3, 2)));
    }

    #[test]
    fn a_repeated_key_is_refused() {
        #[derive(Serialize)]
        struct Raw {
            map: Vec<(ColliderHandle, u32)>,
            set: Vec<RigidBodyHandle>,
        }
        let (c, b) = (
            ColliderHandle::from_raw_parts(1, 0),
            RigidBodyHandle::from_raw_parts(1, 0),
        );
        let twice_in_map = Raw {
            map: vec![(c, 1), (c, 2)],
            set: vec![b],
        };
        let bytes = bincode::serialize(&twice_in_map).unwrap();
        assert!(bincode::deserialize::<Maps>(&bytes).is_err());
        let twice_in_set = Raw {
            map: vec![(c, 1)],
            set: vec![b, b],
        };
        let bytes = bincode::serialize(&twice_in_set).unwrap();
        assert!(bincode::deserialize::<Maps>(&bytes).is_err());
    }

    #[test]
    fn the_world_stamp_sees_one_bit_of_one_pose() {
        let mut world = PhysicsWorld::new();
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(rapier3d::math::Vector::new(0.0, 1.0, 0.0)),
            ColliderBuilder::ball(0.5),
        );
        let before = WorldStamp::of(&WorldView::from(&world));
        assert_eq!(before, WorldStamp::of(&WorldView::from(&world)));
        let mut t = world.bodies[h].translation();
        t.y = f32::from_bits(t.y.to_bits() + 1);
        world.bodies[h].set_translation(t, false);
        let after = WorldStamp::of(&WorldView::from(&world));
        assert_eq!(
            (after.bodies, after.colliders),
            (before.bodies, before.colliders)
        );
        assert_ne!(after.digest, before.digest);
    }
}
