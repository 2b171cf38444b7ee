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
/// their colliders, or a node is gone. O(the contact pairs of the colliders of the
/// node with fewer colliders × the other's collider count): a ball against a bin of
/// five walls reads the ball's dozen pairs, not the bin's hundreds, and no collider.
pub(crate) fn read_details(
    graph: &ContactGraph,
    view: &WorldView,
    a: NodeId,
    b: NodeId,
) -> Option<ContactCache> {
    let mut cache = ContactCache::default();
    cache.begin_update(true);
    let mut any = false;
    visit_pairs(graph, view, a, b, |pair, [_, second]| {
        any = true;
        // Rapier's normal points from `collider1` to `collider2`: flip it when
        // `collider1` is the second node's.
        super::pairs::accumulate_pair(&mut cache, pair, pair.collider1 == second, true);
    })?;
    any.then_some(cache)
}

/// The touching collider pair of `a` and `b` with the smallest handles, *A*'s
/// collider first (*A*: the node with the smaller slot, as in their edge): the pair an
/// edge names when the one it named stopped while others still touch
/// (`Edge::colliders`). `None` if none touches, or a node is gone. O(the contact
/// pairs of the colliders of the node with fewer colliders × the other's collider
/// count).
pub(crate) fn smallest_touching_pair(
    graph: &ContactGraph,
    view: &WorldView,
    a: NodeId,
    b: NodeId,
) -> Option<[ColliderHandle; 2]> {
    let key = |p: [ColliderHandle; 2]| (p[0].into_raw_parts(), p[1].into_raw_parts());
    let mut best: Option<[ColliderHandle; 2]> = None;
    visit_pairs(graph, view, a, b, |pair, named| {
        if pair.has_any_active_contact() && best.is_none_or(|b| key(named) < key(b)) {
            best = Some(named);
        }
    })?;
    best
}

/// Calls `visit` with each Rapier contact pair between the colliders of `a` and `b`
/// and its two colliders, the one of the node with the smaller slot (the edge's *A*)
/// first. It walks the pairs of the side with fewer colliders; a pair is the two
/// nodes' when its other collider is one of the other side's (with one collider each
/// side, Rapier's lookup of their pair walks the same list without reading the pairs).
/// `None` if a node stands for nothing. O(the contact pairs of the colliders of the
/// node with fewer colliders × the other's collider count).
fn visit_pairs<'w>(
    graph: &ContactGraph,
    view: &'w WorldView,
    a: NodeId,
    b: NodeId,
    mut visit: impl FnMut(&'w rapier3d::geometry::ContactPair, [ColliderHandle; 2]),
) -> Option<()> {
    let (first, second) = if a.index() <= b.index() {
        (a, b)
    } else {
        (b, a)
    };
    let (first_colliders, second_colliders) = (
        NodeColliders::of(graph, view, first)?,
        NodeColliders::of(graph, view, second)?,
    );
    let (first_colliders, second_colliders) =
        (first_colliders.as_slice(), second_colliders.as_slice());
    let walk_first = first_colliders.len() <= second_colliders.len();
    let (walked, others) = if walk_first {
        (first_colliders, second_colliders)
    } else {
        (second_colliders, first_colliders)
    };
    // One collider each side (a sphere against a sphere): their one pair, if any, is
    // looked up instead of walking the collider's pairs.
    if let ([c], [other]) = (walked, others) {
        if let Some(pair) = view.narrow_phase.contact_pair(*c, *other) {
            visit(
                pair,
                if walk_first {
                    [*c, *other]
                } else {
                    [*other, *c]
                },
            );
        }
        return Some(());
    }
    for &c in walked {
        for pair in view.narrow_phase.contact_pairs_with(c) {
            let other = super::pairs::other_collider(pair, c);
            if others.contains(&other) {
                visit(pair, if walk_first { [c, other] } else { [other, c] });
            }
        }
    }
    Some(())
}

/// The colliders a node stands for: its body's, or its own as static geometry.
enum NodeColliders<'a> {
    Body(&'a [ColliderHandle]),
    Static(ColliderHandle),
}

impl<'a> NodeColliders<'a> {
    /// `None` if the node, its body or its static collider is gone (a static
    /// geometry node whose collider got a parent or turned into a sensor stands for
    /// nothing). O(1).
    fn of(graph: &ContactGraph, view: &'a WorldView, n: NodeId) -> Option<Self> {
        match graph.node(n)?.source() {
            crate::NodeSource::Body(h) => Some(Self::Body(view.bodies.get(h)?.colliders())),
            crate::NodeSource::StaticCollider(c) => {
                nodes::owns(view, c, crate::NodeSource::StaticCollider(c))
                    .then_some(Self::Static(c))
            }
            _ => None,
        }
    }

    fn as_slice(&self) -> &[ColliderHandle] {
        match self {
            Self::Body(s) => s,
            Self::Static(c) => std::slice::from_ref(c),
        }
    }
}

/// Accumulates `n`'s collider pairs into one value per neighbour node: each starts
/// as `new()` and `add` folds in a pair with its `flip` (`collider1` belongs to the
/// B end, `n`; see [`super::pairs::accumulate_pair`]). Neighbours for which `skip`
/// says so, and `n` itself, are left out; with `points_only`, so are the pairs
/// without a contact point (which add nothing to a cache but its pair count and
/// proximity), before their owner is looked up. `per` is cleared first; `mine` is
/// scratch. False if `n` has no colliders in the world. O(the contact pairs of `n`'s
/// colliders).
#[allow(clippy::too_many_arguments)] // the walk's inputs, its scratch and its fold
fn per_neighbour<T>(
    graph: &ContactGraph,
    view: &WorldView,
    n: NodeId,
    skip: impl Fn(NodeId) -> bool,
    points_only: bool,
    mine: &mut Vec<ColliderHandle>,
    per: &mut Vec<(NodeId, T)>,
    new: impl Fn() -> T,
    mut add: impl FnMut(&mut T, &rapier3d::geometry::ContactPair, bool),
) -> bool {
    per.clear();
    if !super::colliders_of(graph, view, n, mine) {
        return false;
    }
    for &c in mine.iter() {
        for pair in view.narrow_phase.contact_pairs_with(c) {
            if points_only
                && !pair.has_any_active_contact()
                && pair.manifolds().iter().all(|m| m.points.is_empty())
            {
                continue;
            }
            let other = super::pairs::other_collider(pair, c);
            let Some(m) = nodes::collider_owner(graph, view, other) else {
                continue;
            };
            if m == n || skip(m) {
                continue;
            }
            let at = match per.iter().position(|(x, _)| *x == m) {
                Some(i) => i,
                None => {
                    per.push((m, new()));
                    per.len() - 1
                }
            };
            add(&mut per[at].1, pair, pair.collider1 == c);
        }
    }
    true
}

/// A cache ready to accumulate collider pairs with their details, as an edge's at the
/// start of its update. O(1).
fn fresh_cache() -> ContactCache {
    let mut cache = ContactCache::default();
    cache.begin_update(true);
    cache
}

/// The nodes whose contact with `n` holds it up against gravity now, read from
/// Rapier's narrow phase whatever the tracking: the graph's support test
/// (`ContactCache::holds_up`, as `ContactGraph::resting_supports_of` applies it to the
/// cached edges) on every collider pair of `n`'s colliders with a node a physical
/// edge may join (Table 2: not two fixed nodes; not a sensor). Under proximity
/// tracking with the details kept it gives what the edges' caches give; under
/// touching tracking, which keeps no details and no edge for a pair within the gap
/// that does not touch, it is the only way to the answer. In node order, without
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
    let disallowed = |m: NodeId| {
        graph
            .node(m)
            .is_none_or(|o| !edge_allowed(EdgeKind::Physical, kind, o.kind()))
    };
    let mut per = Vec::new();
    // A pair without a contact point holds nothing up (`ContactCache::holds_up`: it
    // neither touches nor lies within the gap): the pairs of a held body with other
    // held ones, most of a pile's, are passed over before any lookup.
    // Each oriented as if `n` were the edge's *B* (the normal points from the
    // neighbour into `n`, the push is what the neighbour does to `n`).
    let accumulate = |cache: &mut ContactCache, pair: &_, flip| {
        super::pairs::accumulate_pair(cache, pair, flip, true)
    };
    per_neighbour(
        graph,
        view,
        n,
        disallowed,
        true,
        &mut Vec::new(),
        &mut per,
        fresh_cache,
        accumulate,
    );
    out.extend(
        per.iter()
            .filter(|(_, cache)| cache.holds_up(true, up, min_cos, gap))
            .map(|(m, _)| *m),
    );
    out.sort_unstable();
}

/// The deepest penetration of each touching edge of the nodes in `nodes`, read from
/// Rapier's narrow phase in one pass over each node's collider pairs: what the
/// per-edge caches hold as `ContactCache::max_penetration` under proximity tracking
/// (the same accumulation, the depth alone), for touching tracking, which copies
/// none. An edge between two of the nodes is read once, from its smaller node.
/// Appended to `out` as `(edge, depth)` in edge order, each edge once. O(the nodes'
/// contact pairs).
pub(crate) fn touching_depths(
    graph: &ContactGraph,
    view: &WorldView,
    nodes: &[NodeId],
    out: &mut Vec<(crate::graph::EdgeId, Real)>,
) {
    let mut sorted: Vec<NodeId> = nodes.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let touching_physical =
        |e: &crate::graph::Edge| e.is_touching() && e.kind() == EdgeKind::Physical;
    let mut mine: Vec<ColliderHandle> = Vec::new();
    // Per neighbour: (the deepest point's distance, the penetration), as
    // `ContactCache::min_distance` and `max_penetration` accumulate them.
    let mut per: Vec<(NodeId, (Real, Real))> = Vec::new();
    for &n in &sorted {
        let Some(node) = graph.node(n) else { continue };
        // Only nodes with a touching edge have anything to read.
        let any = node
            .edges()
            .iter()
            .any(|&e| graph.edge(e).is_some_and(touching_physical));
        // A pair with another listed node is read from the smaller one.
        let listed_before = |m: NodeId| m < n && sorted.binary_search(&m).is_ok();
        let start = || (Real::INFINITY, 0.0);
        let add = |(deepest, depth): &mut (Real, Real), pair: &_, _| deepen(deepest, depth, pair);
        if !any
            || !per_neighbour(
                graph,
                view,
                n,
                listed_before,
                false,
                &mut mine,
                &mut per,
                start,
                add,
            )
        {
            continue;
        }
        for &(m, (_, depth)) in &per {
            let Some(eid) = graph.edge_between(n, m) else {
                continue;
            };
            if graph.edge(eid).is_some_and(touching_physical) {
                out.push((eid, depth));
            }
        }
    }
    out.sort_unstable_by_key(|(e, _)| *e);
    out.dedup_by_key(|(e, _)| *e);
}

/// One collider pair's share of a neighbour's deepest distance and penetration,
/// as `pairs::accumulate_pair` adds it to a cache's. O(the pair's points).
fn deepen(deepest: &mut Real, depth: &mut Real, pair: &rapier3d::geometry::ContactPair) {
    for m in pair.manifolds() {
        for p in &m.points {
            if p.dist.is_finite() && p.dist < *deepest {
                *deepest = p.dist;
            }
        }
    }
    *depth = super::pairs::penetration_with(*depth, *deepest);
}
