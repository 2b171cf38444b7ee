//! Spatial-Temporal Coherence analysis (paper §3, §5): the post-step pass that keeps
//! the contact graph equal to Rapier's state and marks what changed.
//!
//! # Where the paper's phases land in Rapier
//! The paper runs its analysis between broad phase, narrow phase and contact
//! determination. Rapier's step does all three internally, and already has the
//! paper's "relative transform unchanged → skip the narrow phase" test (contact
//! recycling). So this pass runs *after* Rapier's step, reading the narrow phase:
//! 1. node upkeep (`update.rs` runs the phases in order; `refresh.rs`, creating nodes
//!    through `graph::mirror`): bodies awake now or at the last update are refreshed;
//!    a full scan only when the body or collider count changed (it refreshes the
//!    bodies whose own collider count changed) or on request (it refreshes every
//!    node);
//! 2. edge insertion and marks (`pair_update.rs`, Figs. 3 and 5; triggers in
//!    `triggers.rs`): each collider pair of a
//!    refreshed body is aggregated into the physical edge of its two bodies, whose
//!    proximity and touching states are shifted to `e_old` first;
//! 3. vanishing and obsolete removal (`obsolete.rs`, §3.1): an edge of a refreshed body
//!    that no collider pair reached has vanished; one that vanished at an earlier
//!    update is removed once its AABBs are far apart.
//!
//! The cost is proportional to the refreshed bodies' pairs, never to all pairs: the
//! pairs of sleeping bodies are frozen in Rapier and stay exact in the graph.
//!
//! # Idle steps, verification, and what Rapier does not report
//! A step with nothing awake, no transition and nothing asked for is *idle*: the
//! update stops after the round-robin verification (O(1) beyond it). The
//! verification (`verify.rs`) checks a few graph nodes and Rapier body and collider
//! slots per step, as many as the awake bodies warrant
//! ([`Coherence::verify_budget`]), for changes no Rapier list tells; colliders moved
//! between bodies in place are caught by a signature per refreshed body and a check
//! of cached owners on use (`owners.rs`). What none of it sees (a fixed body or static
//! collider moved or retyped in place, a sleeping body changed without waking it)
//! needs [`LayerAnalysisMut::request_full_sync`](crate::LayerAnalysisMut::request_full_sync):
//! O(nodes + pairs), on request only. The design, with the alternatives rejected, is
//! in `docs/ARCHITECTURE.md`, "What the analysis notices".
//!
//! # What a step exposes
//! [`Coherence::touched_edges`] lists the edges refreshed in the step (their marks
//! are valid for the step), [`Coherence::removed_edges`] the edges removed with a
//! node (each shows a final `Vanished` mark), [`Coherence::removed_nodes`] the nodes
//! whose object left the world.

use crate::graph::mirror as nodes;
pub(crate) mod details;
pub(crate) mod held;
pub(crate) mod obsolete;
mod owners;
mod pair_update;
pub(crate) mod pairs;
mod queries;
mod refresh;
mod removal;
mod touch_feed;
mod touch_update;
mod triggers;
mod unseen;
mod update;
mod user_events;
mod verify;

pub use obsolete::aabbs_obsolete;
pub use pairs::WalkCounters;
pub(crate) use touch_feed::TouchEvent;
pub use touch_feed::{TouchFeed, Tracking};
pub use user_events::{UserEventFilter, WithUser};

use std::collections::BTreeMap;

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, Edge, EdgeId, NodeId, NodeKind, NodeSource};
use crate::WorldView;

/// Nodes (and Rapier body and collider slots) checked per step by the round-robin
/// verification at most: while at least `16 × VERIFY_PER_STEP` bodies are awake.
pub(crate) const VERIFY_PER_STEP: usize = 32;

/// Slots checked per step by the round-robin verification at least: while the whole
/// scene sleeps or is held (see [`Coherence::verify_budget`]).
pub(crate) const VERIFY_IDLE_PER_STEP: usize = 2;

/// Awake bodies per verified slot: the round robin checks one slot of each kind per
/// this many bodies Rapier integrated at the last step (between
/// `VERIFY_IDLE_PER_STEP` and `VERIFY_PER_STEP`).
pub(crate) const AWAKE_BODIES_PER_VERIFIED_SLOT: usize = 16;

/// A lingering (vanished) edge is tested for obsolescence every this many steps.
pub const OBSOLETE_EVERY: u64 = 16;

/// A node removed because its Rapier object left the world.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RemovedNode {
    /// The node's (now stale) id.
    pub id: NodeId,
    /// Its kind.
    pub kind: NodeKind,
    /// What it stood for.
    pub source: NodeSource,
}

/// The state of the analysis between steps.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Coherence {
    step: u64,
    known_bodies: Option<usize>,
    known_colliders: usize,
    force_full_sync: bool,
    /// Nodes refreshed at the last update (awake then).
    awake_prev: Vec<NodeId>,
    /// This step's refreshed nodes (awake now, or awake at the last update).
    walk: Vec<NodeId>,
    /// Scratch: the sensor colliders of the bodies in `walk` with their nodes, in walk
    /// order, found when they joined it (their body is then at hand).
    #[cfg_attr(feature = "serde", serde(skip))]
    walk_sensors: Vec<(NodeId, ColliderHandle)>,
    touched: Vec<EdgeId>,
    removed_edges: Vec<Edge>,
    removed_nodes: Vec<RemovedNode>,
    created: Vec<NodeId>,
    counters: WalkCounters,
    /// Scratch: edges found dead this step.
    dead: Vec<EdgeId>,
    /// Collider slot → the node owning it (its parent body's, or its own), so that a
    /// collider pair costs two array reads instead of Rapier collider and body lookups.
    /// A cache: not saved in snapshots (a restored layer rebuilds it from the world on
    /// first use instead of trusting it from bytes).
    #[cfg_attr(feature = "serde", serde(skip))]
    owners: Cache<Vec<Owner>>,
    /// Rapier pair slot → the edge it fed at the last full scan (see `scan_all_pairs`).
    /// A cache, not saved, like `owners`.
    #[cfg_attr(feature = "serde", serde(skip))]
    pair_slots: Cache<Vec<PairSlot>>,
    /// Maintain the per-edge contact details (see [`Coherence::set_contact_details`]).
    skip_details: bool,
    scan: ScanPolicy,
    /// Triggers carried by this step's refreshed bodies.
    triggers: Vec<NodeId>,
    /// Bodies that fell asleep (`false`) or woke up (`true`) this step.
    sleep_changes: Vec<(NodeId, bool)>,
    /// Bodies made passive or active this step.
    passive_changed: Vec<NodeId>,
    /// Nodes whose awake flag changed this step (their group's sleep is counted
    /// again). Per-step scratch.
    #[cfg_attr(feature = "serde", serde(skip))]
    awake_flips: Vec<NodeId>,
    /// Scratch buffer for a node's colliders.
    scratch_colliders: Vec<ColliderHandle>,
    verify_cursor: u32,
    verify_body_cursor: u32,
    verify_collider_cursor: u32,
    /// Node kind changes in the last step.
    kind_changes: usize,
    /// Every trigger read so far, with the state of its sensor collider at its last
    /// read: a trigger that no refreshed body carries is read again when that state
    /// changed (see [`TriggerState`]). In node order, for a deterministic walk.
    trigger_states: BTreeMap<NodeId, TriggerState>,
    /// Triggers to read this step besides those of refreshed bodies and new ones
    /// (rule members, a requested full sync).
    pending_triggers: Vec<NodeId>,
    /// Held bodies the speed-ups disabled for this one step to take them out of
    /// Rapier's active set: not passive, whatever Rapier's enabled flag says. Set
    /// before each update; sorted.
    #[cfg_attr(feature = "serde", serde(skip))]
    parking: Vec<RigidBodyHandle>,
    /// Held bodies enabled again before this step after their step out of Rapier's
    /// active set: Rapier pairs their colliders anew, so their sensor pairs are read
    /// (a sensor widened meanwhile may find them inside; nothing else refreshes a
    /// held body). Set before each update.
    #[cfg_attr(feature = "serde", serde(skip))]
    parked_now: Vec<RigidBodyHandle>,
    /// Bodies in Rapier's active set that Rapier integrates (not fixed) at the last
    /// update.
    #[cfg_attr(feature = "serde", serde(default))]
    integrated: usize,
    /// The tracking in effect at the last update (see [`Tracking`]); `None` before
    /// the first (so that touching tracking reads the touching pairs once when it
    /// starts, whatever the default).
    #[cfg_attr(feature = "serde", serde(default))]
    tracking: Option<Tracking>,
    /// Whether the layer's event handler was given to Rapier's last analysed step
    /// (see [`Tracking`]): touching tracking goes on only then.
    #[cfg_attr(feature = "serde", serde(default))]
    feed_connected: bool,
    /// The tracking the user asked for.
    #[cfg_attr(feature = "serde", serde(default))]
    tracking_requested: Tracking,
    /// Colliders the layer gave `ActiveEvents::COLLISION_EVENTS` (touching tracking),
    /// by raw handle: the flag is taken off them again when tracking ends.
    #[cfg_attr(feature = "serde", serde(default))]
    touch_flagged: BTreeMap<(u32, u32), ColliderHandle>,
    /// The collider count at the last full flag pass.
    #[cfg_attr(feature = "serde", serde(default))]
    touch_flag_colliders: usize,
    #[cfg_attr(feature = "serde", serde(default))]
    touch_flag_cursor: u32,
    /// Colliders flagged since the last update: their touching pairs are read once.
    #[cfg_attr(feature = "serde", serde(default))]
    touch_rescan: Vec<ColliderHandle>,
    /// Nodes that lost or gained a collider in place (`ColliderSet::set_parent`, a
    /// collider swapped for another, a collider turned into a sensor): their pairs are
    /// read again at the next update (see [`Coherence::owner_moved`]).
    #[cfg_attr(feature = "serde", serde(default))]
    stale: Vec<NodeId>,
    /// Where the last world's body and collider storage was (see
    /// [`Coherence::same_world`]). Addresses: not part of a snapshot.
    #[cfg_attr(feature = "serde", serde(skip))]
    world_mark: Cache<Option<(usize, usize)>>,
    /// A few awake bodies as the last update saw them: tells a Rapier step the layer
    /// did not see (see `unseen.rs`). Not part of a snapshot: a restored layer checks
    /// from its first update on.
    #[cfg_attr(feature = "serde", serde(skip))]
    witness: Cache<unseen::StepWitness>,
    /// Nodes the verification found changed in a way only a refresh reads (a body
    /// disabled or enabled in place): refreshed in this step.
    #[cfg_attr(feature = "serde", serde(skip))]
    recheck: Vec<NodeId>,
    /// The frozen edges of the bodies the pre-step gave back (see
    /// [`Coherence::mark_held`]), for this step's update.
    #[cfg_attr(feature = "serde", serde(skip))]
    thawed: Vec<EdgeId>,
    /// The bodies the pre-step gave back, for this step's update.
    #[cfg_attr(feature = "serde", serde(skip))]
    released_now: Vec<NodeId>,
    /// Whether the pre-step found a Rapier step the layer did not see (reported in
    /// the next update's counters).
    #[cfg_attr(feature = "serde", serde(skip))]
    unseen_step: bool,
}

/// What a trigger's read depends on besides the bodies it meets: its sensor collider's
/// pose, enabled flag and shape. A trigger carried by a body that is not refreshed (a
/// fixed or passive carrier, or none) is read again when one of them changed; O(1) per
/// trigger and step.
/// A lookup cache: derived from the world, left out of snapshots and of `Debug` (a
/// restored layer starts with it empty and refills it on first use, with the same
/// results). Reads and writes go through `Deref`.
#[derive(Clone, Default)]
struct Cache<T>(T);

impl<T> std::fmt::Debug for Cache<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Cache")
    }
}

impl<T> std::ops::Deref for Cache<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<T> std::ops::DerefMut for Cache<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.0
    }
}

#[derive(Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct TriggerState {
    pose: [u32; 7],
    enabled: bool,
    /// The carrier body (`ColliderSet::set_parent` moves a sensor in place).
    #[cfg_attr(feature = "serde", serde(default))]
    parent: Option<RigidBodyHandle>,
    /// The address of the shared shape (`set_shape` replaces it). Meaningless in
    /// another process: not part of a snapshot (a restored trigger is read again once,
    /// which changes nothing when nothing changed).
    #[cfg_attr(feature = "serde", serde(skip))]
    shape: usize,
}

/// Without the shape's address, which differs from process to process.
impl std::fmt::Debug for TriggerState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TriggerState")
            .field("pose", &self.pose)
            .field("enabled", &self.enabled)
            .field("parent", &self.parent)
            .finish_non_exhaustive()
    }
}

impl TriggerState {
    fn of(c: &rapier3d::geometry::Collider) -> Self {
        Self {
            pose: crate::util::rapier::pose_bits(c.position()),
            enabled: c.is_enabled(),
            parent: c.parent(),
            shape: std::sync::Arc::as_ptr(&c.shared_shape().0) as *const () as usize,
        }
    }
}

/// How the pairs of the refreshed bodies are found (both give the same graph; the
/// choice is about speed). Exposed for tests and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ScanPolicy {
    /// Scan Rapier's whole pair array when at least half of the moving bodies were
    /// refreshed, walk the refreshed bodies' pairs otherwise.
    #[default]
    Auto,
    /// Always scan the whole pair array.
    Scan,
    /// Always walk the refreshed bodies' pairs.
    Walk,
}

/// What a slot of Rapier's contact-pair array held at the last scan.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct PairSlot {
    c1: ColliderHandle,
    c2: ColliderHandle,
    edge: EdgeId,
    /// `collider1`'s owner is the edge's B node.
    flip: bool,
}

/// A cached collider owner, valid for one collider generation.
#[derive(Clone, Copy, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
enum Owner {
    #[default]
    Unknown,
    /// The collider (of this generation) has no node: a sensor.
    Nobody(u32),
    /// The collider (of this generation) belongs to this node.
    Node(u32, NodeId),
}

/// The logical test of Fig. 4 and the logic layer's refresh requests, handed to the
/// analysis for one step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Screen<'a> {
    /// The rules in force.
    pub rules: &'a crate::logic::RuleTable,
    /// Nodes to refresh even if asleep.
    pub force: &'a [NodeId],
}

impl Screen<'_> {
    /// Whether one collider pair of `a` and `b` is treated: no passive end, and no
    /// rule against it *that Rapier applied*. A rule acts through the filter hooks,
    /// which Rapier asks only for pairs where a collider carries the hook flag
    /// (`FILTER_INTERSECTION_PAIR` for a sensor pair, `FILTER_CONTACT_PAIRS`
    /// otherwise): a pair without it (a collider a member gained since the flags were
    /// set) is collided by Rapier, so the graph shows it; so is a pair with a node made
    /// by this analysis (the hooks could not name it during the step). O(1); two
    /// collider lookups when a rule names the pair.
    #[inline]
    pub(crate) fn admits_pair(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        (a, b): (NodeId, NodeId),
        (c1, c2): (ColliderHandle, ColliderHandle),
        sensor_pair: bool,
    ) -> bool {
        let passive = |n| graph.node(n).is_none_or(|n| n.passive);
        if passive(a) || passive(b) {
            return false;
        }
        self.rules.is_empty() || !self.rule_screens(graph, view, (a, b), (c1, c2), sensor_pair)
    }

    /// [`Self::admits_pair`] for one of Rapier's contact pairs. O(1).
    #[inline]
    pub(crate) fn admits_contact(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        nodes: (NodeId, NodeId),
        pair: &rapier3d::geometry::ContactPair,
    ) -> bool {
        self.admits_pair(graph, view, nodes, (pair.collider1, pair.collider2), false)
    }

    /// Whether a rule screens one collider pair of `a` and `b` *and Rapier applied
    /// it*: the rule ignores the pair, a collider carries the filter flag, and both
    /// nodes existed during Rapier's step (see [`Self::admits_pair`]). What the
    /// analysis hides, and what `validate()` requires Rapier to have filtered. Out of
    /// the hot path (called only when rules exist). O(1).
    #[inline(never)]
    pub(crate) fn rule_screens(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        (a, b): (NodeId, NodeId),
        (c1, c2): (ColliderHandle, ColliderHandle),
        sensor_pair: bool,
    ) -> bool {
        self.rules.ignores(a, b)
            && rule_applied(view, c1, c2, sensor_pair)
            && !born_now(graph, a)
            && !born_now(graph, b)
    }
}

/// Whether the node was made by the last analysis: Rapier's hooks, asked during the
/// step before it, could not name it, so no rule about it was applied yet. O(1).
fn born_now(graph: &ContactGraph, n: NodeId) -> bool {
    graph
        .node(n)
        .is_some_and(|node| node.born_step == graph.clock)
}

/// Whether Rapier asks the filter hooks about a collider pair (so a rule screening
/// it is applied). O(1).
fn rule_applied(
    view: &WorldView,
    c1: ColliderHandle,
    c2: ColliderHandle,
    sensor_pair: bool,
) -> bool {
    use rapier3d::pipeline::ActiveHooks;
    let flag = if sensor_pair {
        ActiveHooks::FILTER_INTERSECTION_PAIR
    } else {
        ActiveHooks::FILTER_CONTACT_PAIRS
    };
    let hooked = |c| {
        view.colliders
            .get(c)
            .is_some_and(|c| c.active_hooks().contains(flag))
    };
    hooked(c1) || hooked(c2)
}

/// The next `n` slots after a round-robin cursor, advancing it by as many: all `span`
/// slots when there are at most `VERIFY_PER_STEP` (a small world is checked whole
/// every step, at the price of a few slots of a large one), otherwise `n`.
fn round_robin(cursor: &mut u32, span: u32, n: usize) -> impl Iterator<Item = u32> {
    let count = if span as usize <= VERIFY_PER_STEP {
        span
    } else {
        n.min(span as usize) as u32
    };
    let start = *cursor;
    *cursor = start.wrapping_add(count);
    (0..count).map(move |k| start.wrapping_add(k) % span.max(1))
}

/// Fills `out` with the colliders a node owns (a body's colliders, or a static
/// collider itself); `false` for other nodes and bodies that are gone.
fn colliders_of(
    graph: &ContactGraph,
    view: &WorldView,
    n: NodeId,
    out: &mut Vec<ColliderHandle>,
) -> bool {
    out.clear();
    match graph.node(n).map(|n| n.source) {
        Some(NodeSource::Body(h)) => match view.bodies.get(h) {
            Some(rb) => {
                out.extend_from_slice(rb.colliders());
                true
            }
            None => false,
        },
        Some(NodeSource::StaticCollider(c)) => {
            out.push(c);
            true
        }
        _ => false,
    }
}

fn pose_of(graph: &ContactGraph, view: &WorldView, n: NodeId) -> Option<rapier3d::math::Pose> {
    match graph.node(n)?.source {
        NodeSource::Body(h) => view.bodies.get(h).map(|rb| *rb.position()),
        NodeSource::StaticCollider(h) | NodeSource::Sensor(h) => {
            view.colliders.get(h).map(|c| *c.position())
        }
        NodeSource::Container(_) | NodeSource::Layer(_) => None,
    }
}
