//! The collider-owner cache (which node a collider belongs to, checked on use) and
//! the world's identity (where its storage is): the lookups of the analysis that
//! Rapier's lists do not answer in O(1).

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, NodeId, NodeSource};
use crate::WorldView;

use super::*;

impl Coherence {
    /// The node owning a collider, from the owner table (slow path: Rapier lookups,
    /// creating the node if it is missing). `None` for sensors.
    #[inline]
    pub(super) fn owner_of(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        collider: ColliderHandle,
    ) -> Option<NodeId> {
        let (i, gen) = collider.into_raw_parts();
        match self.owners.get(i as usize).copied() {
            Some(Owner::Node(g, n)) if g == gen => match graph.node(n) {
                // A body refreshed this step had its collider list checked: an entry
                // naming it is current. Other owners are checked against Rapier.
                Some(node)
                    if (node.seen_step == self.step
                        && matches!(node.source, NodeSource::Body(_)))
                        || nodes::owns(view, collider, node.source) =>
                {
                    return Some(n)
                }
                Some(_) => self.owner_moved(n),
                None => {}
            },
            Some(Owner::Nobody(g)) if g == gen => {
                if view
                    .colliders
                    .get(collider)
                    .is_none_or(|c| c.parent().is_none() && c.is_sensor())
                {
                    return None;
                }
            }
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

    /// A collider left `old` in place (found when its cached owner no longer owns it):
    /// `old` is read again at the next update. The new owner is read from the pairs,
    /// or found by its own collider list. O(1).
    pub(super) fn owner_moved(&mut self, old: NodeId) {
        if !self.stale.contains(&old) {
            self.stale.push(old);
        }
        // The pair-slot cache finds edges without owner lookups: it may name the
        // old owner's edge.
        self.pair_slots.clear();
    }

    /// A body's collider list changed since its last refresh (a collider moved to or
    /// from it, or swapped for another): the owners its colliders had in the cache
    /// and the body itself are read again, and the lookup caches are dropped (they are
    /// rebuilt on use). O(its colliders) plus the cost of rebuilding the caches, on
    /// such a change only.
    pub(super) fn colliders_moved(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        id: NodeId,
        h: RigidBodyHandle,
    ) {
        if let Some(rb) = view.bodies.get(h) {
            for &c in rb.colliders() {
                let (i, gen) = c.into_raw_parts();
                if let Some(Owner::Node(g, n)) = self.owners.get(i as usize).copied() {
                    if g == gen && n != id && graph.contains_node(n) {
                        self.owner_moved(n);
                    }
                }
            }
        }
        // `owner_moved` drops the pair-slot cache too.
        self.owner_moved(id);
        self.owners.clear();
    }

    /// Whether the world is the one of the last update, as far as an O(1) look tells:
    /// the addresses of the first stored body and collider. Rapier's sets keep them
    /// until they grow (which changes their counts, a full scan anyway) or their first
    /// slot is emptied, so a change means another world or a changed first slot; both
    /// are read in full. Moving a `PhysicsWorld` value does not move them.
    pub(super) fn same_world(&mut self, view: &WorldView) -> bool {
        let first_body = view
            .bodies
            .iter()
            .next()
            .map_or(0, |(_, b)| b as *const _ as usize);
        let first_collider = view
            .colliders
            .iter()
            .next()
            .map_or(0, |(_, c)| c as *const _ as usize);
        let mark = Some((first_body, first_collider));
        let same = self.world_mark.is_none() || *self.world_mark == mark;
        *self.world_mark = mark;
        same
    }
}
