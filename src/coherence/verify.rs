//! The round-robin verification (see the module docs, "The round-robin
//! verification"): a few graph nodes and Rapier body and collider slots checked per
//! step, for the changes no Rapier list tells.

use crate::graph::{ContactGraph, NodeSource};
use crate::groups::Groups;
use crate::WorldView;

use super::*;

impl Coherence {
    /// Checks a few nodes and Rapier body and collider slots per step, round robin: a
    /// node whose object is gone is removed, a body whose type changed in place gets
    /// its kind, one disabled or enabled in place is refreshed, and a body without
    /// node gets one. It makes the graph consistent,
    /// within `slots / verify_budget()` steps, after changes the per-step upkeep cannot
    /// see (removing and inserting bodies between two steps, retyping a sleeping body),
    /// without a full scan. O([`Self::verify_budget`]): the budget follows the awake
    /// bodies, so that a sleeping or held scene pays almost nothing for it.
    pub(super) fn verify_some(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
    ) {
        let budget = self.verify_budget();
        let slots = graph.nodes.slot_count() as u32;
        for i in round_robin(&mut self.verify_cursor, slots, budget) {
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
                // A body disabled or enabled again in place while nothing refreshed it
                // (a sleeping or held body: Rapier tells nothing): read it again.
                if self.passive_changed_unseen(graph, view, id, h) {
                    self.recheck.push(id);
                }
            }
        }
        // Rapier's arenas may hold free slots beyond `len()`: cover the highest slot the
        // graph has seen too.
        let body_slots = view.bodies.len().max(graph.body_slot_span()) as u32 + budget as u32;
        for i in round_robin(&mut self.verify_body_cursor, body_slots, budget) {
            if let Some((_, h)) = view.bodies.get_unknown_gen(i) {
                if graph.node_of_body(h).is_none() {
                    nodes::ensure_body_node(graph, view, h, &mut self.created);
                }
            }
        }
        let collider_slots =
            view.colliders.len().max(graph.collider_slot_span()) as u32 + budget as u32;
        for i in round_robin(&mut self.verify_collider_cursor, collider_slots, budget) {
            if let Some((c, h)) = view.colliders.get_unknown_gen(i) {
                // A cached owner that no longer owns the collider (moved in place
                // while nothing that would notice was refreshed): read both again.
                let (_, gen) = h.into_raw_parts();
                if let Some(Owner::Node(g, n)) = self.owners.get(i as usize).copied() {
                    let owned = graph
                        .node(n)
                        .is_some_and(|node| nodes::owns(view, h, node.source));
                    if g == gen && !owned {
                        self.owners[i as usize] = Owner::Unknown;
                        if graph.contains_node(n) {
                            self.owner_moved(n);
                        }
                        if let Some(now) =
                            nodes::ensure_collider_owner(graph, view, h, &mut self.created)
                        {
                            self.owner_moved(now);
                        }
                    }
                }
                if c.is_sensor() {
                    nodes::ensure_trigger_node(graph, view, h, &mut self.created);
                } else if c.parent().is_none() {
                    nodes::ensure_collider_owner(graph, view, h, &mut self.created);
                }
            }
        }
    }

    /// Whether a body's enabled flag disagrees with its node's passive flag, the
    /// bodies the speed-ups disable for one step on their way out of Rapier's active
    /// set aside. O(log parking).
    fn passive_changed_unseen(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        id: crate::graph::NodeId,
        h: rapier3d::prelude::RigidBodyHandle,
    ) -> bool {
        let (Some(node), Some(rb)) = (graph.node(id), view.bodies.get(h)) else {
            return false;
        };
        node.passive != self.is_passive(rb.is_enabled(), h)
    }
}
