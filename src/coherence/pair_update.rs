//! Edge insertion and removal (paper §3.1, Fig. 3) and the proximity and touching
//! marks (§3.2) from Rapier's narrow-phase pairs: the per-body walk, the full scan,
//! and retiring edges whose pair is gone.

use rapier3d::geometry::ContactPair;

use crate::graph::{ContactGraph, EdgeId, EdgeKind, NodeId};
use crate::WorldView;

use super::*;

impl Coherence {
    /// Aggregates the collider pairs of one refreshed body into its edges.
    pub(super) fn walk_pairs(
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
    pub(super) fn scan_all_pairs(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
    ) {
        let step = self.step;
        let stale_before = self.stale.len();
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
            if (refreshed(a) || refreshed(b)) && screen.admits_contact(graph, view, (a, b), pair) {
                self.feed_edge(graph, view, eid, pair, flip);
            }
        }
        slots.truncate(len);
        // A lookup found a collider that changed owner: other slots may still name
        // its old edges (read again at the next update, rebuilt without the cache).
        if self.stale.len() == stale_before {
            self.pair_slots = slots;
        }
    }

    /// The edge of a collider pair and whether `collider1` belongs to its B node;
    /// `None` if the pair makes no edge (sensor, same body, excluded by Table 2).
    pub(super) fn edge_of_pair(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        pair: &ContactPair,
    ) -> Option<(EdgeId, bool)> {
        let n1 = self.owner_of(graph, view, pair.collider1)?;
        let n2 = self.owner_of(graph, view, pair.collider2)?;
        // Screened pairs (passive end, rule) make no edge (Fig. 4).
        if n1 == n2 || !screen.admits_contact(graph, view, (n1, n2), pair) {
            return None;
        }
        let eid = pairs::physical_edge_for(graph, n1, n2, self.step)?;
        Some((eid, graph.edge(eid)?.b == n1))
    }

    /// Adds one collider pair to the edge of its two owners (creating the edge).
    pub(super) fn process_pair(
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
    #[inline]
    pub(super) fn feed_edge(
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
        // Rapier keeps a held body's pairs with what stands still, without contacts:
        // the edge keeps the contact it froze with (`graph/frozen.rs`).
        if e.walk_stamp != step && graph.is_frozen(e) {
            return;
        }
        if e.walk_stamp != step {
            let (pa, pb) = if details {
                (pose_of(graph, view, e.a), pose_of(graph, view, e.b))
            } else {
                (None, None)
            };
            let Some(e) = graph.edge_mut(eid) else { return };
            pairs::begin_edge_update(&mut e.cache, pa.as_ref(), pb.as_ref(), details);
            e.begin_naming(false);
            e.walk_stamp = step;
            e.updated_step = step;
            self.touched.push(eid);
            self.counters.edges += 1;
        }
        if let Some(e) = graph.edge_mut(eid) {
            pairs::accumulate_pair(&mut e.cache, pair, flip, details);
            // The pair the edge's events name (see `Edge::colliders`), *A*'s first.
            let named = if flip {
                [pair.collider2, pair.collider1]
            } else {
                [pair.collider1, pair.collider2]
            };
            e.meet_pair(named, pair.has_any_active_contact());
        }
    }

    /// An edge of a refreshed body that no collider pair reached this step: it has
    /// vanished (mark it), or vanished earlier (remove it if obsolete).
    pub(super) fn retire(&mut self, graph: &mut ContactGraph, view: &WorldView, eid: EdgeId) {
        let step = self.step;
        // A held body's contact with what stands still has no Rapier pair: it stays
        // as it was (`graph/frozen.rs`).
        if graph.edge(eid).is_some_and(|e| graph.is_frozen(e)) {
            return;
        }
        let Some(e) = graph.edge_mut(eid) else { return };
        if e.walk_stamp == step {
            return;
        }
        e.walk_stamp = step;
        let was_proximate = e.cache.proximity;
        e.cache.begin_update(!self.skip_details);
        e.updated_step = step;
        let (a, b, kind) = (e.a, e.b, e.kind);
        let passive = |n| graph.node(n).is_some_and(|n| n.passive);
        // Geometric edges live only while the body is inside the trigger, and a passive
        // body has no edges: both go as soon as their end is reported.
        if kind == EdgeKind::Geometric || passive(a) || passive(b) {
            // Its group drops it by the graph's record of the removal.
            if let Some(e) = graph.remove_edge(eid) {
                if was_proximate {
                    self.removed_edges.push(e);
                }
            }
            return;
        }
        if was_proximate {
            // Vanished now: report, test for obsolescence from the next update on (an
            // ended touch splits its group with the other touched edges).
            self.touched.push(eid);
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
}
