//! Spatial-Temporal Coherence analysis (paper §3, §5): the post-step pass that keeps
//! the contact graph equal to Rapier's state and marks what changed.
//!
//! # Where the paper's phases land in Rapier
//! The paper runs its analysis between broad phase, narrow phase and contact
//! determination. Rapier's step does all three internally, and already has the
//! paper's "relative transform unchanged → skip the narrow phase" test (contact
//! recycling). So this pass runs *after* Rapier's step, reading the narrow phase:
//! 1. node upkeep (`nodes.rs`): bodies awake now or at the last update are refreshed;
//!    a full scan only when the body or collider count changed (it refreshes the
//!    bodies whose own collider count changed) or on request (it refreshes every
//!    node);
//! 2. edge insertion and marks (`pairs.rs`, Figs. 3 and 5): each collider pair of a
//!    refreshed body is aggregated into the physical edge of its two bodies, whose
//!    proximity and touching states are shifted to `e_old` first;
//! 3. vanishing and obsolete removal (`obsolete.rs`, §3.1): an edge of a refreshed body
//!    that no collider pair reached has vanished; one that vanished at an earlier
//!    update is removed once its AABBs are far apart.
//!
//! The cost is proportional to the refreshed bodies' pairs, never to all pairs: the
//! pairs of sleeping bodies are frozen in Rapier and stay exact in the graph.
//!
//! # Overlaps whose two sides are never refreshed
//! Refreshing only what moves misses a change of an overlap between two nodes that are
//! both not refreshed: fixed bodies, static colliders, sleeping or passive bodies, and
//! triggers carried by them. Rapier knows what the user changed (its modified-body and
//! modified-collider lists and per-object change flags), but none of it is public:
//! `ColliderSet::take_modified` empties the list Rapier's own step needs, and it
//! cannot be put back. So the layer notices such changes itself, each at a cost
//! proportional to what changed or to the (few) triggers, never to all colliders:
//! - the layer's own changes: a rule's members of every kind, a body made passive or
//!   active, a sensor whose collision types the layer widened, are refreshed at the
//!   next update;
//! - a body whose number of colliders changed is refreshed by the full scan that the
//!   changed collider count starts anyway (a fixed body losing its collider inside a
//!   trigger);
//! - a trigger that no refreshed body carries is read again when its sensor
//!   collider's pose, enabled flag or shape changed (a fixed or passive carrier
//!   moved, a parentless sensor moved): O(triggers) per update, a compare each;
//! - the sensors of the refreshed bodies are always looked for, so a collider turned
//!   into a sensor gets its trigger in the same step (O(their colliders));
//! - what none of this sees (a fixed body or static collider moved, retyped or turned
//!   into a sensor in place; a sleeping body changed without waking it) needs
//!   [`Coherence::request_full_sync`], which refreshes every node at the next update:
//!   O(nodes + pairs), on request only.
//!
//! Rejected: reading every trigger every step (a trigger over a settled pile would cost
//! its pairs every step), and refreshing every node on every full scan (a scene that
//! spawns a body per step would pay for all its pairs every step).
//!
//! # What a step exposes
//! [`Coherence::touched_edges`] lists the edges refreshed in the step (their marks
//! are valid for the step), [`Coherence::removed_edges`] the edges removed with a
//! node (each shows a final `Vanished` mark), [`Coherence::removed_nodes`] the nodes
//! whose object left the world.

use crate::graph::mirror as nodes;
pub(crate) mod obsolete;
pub(crate) mod pairs;

pub use obsolete::aabbs_obsolete;
pub use pairs::WalkCounters;

use std::collections::BTreeMap;

use rapier3d::geometry::ContactPair;
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, Edge, EdgeId, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::WorldView;

/// Nodes (and Rapier body slots) checked per step by the round-robin verification.
pub const VERIFY_PER_STEP: usize = 32;

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
    touched: Vec<EdgeId>,
    removed_edges: Vec<Edge>,
    removed_nodes: Vec<RemovedNode>,
    created: Vec<NodeId>,
    counters: WalkCounters,
    /// Scratch: edges found dead this step.
    dead: Vec<EdgeId>,
    /// Collider slot → the node owning it (its parent body's, or its own), so that a
    /// collider pair costs two array reads instead of Rapier collider and body lookups.
    owners: Vec<Owner>,
    /// Rapier pair slot → the edge it fed at the last full scan (see `scan_all_pairs`).
    pair_slots: Vec<PairSlot>,
    /// Maintain the per-edge contact details (see [`Coherence::set_contact_details`]).
    skip_details: bool,
    scan: ScanPolicy,
    /// Triggers carried by this step's refreshed bodies.
    triggers: Vec<NodeId>,
    /// Bodies that fell asleep (`false`) or woke up (`true`) this step.
    sleep_changes: Vec<(NodeId, bool)>,
    /// Bodies made passive or active this step.
    passive_changed: Vec<NodeId>,
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
}

/// What a trigger's read depends on besides the bodies it meets: its sensor collider's
/// pose, enabled flag and shape. A trigger carried by a body that is not refreshed (a
/// fixed or passive carrier, or none) is read again when one of them changed; O(1) per
/// trigger and step.
#[derive(Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct TriggerState {
    pose: [u32; 7],
    enabled: bool,
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
            .finish_non_exhaustive()
    }
}

impl TriggerState {
    fn of(c: &rapier3d::geometry::Collider) -> Self {
        let p = c.position();
        let (t, r) = (p.translation, p.rotation);
        Self {
            pose: [t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f32::to_bits),
            enabled: c.is_enabled(),
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

impl Coherence {
    /// The index of the last analysed step (0 before the first).
    pub fn step(&self) -> u64 {
        self.step
    }
    /// Edges refreshed in the last step: their marks are valid. In a deterministic
    /// order: Rapier's pair order, then the edges found vanished.
    pub fn touched_edges(&self) -> &[EdgeId] {
        &self.touched
    }
    /// Takes the addresses of the triggers' shapes from `colliders` (after a restore:
    /// an address means nothing in another process). O(triggers).
    #[cfg(feature = "serde")]
    pub(crate) fn rebind_trigger_shapes(
        &mut self,
        graph: &ContactGraph,
        colliders: &rapier3d::prelude::ColliderSet,
    ) {
        for (n, st) in self.trigger_states.iter_mut() {
            if let Some(NodeSource::Sensor(c)) = graph.node(*n).map(|x| x.source()) {
                if let Some(co) = colliders.get(c) {
                    st.shape = TriggerState::of(co).shape;
                }
            }
        }
    }

    /// Edges removed in the last step because one of their nodes left the world, with
    /// their final state (marks `Vanished` where they were on).
    pub fn removed_edges(&self) -> &[Edge] {
        &self.removed_edges
    }
    /// Nodes removed in the last step.
    pub fn removed_nodes(&self) -> &[RemovedNode] {
        &self.removed_nodes
    }
    /// Nodes created in the last step.
    pub fn created_nodes(&self) -> &[NodeId] {
        &self.created
    }
    /// Nodes refreshed in the last step (awake now or at the update before).
    pub fn refreshed_nodes(&self) -> &[NodeId] {
        &self.walk
    }
    /// Bodies that fell asleep (`false`) or woke up (`true`) in the last step, in the
    /// order they were refreshed.
    pub fn sleep_changes(&self) -> &[(NodeId, bool)] {
        &self.sleep_changes
    }
    /// Node kind changes seen in the last step.
    pub fn kind_changes(&self) -> usize {
        self.kind_changes
    }
    /// Counters of the last pair walk.
    pub fn counters(&self) -> WalkCounters {
        self.counters
    }
    /// Whether the per-edge contact details (relative pose and its change flag, closest
    /// distance, deepest penetration, normal impulse, deepest normal) are maintained.
    pub fn contact_details(&self) -> bool {
        !self.skip_details
    }
    /// Turns the per-edge contact details on (the default) or off. Off, each collider
    /// pair costs only its proximity, touching state and contact count; the details
    /// keep their last values and support queries see no normals.
    pub fn set_contact_details(&mut self, on: bool) {
        self.skip_details = !on;
    }
    /// Chooses how pairs are found (see [`ScanPolicy`]).
    pub fn set_scan_policy(&mut self, policy: ScanPolicy) {
        self.scan = policy;
    }
    /// Asks for a full scan of bodies and colliders at the next update, which also
    /// refreshes every node (pairs and triggers read again): after changing a sleeping
    /// or fixed body, or static geometry, in place (moving it, its type, a sensor
    /// flag), which Rapier does not report. That update costs O(nodes + pairs).
    pub fn request_full_sync(&mut self) {
        self.force_full_sync = true;
    }

    /// Checks a few nodes and Rapier body slots per step, round robin: a node whose
    /// object is gone is removed, a body whose type changed in place gets its kind,
    /// and a body without node gets one. It makes the graph consistent, within
    /// `nodes / VERIFY_PER_STEP` steps, after changes the per-step upkeep cannot see
    /// (removing and inserting bodies between two steps, retyping a sleeping body),
    /// without a full scan. O(VERIFY_PER_STEP).
    fn verify_some(&mut self, graph: &mut ContactGraph, groups: &mut Groups, view: &WorldView) {
        let slots = graph.nodes.slot_count() as u32;
        for i in round_robin(&mut self.verify_cursor, slots, VERIFY_PER_STEP) {
            let Some(id) = graph.node_id_at(i) else {
                continue;
            };
            let Some(source) = graph.node(id).map(|n| n.source) else {
                continue;
            };
            if !nodes::source_exists(view, source) {
                self.remove_node(graph, groups, id);
            } else if let NodeSource::Body(h) = source {
                nodes::ensure_body_node(graph, view, h, &mut self.created);
            }
        }
        // Rapier's arenas may hold free slots beyond `len()`: cover the highest slot the
        // graph has seen too.
        let body_slots =
            view.bodies.len().max(graph.body_slot_span()) as u32 + VERIFY_PER_STEP as u32;
        for i in round_robin(&mut self.verify_body_cursor, body_slots, VERIFY_PER_STEP) {
            if let Some((_, h)) = view.bodies.get_unknown_gen(i) {
                if graph.node_of_body(h).is_none() {
                    nodes::ensure_body_node(graph, view, h, &mut self.created);
                }
            }
        }
        let collider_slots =
            view.colliders.len().max(graph.collider_slot_span()) as u32 + VERIFY_PER_STEP as u32;
        for i in round_robin(
            &mut self.verify_collider_cursor,
            collider_slots,
            VERIFY_PER_STEP,
        ) {
            if let Some((c, h)) = view.colliders.get_unknown_gen(i) {
                if c.is_sensor() {
                    nodes::ensure_trigger_node(graph, view, h, &mut self.created);
                } else if c.parent().is_none() {
                    nodes::ensure_collider_owner(graph, view, h, &mut self.created);
                }
            }
        }
    }

    /// Reports the edges a kind change dropped (ended, with `Vanished` marks) and
    /// regroups their ends.
    pub(crate) fn take_dropped(&mut self, graph: &mut ContactGraph, groups: &mut Groups) {
        let step = self.step;
        for n in std::mem::take(&mut graph.evicted) {
            self.remove_node(graph, groups, n);
        }
        for n in std::mem::take(&mut graph.kind_changed) {
            self.kind_changes += 1;
            groups.disturb(graph, n);
        }
        for mut e in std::mem::take(&mut graph.dropped) {
            groups.disturb(graph, e.a);
            groups.disturb(graph, e.b);
            if e.cache.proximity {
                e.cache.begin_update(true);
                e.updated_step = step;
                self.removed_edges.push(e);
            }
        }
    }

    fn remove_node(&mut self, graph: &mut ContactGraph, groups: &mut Groups, id: NodeId) {
        let Some(node) = graph.node(id) else { return };
        let record = RemovedNode {
            id,
            kind: node.kind,
            source: node.source,
        };
        if let Some(g) = node.group {
            groups.dissolve(graph, g);
        }
        // Neighbours lose an edge: their groups must be rebuilt.
        let neighbours: Vec<NodeId> = graph.neighbors(id).map(|(m, _, _)| m).collect();
        for m in neighbours {
            groups.disturb(graph, m);
        }
        let step = self.step;
        for mut e in graph.remove_node(id) {
            e.cache.begin_update(true);
            e.updated_step = step;
            self.removed_edges.push(e);
        }
        self.removed_nodes.push(record);
    }

    /// Runs the analysis of one step. `step` must grow by one per call. `screen`
    /// carries the logical test of Fig. 4 (rules) and the nodes the logic layer wants
    /// refreshed even if asleep (rule members, bodies made passive or active).
    pub(crate) fn update(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        screen: &Screen,
    ) {
        self.step += 1;
        let step = self.step;
        graph.clock = step;
        self.touched.clear();
        self.removed_edges.clear();
        self.removed_nodes.clear();
        self.created.clear();
        self.sleep_changes.clear();
        self.passive_changed.clear();
        self.kind_changes = 0;
        self.counters = WalkCounters::default();

        // 1. Node upkeep.
        self.pending_triggers.clear();
        let requested = self.force_full_sync;
        let counts_changed = self.known_bodies != Some(view.bodies.len())
            || self.known_colliders != view.colliders.len();
        let mut resized = Vec::new();
        if counts_changed || requested {
            self.force_full_sync = false;
            let gone = nodes::full_sync(graph, view, &mut self.created, &mut resized);
            for id in gone {
                self.remove_node(graph, groups, id);
            }
            self.known_bodies = Some(view.bodies.len());
            self.known_colliders = view.colliders.len();
        }
        self.verify_some(graph, groups, view);
        self.walk.clear();
        for h in view.islands.active_bodies() {
            // Rapier keeps a body turned fixed in its active set: once the graph has it
            // as fixed, there is nothing to refresh (it does not move).
            if view.bodies.get(h).is_some_and(|b| b.is_fixed())
                && graph
                    .node_of_body(h)
                    .and_then(|n| graph.node(n))
                    .is_some_and(|n| n.kind == NodeKind::Fixed && n.seen_step != 0)
            {
                continue;
            }
            let Some(id) = nodes::ensure_body_node(graph, view, h, &mut self.created) else {
                continue;
            };
            self.mark_refreshed(graph, view, id, h, true);
        }
        // Bodies that fell asleep, turned fixed or were disabled (awake at the last
        // update), the nodes the logic layer asks for (rule members of any kind, bodies
        // made passive or active), and bodies whose colliders were added or removed (a
        // fixed body losing its collider inside a trigger: nobody else would notice).
        let prev = std::mem::take(&mut self.awake_prev);
        for &id in prev.iter().chain(screen.force.iter()).chain(resized.iter()) {
            self.refresh_node(graph, groups, view, id);
        }
        // Nodes created this step are refreshed once whatever their state: a body
        // Rapier put to sleep in its very first step (a huge dt), or new static
        // geometry, still has its pairs read.
        for i in 0..self.created.len() {
            let id = self.created[i];
            self.refresh_node(graph, groups, view, id);
        }
        // A requested full sync refreshes everything: the user changed a sleeping or
        // fixed body (or static geometry) in place, which no Rapier list tells. O(nodes
        // + pairs), on request only.
        if requested {
            let all: Vec<NodeId> = graph.nodes().map(|(id, _)| id).collect();
            for id in all {
                self.refresh_node(graph, groups, view, id);
            }
        }
        self.awake_prev = prev;
        self.awake_prev.clear();
        for &id in &self.walk {
            if graph.node(id).is_some_and(|n| n.awake) {
                self.awake_prev.push(id);
            }
        }
        self.take_dropped(graph, groups);
        // Nodes created this step (e.g. a new fixed body) have no pairs walked from
        // them, but their pairs with awake bodies are walked from the other side.
        for i in 0..self.created.len() {
            let id = self.created[i];
            groups.disturb(graph, id);
        }

        // 2. Edge insertion and marks. When at least half of the moving bodies were
        // refreshed, one sequential pass over Rapier's pair array beats walking each
        // body's adjacency (which reaches every pair twice); otherwise the walk keeps
        // the cost proportional to the refreshed bodies.
        let walk = std::mem::take(&mut self.walk);
        let moving = graph.count_of_kind(NodeKind::Rigid)
            + graph.count_of_kind(NodeKind::Link)
            + graph.count_of_kind(NodeKind::Scripted);
        let scan = match self.scan {
            ScanPolicy::Auto => 2 * walk.len() >= moving,
            ScanPolicy::Scan => true,
            ScanPolicy::Walk => false,
        };
        if scan {
            self.scan_all_pairs(graph, view, screen);
            self.counters.bodies = walk.len();
        } else {
            for &me in &walk {
                self.walk_pairs(graph, view, screen, me);
            }
        }
        // Trigger volumes: the triggers carried by refreshed bodies, the new ones and
        // those asked for are read from their side; then the triggers whose sensor
        // collider changed (moved with a fixed or passive carrier, or parentless);
        // then the refreshed and new bodies' colliders meet the other triggers. The
        // refreshed bodies' colliders are always looked at, so that a collider turned
        // into a sensor gets its trigger in the same step: O(their colliders).
        self.triggers.clear();
        let mut sensors = Vec::new();
        for &me in &walk {
            if let Some(NodeSource::Body(h)) = graph.node(me).map(|n| n.source) {
                if let Some(rb) = view.bodies.get(h) {
                    for &c in rb.colliders() {
                        if view.colliders.get(c).is_some_and(|c| c.is_sensor()) {
                            sensors.push(c);
                        }
                    }
                }
            }
        }
        let mut to_read: Vec<NodeId> = sensors
            .into_iter()
            .filter_map(|c| nodes::ensure_trigger_node(graph, view, c, &mut self.created))
            .collect();
        let created_now = self.created.clone();
        to_read.extend(
            created_now
                .iter()
                .copied()
                .filter(|&n| graph.node(n).is_some_and(|n| n.kind == NodeKind::Trigger)),
        );
        to_read.append(&mut self.pending_triggers);
        for t in to_read {
            self.walk_trigger(graph, view, screen, t);
        }
        self.read_changed_triggers(graph, view, screen);
        if graph.count_of_kind(NodeKind::Trigger) > 0 {
            for &me in walk.iter().chain(created_now.iter()) {
                self.walk_body_sensors(graph, view, screen, me);
            }
        }

        // 3. Vanished edges and obsolete removal, for the refreshed bodies and the
        // triggers they carry.
        let triggers = std::mem::take(&mut self.triggers);
        if scan {
            // One sequential pass over the edge arena instead of each refreshed node's
            // edges (random access, every edge twice): the scan already cost O(pairs).
            self.dead.clear();
            for (eid, e) in graph.edges() {
                let dynamic = matches!(e.kind, EdgeKind::Physical | EdgeKind::Geometric);
                if !dynamic || e.walk_stamp == step {
                    continue;
                }
                let refreshed = |n| {
                    graph
                        .node(n)
                        .is_some_and(|n: &crate::Node| n.seen_step == step)
                };
                if refreshed(e.a) || refreshed(e.b) {
                    self.dead.push(eid);
                }
            }
            for i in 0..self.dead.len() {
                let eid = self.dead[i];
                self.retire(graph, groups, view, eid);
            }
        }
        for &me in walk.iter().filter(|_| !scan).chain(triggers.iter()) {
            self.dead.clear();
            let Some(node) = graph.node(me) else { continue };
            for &eid in &node.edges {
                let Some(e) = graph.edge(eid) else { continue };
                let dynamic = matches!(e.kind, EdgeKind::Physical | EdgeKind::Geometric);
                if dynamic && e.walk_stamp != step {
                    self.dead.push(eid);
                }
            }
            for i in 0..self.dead.len() {
                let eid = self.dead[i];
                self.retire(graph, groups, view, eid);
            }
        }
        self.triggers = triggers;

        // Groups change only where structure changed: a contact started or ended, a
        // body woke, slept, became passive (above), changed kind or appeared (in
        // `take_dropped` and node upkeep). A refreshed body without a group (first
        // seen, released) is a root too.
        for i in 0..self.touched.len() {
            let Some(e) = graph.edge(self.touched[i]) else {
                continue;
            };
            if e.kind == EdgeKind::Physical && e.cache.touching != e.cache.touching_old {
                let (a, b) = (e.a, e.b);
                groups.disturb(graph, a);
                groups.disturb(graph, b);
            }
        }
        for &(n, _) in &self.sleep_changes {
            groups.disturb(graph, n);
        }
        for &me in &walk {
            let ungrouped = graph
                .node(me)
                .is_some_and(|n| n.kind.is_simulated() && n.group.is_none() && !n.passive);
            if ungrouped || self.passive_changed.contains(&me) {
                groups.disturb(graph, me);
            }
        }
        self.take_dropped(graph, groups);
        self.walk = walk;
        // Each edge is pushed once (guarded by its walk stamp) and no touched edge is
        // removed in the same step, so the list needs no sorting or filtering: its
        // order is Rapier's pair order, then the vanished edges, which is deterministic.
        debug_assert!(self.touched.iter().all(|&e| graph.edge(e).is_some()));
    }

    /// Refreshes one node whatever its state, if not done this step: a body's pairs are
    /// read (it joins the walk), static geometry's too, a trigger is read from its side.
    /// A node whose object is gone is removed. Containers and logical nodes: nothing.
    fn refresh_node(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        id: NodeId,
    ) {
        let step = self.step;
        let Some(node) = graph.node(id) else { return };
        if node.seen_step == step {
            return;
        }
        match node.source {
            NodeSource::Body(h) if view.bodies.contains(h) => {
                let _ = nodes::ensure_body_node(graph, view, h, &mut self.created);
                self.mark_refreshed(graph, view, id, h, false);
            }
            NodeSource::StaticCollider(c) if nodes::is_static_collider_node(view, c) => {
                if let Some(n) = graph.node_mut(id) {
                    n.seen_step = step;
                }
                self.walk.push(id);
            }
            NodeSource::Sensor(c) if view.colliders.get(c).is_some_and(|c| c.is_sensor()) => {
                self.pending_triggers.push(id);
            }
            NodeSource::Body(_) | NodeSource::StaticCollider(_) | NodeSource::Sensor(_) => {
                self.remove_node(graph, groups, id);
            }
            NodeSource::Container(_) | NodeSource::Layer(_) => {}
        }
    }

    fn mark_refreshed(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        id: NodeId,
        h: RigidBodyHandle,
        awake: bool,
    ) {
        let step = self.step;
        let rb = view.bodies.get(h);
        let finite = rb.is_some_and(|rb| {
            rb.position().translation.is_finite() && rb.position().rotation.is_finite()
        });
        let enabled = rb.is_some_and(|rb| rb.is_enabled());
        if let Some(n) = graph.node_mut(id) {
            if n.seen_step == step {
                return;
            }
            let was_passive = n.passive;
            n.seen_step = step;
            n.awake = awake && !matches!(n.kind, NodeKind::Fixed);
            n.non_finite = !finite;
            n.passive = !enabled;
            if was_passive != n.passive {
                self.passive_changed.push(id);
            }
            // Sleep events report changes of a simulated, non-passive body's state
            // against the last reported one: a body created this step starts (no
            // event), a passive spell or a time as a fixed body reports nothing, and
            // the events alternate.
            if n.kind.is_simulated() && !n.passive {
                match n.reported_awake {
                    None => n.reported_awake = Some(n.awake),
                    Some(r) if r != n.awake && n.born_step != step => {
                        n.reported_awake = Some(n.awake);
                        self.sleep_changes.push((id, n.awake));
                    }
                    Some(_) => n.reported_awake = Some(n.awake),
                }
            }
            self.walk.push(id);
        }
    }

    /// The node owning a collider, from the owner table (slow path: Rapier lookups,
    /// creating the node if it is missing). `None` for sensors.
    #[inline]
    fn owner_of(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        collider: ColliderHandle,
    ) -> Option<NodeId> {
        let (i, gen) = collider.into_raw_parts();
        match self.owners.get(i as usize) {
            Some(Owner::Node(g, n)) if *g == gen && graph.contains_node(*n) => return Some(*n),
            Some(Owner::Nobody(g)) if *g == gen => return None,
            _ => {}
        }
        let owner = nodes::ensure_collider_owner(graph, view, collider, &mut self.created);
        if self.owners.len() <= i as usize {
            self.owners.resize(i as usize + 1, Owner::Unknown);
        }
        self.owners[i as usize] = match owner {
            Some(n) => Owner::Node(gen, n),
            None if view.colliders.contains(collider) => Owner::Nobody(gen),
            None => Owner::Unknown,
        };
        owner
    }

    /// Aggregates the collider pairs of one refreshed body into its edges.
    fn walk_pairs(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        me: NodeId,
    ) {
        let step = self.step;
        let mut colliders = std::mem::take(&mut self.scratch_colliders);
        if !colliders_of(graph, view, me, &mut colliders) {
            self.scratch_colliders = colliders;
            return;
        }
        self.counters.bodies += 1;
        for &ch in &colliders {
            for pair in view.narrow_phase.contact_pairs_with(ch) {
                self.counters.collider_pairs += 1;
                let oc = pairs::other_collider(pair, ch);
                let Some(other) = self.owner_of(graph, view, oc) else {
                    continue;
                };
                // Both sides refreshed: aggregate from the smaller index only.
                if other.index() < me.index()
                    && graph.node(other).is_some_and(|n| n.seen_step == step)
                {
                    continue;
                }
                self.process_pair(graph, view, screen, pair);
            }
        }
        self.scratch_colliders = colliders;
    }

    /// Aggregates every Rapier pair with a refreshed body into its edge, in one pass
    /// over the narrow phase's pair array.
    ///
    /// Rapier keeps its pairs in a vector (new pairs pushed, removed ones
    /// swap-removed), so a pair mostly stays in its slot from step to step. Each slot
    /// remembers the collider pair and edge it fed last time; when the colliders match,
    /// the edge is found without owner or hash lookups. A mismatch (a slot that changed
    /// hands) falls back to the lookups and refreshes the slot.
    fn scan_all_pairs(&mut self, graph: &mut ContactGraph, view: &WorldView, screen: &Screen) {
        let step = self.step;
        let mut slots = std::mem::take(&mut self.pair_slots);
        let mut len = 0;
        for (i, pair) in view.narrow_phase.contact_pairs().enumerate() {
            len = i + 1;
            self.counters.collider_pairs += 1;
            let cached = slots.get(i).filter(|s| {
                s.c1 == pair.collider1 && s.c2 == pair.collider2 && graph.edge(s.edge).is_some()
            });
            let (eid, flip) = match cached {
                Some(s) => (s.edge, s.flip),
                None => {
                    let Some((eid, flip)) = self.edge_of_pair(graph, view, screen, pair) else {
                        continue;
                    };
                    let slot = PairSlot {
                        c1: pair.collider1,
                        c2: pair.collider2,
                        edge: eid,
                        flip,
                    };
                    if i < slots.len() {
                        slots[i] = slot;
                    } else {
                        slots.push(slot);
                    }
                    (eid, flip)
                }
            };
            let Some(e) = graph.edge(eid) else { continue };
            let (a, b) = (e.a, e.b);
            let refreshed = |n| graph.node(n).is_some_and(|n| n.seen_step == step);
            if (refreshed(a) || refreshed(b)) && screen.admits(graph, a, b) {
                self.feed_edge(graph, view, eid, pair, flip);
            }
        }
        slots.truncate(len);
        self.pair_slots = slots;
    }

    /// The edge of a collider pair and whether `collider1` belongs to its B node;
    /// `None` if the pair makes no edge (sensor, same body, excluded by Table 2).
    fn edge_of_pair(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        pair: &ContactPair,
    ) -> Option<(EdgeId, bool)> {
        let n1 = self.owner_of(graph, view, pair.collider1)?;
        let n2 = self.owner_of(graph, view, pair.collider2)?;
        // Screened pairs (passive end, rule) make no edge (Fig. 4).
        if n1 == n2 || !screen.admits(graph, n1, n2) {
            return None;
        }
        let eid = pairs::physical_edge_for(graph, n1, n2, self.step)?;
        Some((eid, graph.edge(eid)?.b == n1))
    }

    /// Adds one collider pair to the edge of its two owners (creating the edge).
    fn process_pair(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        pair: &ContactPair,
    ) {
        if let Some((eid, flip)) = self.edge_of_pair(graph, view, screen, pair) {
            self.feed_edge(graph, view, eid, pair, flip);
        }
    }

    /// Adds a collider pair to an edge, shifting the edge's state to `e_old` on the
    /// first pair of the step. `flip`: Rapier's normal points from `collider1` to
    /// `collider2`, the edge's from A to B; flip when `collider1` belongs to B.
    fn feed_edge(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        eid: EdgeId,
        pair: &ContactPair,
        flip: bool,
    ) {
        let step = self.step;
        let details = !self.skip_details;
        let Some(e) = graph.edge(eid) else { return };
        if e.walk_stamp != step {
            let (pa, pb) = if details {
                (pose_of(graph, view, e.a), pose_of(graph, view, e.b))
            } else {
                (None, None)
            };
            let Some(e) = graph.edge_mut(eid) else { return };
            pairs::begin_edge_update(&mut e.cache, pa.as_ref(), pb.as_ref(), details);
            e.walk_stamp = step;
            e.updated_step = step;
            self.touched.push(eid);
            self.counters.edges += 1;
        }
        if let Some(e) = graph.edge_mut(eid) {
            pairs::accumulate_pair(&mut e.cache, pair, flip, details);
        }
    }

    /// An edge of a refreshed body that no collider pair reached this step: it has
    /// vanished (mark it), or vanished earlier (remove it if obsolete).
    fn retire(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        eid: EdgeId,
    ) {
        let step = self.step;
        let Some(e) = graph.edge_mut(eid) else { return };
        if e.walk_stamp == step {
            return;
        }
        e.walk_stamp = step;
        let was_proximate = e.cache.proximity;
        let was_touching = e.cache.touching;
        e.cache.begin_update(!self.skip_details);
        e.updated_step = step;
        let (a, b, kind) = (e.a, e.b, e.kind);
        let passive = |n| graph.node(n).is_some_and(|n| n.passive);
        // Geometric edges live only while the body is inside the trigger, and a passive
        // body has no edges: both go as soon as their end is reported.
        if kind == EdgeKind::Geometric || passive(a) || passive(b) {
            if let Some(e) = graph.remove_edge(eid) {
                if was_proximate {
                    self.removed_edges.push(e);
                }
            }
            if was_touching {
                groups.disturb(graph, a);
                groups.disturb(graph, b);
            }
            return;
        }
        if was_proximate {
            // Vanished now: report, test for obsolescence from the next update on.
            self.touched.push(eid);
            if was_touching {
                groups.disturb(graph, a);
                groups.disturb(graph, b);
            }
            return;
        }
        // The obsolete test recomputes two AABBs; a lingering edge is tested every
        // `OBSOLETE_EVERY` steps (staggered by slot), which delays removal by at most
        // that many steps and keeps a dense pile's many near-miss edges cheap.
        if (step + eid.index() as u64) % OBSOLETE_EVERY != 0 {
            return;
        }
        let sa = graph.node(a).map(|n| n.source);
        let sb = graph.node(b).map(|n| n.source);
        if let (Some(sa), Some(sb)) = (sa, sb) {
            if obsolete::is_obsolete(view, sa, sb) {
                graph.remove_edge(eid);
            }
        }
    }

    /// Reads the intersection pairs of one trigger (its sensor collider) into
    /// geometric edges, and marks the trigger as read this step.
    fn walk_trigger(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        t: NodeId,
    ) {
        let step = self.step;
        let Some(node) = graph.node_mut(t) else {
            return;
        };
        let NodeSource::Sensor(sensor) = node.source else {
            return;
        };
        if node.seen_step == step {
            return;
        }
        node.seen_step = step;
        self.triggers.push(t);
        if let Some(c) = view.colliders.get(sensor) {
            self.trigger_states.insert(t, TriggerState::of(c));
        }
        for (c1, c2, intersecting) in view.narrow_phase.intersection_pairs_with(sensor) {
            let oc = if c1 == sensor { c2 } else { c1 };
            if view.colliders.get(oc).is_none_or(|c| c.is_sensor()) {
                continue; // trigger–trigger pairs are ignored (Table 2)
            }
            self.counters.collider_pairs += 1;
            if intersecting {
                self.feed_trigger(graph, view, screen, t, oc);
            }
        }
    }

    /// Reads again the triggers not read this step whose sensor collider changed since
    /// their last read (see [`TriggerState`]), and forgets removed triggers.
    /// O(triggers).
    fn read_changed_triggers(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
    ) {
        if self.trigger_states.is_empty() {
            return;
        }
        let step = self.step;
        let mut stale = Vec::new();
        let mut changed = Vec::new();
        for (&t, state) in &self.trigger_states {
            let Some(node) = graph.node(t) else {
                stale.push(t);
                continue;
            };
            let NodeSource::Sensor(c) = node.source else {
                stale.push(t);
                continue;
            };
            if node.seen_step == step {
                continue;
            }
            // A removed sensor's node goes with the node upkeep.
            if view
                .colliders
                .get(c)
                .is_some_and(|c| TriggerState::of(c) != *state)
            {
                changed.push(t);
            }
        }
        for t in stale {
            self.trigger_states.remove(&t);
        }
        for t in changed {
            self.walk_trigger(graph, view, screen, t);
        }
    }

    /// Reads the intersection pairs of a body's (or static collider's) non-sensor
    /// colliders with triggers not read this step.
    fn walk_body_sensors(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        me: NodeId,
    ) {
        let step = self.step;
        let mut colliders = std::mem::take(&mut self.scratch_colliders);
        if !colliders_of(graph, view, me, &mut colliders) {
            self.scratch_colliders = colliders;
            return;
        }
        for &ch in &colliders {
            if view.colliders.get(ch).is_none_or(|c| c.is_sensor()) {
                continue;
            }
            for (c1, c2, intersecting) in view.narrow_phase.intersection_pairs_with(ch) {
                let sensor = if c1 == ch { c2 } else { c1 };
                let known = self.created.len();
                let Some(t) = nodes::ensure_trigger_node(graph, view, sensor, &mut self.created)
                else {
                    continue;
                };
                if self.created.len() != known {
                    // A trigger first seen here: read all of it from its side now.
                    self.walk_trigger(graph, view, screen, t);
                }
                if graph.node(t).is_some_and(|n| n.seen_step == step) {
                    continue; // read from the trigger's side
                }
                self.counters.collider_pairs += 1;
                if intersecting {
                    self.feed_trigger(graph, view, screen, t, ch);
                }
            }
        }
        self.scratch_colliders = colliders;
    }

    /// Adds one intersecting sensor–collider pair to the geometric edge of the trigger
    /// and the collider's owner.
    fn feed_trigger(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        t: NodeId,
        body_collider: ColliderHandle,
    ) {
        let step = self.step;
        let Some(b) = self.owner_of(graph, view, body_collider) else {
            return;
        };
        if !screen.admits(graph, t, b) {
            return;
        }
        let Some(eid) = graph.ensure_edge(t, b, EdgeKind::Geometric, step) else {
            return;
        };
        let Some(e) = graph.edge_mut(eid) else { return };
        if e.kind != EdgeKind::Geometric {
            return;
        }
        if e.walk_stamp != step {
            e.cache.begin_update(false);
            e.walk_stamp = step;
            e.updated_step = step;
            self.touched.push(eid);
            self.counters.edges += 1;
        }
        e.cache.proximity = true;
        e.cache.collider_pairs += 1;
    }
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
    /// Whether an overlap of `a` and `b` is treated: no passive end, no rule against it.
    #[inline]
    pub(crate) fn admits(&self, graph: &ContactGraph, a: NodeId, b: NodeId) -> bool {
        let passive = |n| graph.node(n).is_none_or(|n| n.passive);
        !passive(a) && !passive(b) && !self.rules.ignores(a, b)
    }
}

/// The next `n` slots (at most `span`) after a round-robin cursor, advancing it by as
/// many.
fn round_robin(cursor: &mut u32, span: u32, n: usize) -> impl Iterator<Item = u32> {
    let count = if span == 0 {
        0
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
