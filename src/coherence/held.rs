//! Held bodies in the analysis: the speed-ups' fixations and releases applied at the
//! pre-step, seen as sleep and wake, with the held bodies' contacts with what stands
//! still kept frozen (`graph/frozen.rs`) and their details read while Rapier still
//! has them.

use rapier3d::prelude::RigidBodyHandle;

use super::details::read_details;
use super::Coherence;
use crate::graph::{ContactGraph, EdgeKind, NodeId};
use crate::WorldView;

impl Coherence {
    /// Marks the bodies the pre-step held (`false`) or gave back (`true`) before the
    /// update reads the step: a held body's contacts with what stands still are
    /// frozen from now on; a body given back has its touching pairs counted again
    /// under touching tracking (Rapier pairs it anew in this step and sends `Started`
    /// for contacts the graph kept). O(changes).
    pub(crate) fn mark_held(
        &mut self,
        graph: &mut ContactGraph,
        changes: &[(RigidBodyHandle, bool)],
    ) {
        for &(h, released) in changes {
            let Some(id) = graph.node_of_body(h) else {
                continue;
            };
            graph.set_held(id, !released);
            if released {
                // Read again in this step: its kind (dynamic again, or what the user
                // gave it), and under touching tracking its touching pairs.
                self.stale.push(id);
                self.recheck.push(id);
            }
        }
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
