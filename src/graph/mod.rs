//! The contact graph (paper §2): typed nodes, typed edges keyed by the sorted node
//! pair, adjacency both ways, and the per-edge cache.
//!
//! # Design
//! Chosen: two slot arenas with free lists (nodes, edges), a hash map from
//! [`PairKey`] to edge for the O(1) "edge of two nodes" query the paper asks for, and
//! an incident-edge list per node. Iteration always goes through the arenas in slot
//! order, so it is deterministic and independent of hashing.
//!
//! Rejected: `petgraph::StableGraph` as the store. It has the right shape (stable
//! indices, both-way adjacency) but no generations, so a user's stale id would
//! silently name a recycled node, and finding the edge of two nodes is O(degree)
//! without a side map anyway. [`ContactGraph::to_petgraph`] exports a snapshot for
//! users who want petgraph's algorithms; the tests use it to check the groups against
//! petgraph's connected components.
//!
//! Rejected: one node per collider. Rapier pairs colliders, but the paper's entities
//! are bodies; an edge aggregates all collider pairs of two bodies, which is what
//! group traversal and "what touches X" need.
//!
//! The graph itself is passive storage. [`crate::ContactLayer`] keeps it in step with
//! a Rapier world; users read it. Reads are in this file, the crate's writes in
//! `edit.rs`.

mod edge;
mod edit;
mod frozen;
pub(crate) mod mirror;
mod node;
pub(crate) mod validate;

use std::collections::HashMap;

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

pub(crate) use crate::util::arena::Arena;
pub use crate::util::id::{EdgeId, NodeId, PairBuildHasher, PairHasher, PairKey};
pub use edge::{ContactCache, Edge, EdgeKind, Transition};
pub(crate) use edge::{LeftEdge, NO_SLOT};
pub(crate) use node::Storage;
pub use node::{Category, ContainerSource, Node, NodeKind, NodeSource};

use crate::{Error, Result};

/// The contact graph of a scene.
///
/// Costs: node and edge lookups by id, by body handle and by node pair are O(1);
/// iterating a node's neighbours is O(degree); iterating all nodes or edges is
/// O(slots).
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactGraph {
    pub(crate) nodes: Arena<Node>,
    pub(crate) edges: Arena<Edge>,
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    pairs: HashMap<PairKey, EdgeId, PairBuildHasher>,
    /// Body handle index → node (checked against the node's source for generation).
    body_nodes: Vec<Option<NodeId>>,
    /// Parentless collider index → node.
    collider_nodes: Vec<Option<NodeId>>,
    kind_counts: [usize; 9],
    /// The step nodes created now are born in (set by the layer).
    pub(crate) clock: u64,
    /// Edges dropped by kind changes, waiting to be reported by the layer.
    pub(crate) dropped: Vec<Edge>,
    /// Nodes whose kind changed, waiting for their groups to be rebuilt.
    pub(crate) kind_changed: Vec<NodeId>,
    /// Nodes whose Rapier slot was taken by a newer object (so their object is gone),
    /// waiting to be removed and reported by the layer.
    pub(crate) evicted: Vec<NodeId>,
    /// Joining edges removed since the groups last looked (they take them out of
    /// their groups in O(1) each). Per-step scratch.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) left: Vec<LeftEdge>,
}

pub(super) fn kind_slot(kind: NodeKind) -> usize {
    NodeKind::ALL.iter().position(|k| *k == kind).unwrap_or(0)
}

pub(super) fn set_slot(map: &mut Vec<Option<NodeId>>, index: u32, value: Option<NodeId>) {
    let i = index as usize;
    if map.len() <= i {
        map.resize(i + 1, None);
    }
    map[i] = value;
}

impl ContactGraph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    // ── Nodes ──────────────────────────────────────────────────────────

    /// The node `id`, or `None` if it was removed. O(1).
    #[inline]
    pub fn node(&self, id: NodeId) -> Option<&Node> {
        self.nodes.get(id.index(), id.generation())
    }

    /// The node `id`, or [`Error::StaleNode`]. O(1).
    #[inline]
    pub fn try_node(&self, id: NodeId) -> Result<&Node> {
        self.node(id).ok_or(Error::StaleNode(id))
    }

    #[inline]
    pub(crate) fn node_mut(&mut self, id: NodeId) -> Option<&mut Node> {
        self.nodes.get_mut(id.index(), id.generation())
    }

    /// Whether `id` names a live node. O(1).
    #[inline]
    pub fn contains_node(&self, id: NodeId) -> bool {
        self.node(id).is_some()
    }

    /// The id of the live node in slot `index`, if any. O(1).
    #[inline]
    pub fn node_id_at(&self, index: u32) -> Option<NodeId> {
        self.nodes
            .get_by_index(index)
            .map(|(g, _)| NodeId::from_raw_parts(index, g))
    }

    /// The node of a Rapier body. O(1).
    #[inline]
    pub fn node_of_body(&self, body: RigidBodyHandle) -> Option<NodeId> {
        let (i, _) = body.into_raw_parts();
        let id = (*self.body_nodes.get(i as usize)?)?;
        match self.node(id)?.source {
            NodeSource::Body(h) if h == body => Some(id),
            _ => None,
        }
    }

    /// The node of a Rapier body, or [`Error::UnknownBody`]. O(1).
    #[inline]
    pub fn try_node_of_body(&self, body: RigidBodyHandle) -> Result<NodeId> {
        self.node_of_body(body).ok_or(Error::UnknownBody(body))
    }

    /// The node of a parentless collider (static geometry), or of the parent body of a
    /// collider attached to one (needs the collider set to find the parent; see
    /// [`crate::ContactLayer::node_of_collider`]). O(1).
    #[inline]
    pub fn node_of_static_collider(&self, collider: ColliderHandle) -> Option<NodeId> {
        let (i, _) = collider.into_raw_parts();
        let id = (*self.collider_nodes.get(i as usize)?)?;
        match self.node(id)?.source {
            NodeSource::StaticCollider(h) if h == collider => Some(id),
            _ => None,
        }
    }

    /// One past the highest Rapier collider slot the graph has seen.
    pub(crate) fn collider_slot_span(&self) -> usize {
        self.collider_nodes.len()
    }

    /// One past the highest Rapier body slot the graph has seen.
    pub(crate) fn body_slot_span(&self) -> usize {
        self.body_nodes.len()
    }

    /// The trigger node of a sensor collider. O(1).
    #[inline]
    pub fn node_of_sensor(&self, collider: ColliderHandle) -> Option<NodeId> {
        let (i, _) = collider.into_raw_parts();
        let id = (*self.collider_nodes.get(i as usize)?)?;
        match self.node(id)?.source {
            NodeSource::Sensor(h) if h == collider => Some(id),
            _ => None,
        }
    }

    /// The Rapier body of a node, if it is a body node. O(1).
    #[inline]
    pub fn body_of(&self, node: NodeId) -> Option<RigidBodyHandle> {
        self.node(node)?.body()
    }

    /// The Rapier body of a node, or an error naming what is wrong. O(1).
    pub fn try_body_of(&self, node: NodeId) -> Result<RigidBodyHandle> {
        self.try_node(node)?.body().ok_or(Error::WrongKind {
            node,
            expected: "a body node",
        })
    }

    /// Clears every node's and edge's traversal stamp, so that a traversal numbering
    /// that ran out of range can start again. O(nodes + edges).
    pub(crate) fn clear_stamps(&mut self) {
        for n in self.nodes.values_mut() {
            n.visit_stamp = 0;
        }
        for e in self.edges.values_mut() {
            e.colour_stamp = 0;
        }
    }

    /// All live nodes in slot order. O(slots).
    pub fn nodes(&self) -> impl Iterator<Item = (NodeId, &Node)> + '_ {
        self.nodes
            .iter()
            .map(|(i, g, n)| (NodeId::from_raw_parts(i, g), n))
    }

    /// The nodes of one kind, in slot order. O(slots).
    pub fn nodes_of_kind(&self, kind: NodeKind) -> impl Iterator<Item = (NodeId, &Node)> + '_ {
        self.nodes().filter(move |(_, n)| n.kind == kind)
    }

    /// The number of live nodes. O(1).
    #[inline]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The number of live nodes of a kind. O(1).
    #[inline]
    pub fn count_of_kind(&self, kind: NodeKind) -> usize {
        self.kind_counts[kind_slot(kind)]
    }

    // ── Edges ──────────────────────────────────────────────────────────

    /// The edge `id`, or `None` if it was removed. O(1).
    #[inline]
    pub fn edge(&self, id: EdgeId) -> Option<&Edge> {
        self.edges.get(id.index(), id.generation())
    }

    /// The edge `id`, or [`Error::StaleEdge`]. O(1).
    #[inline]
    pub fn try_edge(&self, id: EdgeId) -> Result<&Edge> {
        self.edge(id).ok_or(Error::StaleEdge(id))
    }

    #[inline]
    pub(crate) fn edge_mut(&mut self, id: EdgeId) -> Option<&mut Edge> {
        self.edges.get_mut(id.index(), id.generation())
    }

    /// The edge between two nodes, in either order. O(1) expected.
    #[inline]
    pub fn edge_between(&self, a: NodeId, b: NodeId) -> Option<EdgeId> {
        let id = *self.pairs.get(&PairKey::of(a, b))?;
        let e = self.edge(id)?;
        // Guard against stale node ids whose slots were reused.
        ((e.a == a && e.b == b) || (e.a == b && e.b == a)).then_some(id)
    }

    /// The edge between two nodes, or the error for whichever node is stale; `Ok(None)`
    /// when both live and no edge joins them. O(1) expected.
    pub fn try_edge_between(&self, a: NodeId, b: NodeId) -> Result<Option<EdgeId>> {
        self.try_node(a)?;
        self.try_node(b)?;
        Ok(self.edge_between(a, b))
    }

    /// The edge between two Rapier bodies. O(1) expected.
    pub fn edge_of_bodies(&self, b1: RigidBodyHandle, b2: RigidBodyHandle) -> Option<&Edge> {
        let id = self.edge_between(self.node_of_body(b1)?, self.node_of_body(b2)?)?;
        self.edge(id)
    }

    /// The edge with a given pair key. O(1) expected.
    #[inline]
    pub fn edge_by_key(&self, key: PairKey) -> Option<EdgeId> {
        self.pairs.get(&key).copied()
    }

    /// All live edges in slot order. O(slots).
    pub fn edges(&self) -> impl Iterator<Item = (EdgeId, &Edge)> + '_ {
        self.edges
            .iter()
            .map(|(i, g, e)| (EdgeId::from_raw_parts(i, g), e))
    }

    /// The number of live edges. O(1).
    #[inline]
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// The `k`-th edge of node `n` (none past its last, or for a stale id): for loops
    /// that change edges' fields while they walk a node's list by index. O(1).
    pub(crate) fn nth_edge(&self, n: NodeId, k: usize) -> Option<EdgeId> {
        self.node(n).and_then(|node| node.edges.get(k).copied())
    }

    /// The neighbours of `n` with the joining edge, in edge insertion order.
    /// Empty for a stale id. O(degree).
    pub fn neighbors(&self, n: NodeId) -> impl Iterator<Item = (NodeId, EdgeId, &Edge)> + '_ {
        self.node(n)
            .map(|node| node.edges.as_slice())
            .unwrap_or(&[])
            .iter()
            .filter_map(move |&eid| {
                let e = self.edge(eid)?;
                Some((e.other(n)?, eid, e))
            })
    }

    /// The nodes touching `n` now ("what touches X"). Empty for a stale id.
    /// O(degree).
    pub fn touching(&self, n: NodeId) -> impl Iterator<Item = NodeId> + '_ {
        self.neighbors(n)
            .filter(|(_, _, e)| e.kind == EdgeKind::Physical && e.cache.touching)
            .map(|(m, _, _)| m)
    }

    /// Whether `n` is supported: it touches some node through a contact whose normal,
    /// as seen pushing on `n`, points against gravity (more than `min_cos` of the unit
    /// push along `-gravity`; 0.0 accepts any upward component). O(degree).
    ///
    /// A zero gravity supports nothing. A stale id, a non-finite gravity or a NaN
    /// `min_cos` is an error.
    ///
    /// The normals are the edges' kept contact details, which the layer keeps under
    /// proximity tracking with the details on (`Coherence::details_kept`); under
    /// touching tracking (the layer's default) the edges hold none and nothing is
    /// supported here: `ContactLayer::supports_of_body` reads the normals from Rapier.
    pub fn try_is_supported(&self, n: NodeId, gravity: Vector, min_cos: Real) -> Result<bool> {
        self.try_node(n)?;
        if !gravity.is_finite() {
            return Err(Error::NonFinite("gravity"));
        }
        if min_cos.is_nan() {
            return Err(Error::NonFinite("min_cos"));
        }
        // Scale before normalising: `length()` of a huge or tiny finite vector
        // overflows or underflows in f32.
        let scale = gravity.abs().max_element();
        if scale == 0.0 {
            return Ok(false);
        }
        let up = -(gravity / scale).normalize();
        Ok(self.supports_of(n, up, min_cos).next().is_some())
    }

    /// The nodes supporting `n` against gravity (see [`Self::try_is_supported`]);
    /// `up` must be a unit vector opposite to gravity. Empty for a stale id.
    /// O(degree).
    pub fn supports_of(
        &self,
        n: NodeId,
        up: Vector,
        min_cos: Real,
    ) -> impl Iterator<Item = NodeId> + '_ {
        self.neighbors(n).filter_map(move |(m, _, e)| {
            if e.kind != EdgeKind::Physical || !e.cache.touching {
                return None;
            }
            // The normal points from A to B: it pushes B along +normal, A along -normal.
            let push = if e.b == n {
                e.cache.normal
            } else {
                -e.cache.normal
            };
            (push.dot(up) > min_cos).then_some(m)
        })
    }

    /// [`Self::supports_of`], judged by the resultant of the contact's normal impulses
    /// ([`crate::graph::ContactCache::push`]) where there is one, and also counting
    /// physical edges that are not touching but whose closest contact point is at most
    /// `gap` apart (a body resting a hair above
    /// its support, within Rapier's contact prediction distance, is held by it: the
    /// solver keeps such speculative contacts). O(degree).
    pub fn resting_supports_of(
        &self,
        n: NodeId,
        up: Vector,
        min_cos: Real,
        gap: Real,
    ) -> impl Iterator<Item = NodeId> + '_ {
        self.neighbors(n).filter_map(move |(m, _, e)| {
            let held = e.kind == EdgeKind::Physical && e.cache.holds_up(e.b == n, up, min_cos, gap);
            held.then_some(m)
        })
    }

    /// A petgraph snapshot of the graph (feature `petgraph`): node weights are the
    /// [`NodeId`]s, edge weights the [`EdgeId`]s. O(nodes + edges).
    ///
    /// # Example
    /// ```
    /// use rapier_contact_graph::ContactGraph;
    /// let g = ContactGraph::new().to_petgraph();
    /// assert_eq!(g.node_count(), 0);
    /// ```
    #[cfg(feature = "petgraph")]
    pub fn to_petgraph(&self) -> petgraph::stable_graph::StableUnGraph<NodeId, EdgeId> {
        let mut g = petgraph::stable_graph::StableUnGraph::default();
        let mut map = HashMap::<NodeId, _, PairBuildHasher>::default();
        for (id, _) in self.nodes() {
            map.insert(id, g.add_node(id));
        }
        for (eid, e) in self.edges() {
            g.add_edge(map[&e.a], map[&e.b], eid);
        }
        g
    }
}

#[cfg(test)]
mod tests;
