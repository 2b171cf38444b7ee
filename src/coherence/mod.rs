//! Spatial-Temporal Coherence analysis (paper §3, §5): the post-step pass that keeps
//! the contact graph equal to Rapier's state and marks what changed.
//!
//! # Where the paper's phases land in Rapier
//! The paper runs its analysis between broad phase, narrow phase and contact
//! determination. Rapier's step does all three internally, and already has the
//! paper's "relative transform unchanged → skip the narrow phase" test (contact
//! recycling). So this pass runs *after* Rapier's step, reading the narrow phase:
//! 1. node upkeep ([`nodes`]): bodies awake now or at the last update are refreshed;
//!    a full scan only when the body or collider count changed;
//! 2. edge insertion and marks ([`pairs`], Figs. 3 and 5): each collider pair of a
//!    refreshed body is aggregated into the physical edge of its two bodies, whose
//!    proximity and touching states are shifted to `e_old` first;
//! 3. vanishing and obsolete removal ([`obsolete`], §3.1): an edge of a refreshed body
//!    that no collider pair reached has vanished; one that vanished at an earlier
//!    update is removed once its AABBs are far apart.
//!
//! The cost is proportional to the refreshed bodies' pairs, never to all pairs: the
//! pairs of sleeping bodies are frozen in Rapier and stay exact in the graph.
//!
//! # What a step exposes
//! [`Coherence::touched_edges`] lists the edges refreshed in the step (their marks
//! are valid for the step), [`Coherence::removed_edges`] the edges removed with a
//! node (each shows a final `Vanished` mark), [`Coherence::removed_nodes`] the nodes
//! whose object left the world.

pub(crate) mod nodes;
pub(crate) mod obsolete;
pub(crate) mod pairs;

pub use obsolete::aabbs_obsolete;
pub use pairs::WalkCounters;

use rapier3d::prelude::RigidBodyHandle;

use crate::graph::{ContactGraph, Edge, EdgeId, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::WorldView;

/// A node removed because its Rapier object left the world.
#[derive(Clone, Debug, PartialEq)]
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
}

impl Coherence {
    /// The index of the last analysed step (0 before the first).
    pub fn step(&self) -> u64 {
        self.step
    }
    /// Edges refreshed in the last step: their marks are valid. Sorted by slot.
    pub fn touched_edges(&self) -> &[EdgeId] {
        &self.touched
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
    /// Counters of the last pair walk.
    pub fn counters(&self) -> WalkCounters {
        self.counters
    }
    /// Asks for a full scan of bodies and colliders at the next update (after changing
    /// a sleeping or fixed body in place, e.g. its type, which Rapier does not report).
    pub fn request_full_sync(&mut self) {
        self.force_full_sync = true;
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
            e.cache.begin_update();
            e.updated_step = step;
            self.removed_edges.push(e);
        }
        self.removed_nodes.push(record);
    }

    /// Runs the analysis of one step. `step` must grow by one per call.
    pub(crate) fn update(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
    ) {
        self.step += 1;
        let step = self.step;
        self.touched.clear();
        self.removed_edges.clear();
        self.removed_nodes.clear();
        self.created.clear();
        self.counters = WalkCounters::default();

        // 1. Node upkeep.
        let counts_changed = self.known_bodies != Some(view.bodies.len())
            || self.known_colliders != view.colliders.len();
        if counts_changed || self.force_full_sync {
            self.force_full_sync = false;
            let gone = nodes::full_sync(graph, view, &mut self.created);
            for id in gone {
                self.remove_node(graph, groups, id);
            }
            self.known_bodies = Some(view.bodies.len());
            self.known_colliders = view.colliders.len();
        }
        self.walk.clear();
        for h in view.islands.active_bodies() {
            let Some(id) = nodes::ensure_body_node(graph, view, h, &mut self.created) else {
                continue;
            };
            self.mark_refreshed(graph, view, id, h, true);
        }
        let prev = std::mem::take(&mut self.awake_prev);
        for &id in &prev {
            let Some(node) = graph.node(id) else { continue };
            if node.seen_step == step {
                continue;
            }
            let NodeSource::Body(h) = node.source else {
                continue;
            };
            if view.bodies.contains(h) {
                // Fell asleep, turned fixed or was disabled since the last update.
                let _ = nodes::ensure_body_node(graph, view, h, &mut self.created);
                self.mark_refreshed(graph, view, id, h, false);
            } else {
                self.remove_node(graph, groups, id);
            }
        }
        self.awake_prev = prev;
        self.awake_prev.clear();
        for &id in &self.walk {
            if graph.node(id).is_some_and(|n| n.awake) {
                self.awake_prev.push(id);
            }
        }
        // Nodes created this step (e.g. a new fixed body) have no pairs walked from
        // them, but their pairs with awake bodies are walked from the other side.
        for i in 0..self.created.len() {
            let id = self.created[i];
            groups.disturb(graph, id);
        }

        // 2. Edge insertion and marks.
        let walk = std::mem::take(&mut self.walk);
        for &me in &walk {
            self.walk_pairs(graph, view, me);
            groups.disturb(graph, me);
        }

        // 3. Vanished edges and obsolete removal.
        for &me in &walk {
            self.dead.clear();
            let Some(node) = graph.node(me) else { continue };
            for &eid in &node.edges {
                let Some(e) = graph.edge(eid) else { continue };
                if e.kind == EdgeKind::Physical && e.walk_stamp != step {
                    self.dead.push(eid);
                }
            }
            for i in 0..self.dead.len() {
                let eid = self.dead[i];
                self.retire(graph, groups, view, eid);
            }
        }
        self.walk = walk;
        self.touched.sort_unstable();
        self.touched.dedup();
        self.touched.retain(|&e| graph.edge(e).is_some());
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
        let finite = view.bodies.get(h).is_some_and(|rb| {
            rb.position().translation.is_finite() && rb.position().rotation.is_finite()
        });
        if let Some(n) = graph.node_mut(id) {
            if n.seen_step == step {
                return;
            }
            n.seen_step = step;
            n.awake = awake && !matches!(n.kind, NodeKind::Fixed);
            n.non_finite = !finite;
            self.walk.push(id);
        }
    }

    /// Aggregates the collider pairs of one refreshed body into its edges.
    fn walk_pairs(&mut self, graph: &mut ContactGraph, view: &WorldView, me: NodeId) {
        let step = self.step;
        let Some(NodeSource::Body(h)) = graph.node(me).map(|n| n.source) else {
            return;
        };
        let Some(rb) = view.bodies.get(h) else { return };
        self.counters.bodies += 1;
        for &ch in rb.colliders() {
            let Some(c) = view.colliders.get(ch) else {
                continue;
            };
            if c.is_sensor() {
                continue;
            }
            for pair in view.narrow_phase.contact_pairs_with(ch) {
                self.counters.collider_pairs += 1;
                let oc = pairs::other_collider(pair, ch);
                let Some(other) = nodes::ensure_collider_owner(graph, view, oc, &mut self.created)
                else {
                    continue;
                };
                if other == me {
                    continue;
                }
                // Both sides refreshed: aggregate from the smaller index only.
                if graph.node(other).is_some_and(|n| n.seen_step == step)
                    && other.index() < me.index()
                {
                    continue;
                }
                let Some(eid) = pairs::physical_edge_for(graph, me, other, step) else {
                    continue;
                };
                let (a, b) = match graph.edge(eid) {
                    Some(e) => (e.a, e.b),
                    None => continue,
                };
                let first_visit = graph.edge(eid).is_some_and(|e| e.walk_stamp != step);
                if first_visit {
                    let pa = pose_of(graph, view, a);
                    let pb = pose_of(graph, view, b);
                    let Some(e) = graph.edge_mut(eid) else {
                        continue;
                    };
                    pairs::begin_edge_update(&mut e.cache, pa.as_ref(), pb.as_ref());
                    e.walk_stamp = step;
                    e.updated_step = step;
                    self.touched.push(eid);
                    self.counters.edges += 1;
                }
                // Rapier's normal points from collider1 to collider2; flip if collider1
                // belongs to the edge's B node.
                let c1_owner_is_me = pair.collider1 == ch;
                let me_is_a = a == me;
                let flip = c1_owner_is_me != me_is_a;
                if let Some(e) = graph.edge_mut(eid) {
                    pairs::accumulate_pair(&mut e.cache, pair, flip);
                }
            }
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
        e.cache.begin_update();
        e.updated_step = step;
        let (a, b) = (e.a, e.b);
        if was_proximate {
            // Vanished now: report, test for obsolescence from the next update on.
            self.touched.push(eid);
            if was_touching {
                groups.disturb(graph, a);
                groups.disturb(graph, b);
            }
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
}

fn pose_of(graph: &ContactGraph, view: &WorldView, n: NodeId) -> Option<rapier3d::math::Pose> {
    match graph.node(n)?.source {
        NodeSource::Body(h) => view.bodies.get(h).map(|rb| *rb.position()),
        NodeSource::StaticCollider(h) => view.colliders.get(h).map(|c| *c.position()),
        NodeSource::Layer(_) => None,
    }
}
