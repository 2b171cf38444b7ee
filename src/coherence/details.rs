//! Contact details on demand: the closest distance, deepest penetration, contact
//! normal, solver contact count and normal impulses of two nodes' contact, read from
//! Rapier's narrow phase when a query asks, whatever the tracking.
//!
//! Proximity tracking with contact details on copies these into every edge's
//! [`ContactCache`] each step (what the speed-ups and the monitor read); touching
//! tracking copies nothing (the paper's §3 marks need none of it). A query that needs
//! a detail reads it here instead, at the cost of the pairs it reads: the same
//! accumulation as the per-step copy ([`super::pairs::accumulate_pair`]), so that both
//! give the same figures for the same world.

use rapier3d::prelude::ColliderHandle;

use crate::graph::{mirror as nodes, ContactCache, ContactGraph, NodeId};
use crate::WorldView;

/// The details of the contact between `a` and `b` as Rapier's narrow phase holds
/// them now, oriented like their edge (the normal points from the edge's *A*, the
/// node with the smaller slot, to *B*). `None` if Rapier has no contact pair between
/// their colliders, or a node is gone. O(the contact pairs of `a`'s colliders).
pub(crate) fn read_details(
    graph: &ContactGraph,
    view: &WorldView,
    a: NodeId,
    b: NodeId,
) -> Option<ContactCache> {
    let (first, second) = if a.index() <= b.index() {
        (a, b)
    } else {
        (b, a)
    };
    let second_source = graph.node(second)?.source();
    let mut mine: Vec<ColliderHandle> = Vec::new();
    if !super::colliders_of(graph, view, first, &mut mine) {
        return None;
    }
    let mut cache = ContactCache::default();
    cache.begin_update(true);
    let mut any = false;
    for &c in &mine {
        for pair in view.narrow_phase.contact_pairs_with(c) {
            let other = super::pairs::other_collider(pair, c);
            if !nodes::owns(view, other, second_source) {
                continue;
            }
            any = true;
            // Rapier's normal points from `collider1` to `collider2`: flip it when
            // `collider1` is the second node's.
            super::pairs::accumulate_pair(&mut cache, pair, pair.collider1 == other, true);
        }
    }
    any.then_some(cache)
}
