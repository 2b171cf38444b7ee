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

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::ColliderHandle;

use crate::graph::validate::edge_allowed;
use crate::graph::{mirror as nodes, ContactCache, ContactGraph, EdgeKind, NodeId};
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

/// The nodes whose contact with `n` holds it up against gravity now, read from
/// Rapier's narrow phase whatever the tracking: the test of the graph's
/// `ContactGraph::resting_supports_of` (a contact that touches or lies within `gap`,
/// whose impulses' resultant, or else its deepest normal, pushes `n` along `up` by
/// more than `min_cos`), on every collider pair of `n`'s colliders with a node a
/// physical edge may join (Table 2: not two fixed nodes; not a sensor). Under
/// proximity tracking with the details kept it gives what the edges' caches give;
/// under touching tracking, which keeps no details and no edge for a pair within the
/// gap that does not touch, it is the only way to the answer. In node order, without
/// repeats. O(the contact pairs of `n`'s colliders).
pub(crate) fn resting_supports(
    graph: &ContactGraph,
    view: &WorldView,
    n: NodeId,
    up: Vector,
    min_cos: Real,
    gap: Real,
    out: &mut Vec<NodeId>,
) {
    out.clear();
    let Some(kind) = graph.node(n).map(|node| node.kind()) else {
        return;
    };
    let mut mine: Vec<ColliderHandle> = Vec::new();
    if !super::colliders_of(graph, view, n, &mut mine) {
        return;
    }
    // Per neighbour, the details oriented as if `n` were the edge's B: the normal
    // points from the neighbour into `n`, the push is what it does to `n`.
    let mut per: Vec<(NodeId, ContactCache)> = Vec::new();
    for &c in &mine {
        for pair in view.narrow_phase.contact_pairs_with(c) {
            let other = super::pairs::other_collider(pair, c);
            let Some(m) = owner_node(graph, view, other) else {
                continue;
            };
            let allowed = m != n
                && graph
                    .node(m)
                    .is_some_and(|o| edge_allowed(EdgeKind::Physical, kind, o.kind()));
            if !allowed {
                continue;
            }
            let at = match per.iter().position(|(x, _)| *x == m) {
                Some(i) => i,
                None => {
                    let mut cache = ContactCache::default();
                    cache.begin_update(true);
                    per.push((m, cache));
                    per.len() - 1
                }
            };
            // `flip`: `collider1` belongs to the B end, `n`.
            super::pairs::accumulate_pair(&mut per[at].1, pair, pair.collider1 == c, true);
        }
    }
    for (m, cache) in &per {
        let close = cache.touching || cache.min_distance <= gap;
        if !close {
            continue;
        }
        let dir = if cache.push != Vector::ZERO {
            cache.push.normalize()
        } else {
            cache.normal
        };
        if dir.dot(up) > min_cos {
            out.push(*m);
        }
    }
    out.sort_unstable();
}

/// The node a collider belongs to in the graph, without creating one: its parent
/// body's, or its own as static geometry. `None` for a sensor or an unknown collider.
/// O(1).
fn owner_node(graph: &ContactGraph, view: &WorldView, c: ColliderHandle) -> Option<NodeId> {
    let co = view.colliders.get(c)?;
    if co.is_sensor() {
        return None;
    }
    match co.parent() {
        Some(parent) => graph.node_of_body(parent),
        None => graph.node_of_static_collider(c),
    }
}

/// The deepest penetration of each touching edge of the nodes in `nodes`, read from
/// Rapier's narrow phase in one pass over each node's collider pairs: what the
/// per-edge caches hold as `ContactCache::max_penetration` under proximity tracking
/// (the largest `-distance` over every contact point of every collider pair of the
/// edge, at least 0), for touching tracking, which copies none. An edge between two
/// of the nodes is read once, from its smaller node. Appended to `out` as
/// `(edge, depth)` in edge order, each edge once. O(the nodes' contact pairs).
pub(crate) fn touching_depths(
    graph: &ContactGraph,
    view: &WorldView,
    nodes: &[NodeId],
    out: &mut Vec<(crate::graph::EdgeId, Real)>,
) {
    let mut sorted: Vec<NodeId> = nodes.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut mine: Vec<ColliderHandle> = Vec::new();
    // Per neighbour of the node at hand: the smallest distance over its pairs.
    let mut per: Vec<(NodeId, Real)> = Vec::new();
    for &n in &sorted {
        let Some(node) = graph.node(n) else { continue };
        // Only nodes with a touching edge have anything to read.
        let any = node.edges().iter().any(|&e| {
            graph
                .edge(e)
                .is_some_and(|e| e.is_touching() && e.kind() == EdgeKind::Physical)
        });
        if !any || !super::colliders_of(graph, view, n, &mut mine) {
            continue;
        }
        per.clear();
        for &c in &mine {
            for pair in view.narrow_phase.contact_pairs_with(c) {
                let other = super::pairs::other_collider(pair, c);
                let Some(m) = owner_node(graph, view, other) else {
                    continue;
                };
                // A pair with another listed node is read from the smaller one.
                if m == n || (m < n && sorted.binary_search(&m).is_ok()) {
                    continue;
                }
                let mut deepest = Real::INFINITY;
                for manifold in pair.manifolds() {
                    for p in &manifold.points {
                        if p.dist.is_finite() && p.dist < deepest {
                            deepest = p.dist;
                        }
                    }
                }
                match per.iter_mut().find(|(x, _)| *x == m) {
                    Some((_, d)) => *d = d.min(deepest),
                    None => per.push((m, deepest)),
                }
            }
        }
        for &(m, deepest) in &per {
            let Some(eid) = graph.edge_between(n, m) else {
                continue;
            };
            let touching = graph
                .edge(eid)
                .is_some_and(|e| e.is_touching() && e.kind() == EdgeKind::Physical);
            if touching {
                let depth = if deepest.is_finite() {
                    (-deepest).max(0.0)
                } else {
                    0.0
                };
                out.push((eid, depth));
            }
        }
    }
    out.sort_unstable_by_key(|(e, _)| *e);
    out.dedup_by_key(|(e, _)| *e);
}
