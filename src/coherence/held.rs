//! Held bodies in the analysis: the speed-ups' fixations and releases applied since
//! the last analysis, seen as sleep and wake, with the held bodies' contacts with
//! what stands still kept frozen (`graph/frozen.rs`) and their details read while
//! Rapier still has them.

use rapier3d::prelude::RigidBodyHandle;

use super::details::read_details;
use super::Coherence;
use crate::graph::{ContactGraph, EdgeId, EdgeKind, NodeId};
use crate::WorldView;

impl Coherence {
    /// Marks the bodies held (`false`) or given back (`true`) since the last analysis,
    /// before the update reads the step: a held body's contacts with what stands still
    /// are frozen from now on. A body given back is refreshed in this step; its frozen
    /// edges are thawed: Rapier pairs it anew in this step and sends `Started` for
    /// each contact that still touches, so under touching tracking those edges are
    /// counted from this step's events alone (one that gets none has ended), and under
    /// proximity tracking its pairs are read again. O(changes + their edges).
    pub(crate) fn mark_held(
        &mut self,
        graph: &mut ContactGraph,
        changes: &[(RigidBodyHandle, bool)],
    ) {
        for &(h, released) in changes {
            let Some(id) = graph.node_of_body(h) else {
                continue;
            };
            if released {
                // Frozen while the node is still held: read before it is given back.
                if let Some(node) = graph.node(id) {
                    let frozen = node
                        .edges
                        .iter()
                        .copied()
                        .filter(|&e| graph.edge(e).is_some_and(|e| graph.is_frozen(e)));
                    self.thawed.extend(frozen);
                }
                self.released_now.push(id);
                self.recheck.push(id);
            }
            graph.set_held(id, !released);
        }
    }

    /// Thaws the edges of the bodies given back (touching tracking): each starts its
    /// update with no touching collider pair, to be counted by this step's `Started`
    /// events; the edges are returned to be settled with the events' changes.
    /// O(thawed edges).
    pub(super) fn thaw_edges(&mut self, graph: &mut ContactGraph) -> Vec<EdgeId> {
        let mut changed = Vec::new();
        let mut thawed = std::mem::take(&mut self.thawed);
        // An edge between two bodies given back is listed twice.
        thawed.sort_unstable();
        thawed.dedup();
        for e in thawed {
            self.begin_touch_update(graph, e, &mut changed);
            if let Some(edge) = graph.edge_mut(e) {
                edge.cache.collider_pairs = 0;
            }
        }
        self.released_now.clear();
        changed
    }

    /// The bodies given back, read again in full (proximity tracking). O(their
    /// count).
    pub(super) fn restale_released(&mut self) {
        self.thawed.clear();
        let released = std::mem::take(&mut self.released_now);
        self.stale.extend(released);
    }

    /// Reports the speed-ups' fixations (`false`) and releases (`true`) applied before
    /// this step as sleep and wake of the body: a held body is out of the simulation
    /// like a sleeping one. A release is reported by the refresh that sees the body
    /// dynamic again (its last reported state is "asleep"), so only fixations are
    /// pushed here. O(changes).
    pub(crate) fn note_hold_changes(
        &mut self,
        graph: &mut ContactGraph,
        changes: &[(RigidBodyHandle, bool)],
    ) {
        for &(h, released) in changes {
            let Some(id) = graph.node_of_body(h) else {
                continue;
            };
            let Some(n) = graph.node_mut(id) else {
                continue;
            };
            if released || n.passive {
                continue;
            }
            if n.reported_awake == Some(true) {
                n.reported_awake = Some(false);
                self.sleep_changes.push((id, false));
            }
        }
    }
}

/// Reads from Rapier the details of the touching contacts of the bodies about to be
/// held (distance, depth, impulses, normal, push) into their edges' caches: Rapier
/// drops the pairs that freeze, and the queries answer from the cache while the body
/// is held. O(their touching edges × the contact pairs of the node with fewer
/// colliders).
pub(crate) fn keep_frozen_details(graph: &mut ContactGraph, view: &WorldView, nodes: &[NodeId]) {
    for &n in nodes {
        let Some(node) = graph.node(n) else { continue };
        let edges: Vec<_> = node
            .edges
            .iter()
            .copied()
            .filter(|&e| {
                graph
                    .edge(e)
                    .is_some_and(|e| e.kind == EdgeKind::Physical && e.cache.touching)
            })
            .collect();
        for eid in edges {
            let Some((a, b)) = graph.edge(eid).map(|e| (e.a, e.b)) else {
                continue;
            };
            let Some(read) = read_details(graph, view, a, b) else {
                continue;
            };
            if let Some(e) = graph.edge_mut(eid) {
                let c = &mut e.cache;
                c.min_distance = read.min_distance;
                c.max_penetration = read.max_penetration;
                c.normal_impulse = read.normal_impulse;
                c.normal = read.normal;
                c.push = read.push;
            }
        }
    }
}
