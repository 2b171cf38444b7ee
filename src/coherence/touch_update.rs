//! The touch update under touching tracking: the layer's `COLLISION_EVENTS` flags,
//! the step's touch transitions applied to the physical edges, and the rescans that
//! read touching pairs from Rapier where events cannot be trusted.

use rapier3d::geometry::{ColliderSet, ContactPair};
use rapier3d::pipeline::ActiveEvents;
use rapier3d::prelude::ColliderHandle;

use crate::graph::{ContactGraph, EdgeId, EdgeKind};
use crate::WorldView;

use super::*;

/// Whether a collider of the set lacks `ActiveEvents::COLLISION_EVENTS` (one the set
/// lacks does not). O(1).
fn lacks_touch_flag(colliders: &ColliderSet, c: ColliderHandle) -> bool {
    colliders
        .get(c)
        .is_some_and(|co| !co.active_events().contains(ActiveEvents::COLLISION_EVENTS))
}

impl Coherence {
    /// Sets or takes off the layer's `COLLISION_EVENTS` flags, before Rapier's step:
    /// with `on`, every collider lacking the flag gets it (all colliders when their
    /// count changed or tracking just started, [`Self::verify_budget`] slots round robin
    /// otherwise); without,
    /// the flags the layer set are taken off again. A collider found unflagged is
    /// remembered: its touching pairs are read at the next update. O(colliders) on a
    /// change, O(verify_budget) otherwise.
    pub(crate) fn sync_touch_flags(&mut self, colliders: &mut ColliderSet, on: bool) {
        if !on {
            for (_, c) in std::mem::take(&mut self.touch_flagged) {
                if let Some(co) = colliders.get_mut(c) {
                    let f = co.active_events() - ActiveEvents::COLLISION_EVENTS;
                    co.set_active_events(f);
                }
            }
            self.force_touch_flags();
            return;
        }
        let budget = self.verify_budget();
        let flagged = &mut self.touch_flagged;
        let rescan = &mut self.touch_rescan;
        // Read first: `ColliderSet::get_mut` marks a collider modified for Rapier's
        // next step, so only a collider that needs the flag is written.
        let mut flag = |c: ColliderHandle, colliders: &mut ColliderSet| {
            let lacks = lacks_touch_flag(colliders, c);
            // (`lacks` first: `get_mut` marks the collider even when nothing is written.)
            if let Some(co) = lacks.then(|| colliders.get_mut(c)).flatten() {
                co.set_active_events(co.active_events() | ActiveEvents::COLLISION_EVENTS);
                flagged.insert(c.into_raw_parts(), c);
                rescan.push(c);
            }
        };
        if colliders.len() != self.touch_flag_colliders {
            self.touch_flag_colliders = colliders.len();
            let all: Vec<ColliderHandle> = colliders.iter().map(|(h, _)| h).collect();
            for c in all {
                flag(c, colliders);
            }
            // Forget colliders that are gone.
            self.touch_flagged.retain(|_, c| colliders.contains(*c));
        } else {
            let span = colliders.len() as u32 + budget as u32;
            for i in round_robin(&mut self.touch_flag_cursor, span, budget) {
                if let Some((_, h)) = colliders.get_unknown_gen(i) {
                    flag(h, colliders);
                }
            }
        }
    }

    /// The colliders of the nodes created at this update whose touching pairs the
    /// step's events may not tell in full: those that lack the layer's
    /// `COLLISION_EVENTS` flag (first list), and those that carry a flag the layer did
    /// not set (second list: the user's, or another layer's, which may have stepped
    /// the world meanwhile; the layer reads the pairs of the colliders it flags
    /// itself). O(created nodes' colliders · log).
    pub(super) fn unheard_of_created(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
    ) -> (Vec<ColliderHandle>, Vec<ColliderHandle>) {
        let (mut unflagged, mut foreign) = (Vec::new(), Vec::new());
        let mut sort = |c: ColliderHandle| {
            if lacks_touch_flag(view.colliders, c) {
                unflagged.push(c);
            } else if !self.touch_flagged.contains_key(&c.into_raw_parts()) {
                foreign.push(c);
            }
        };
        for &n in &self.created {
            match graph.node(n).map(|n| n.source) {
                Some(NodeSource::Body(h)) => {
                    if let Some(rb) = view.bodies.get(h) {
                        rb.colliders().iter().for_each(|&c| sort(c));
                    }
                }
                Some(NodeSource::StaticCollider(c) | NodeSource::Sensor(c)) => sort(c),
                _ => {}
            }
        }
        (unflagged, foreign)
    }

    /// Makes the next [`Self::sync_touch_flags`] look at every collider. O(1).
    pub(super) fn force_touch_flags(&mut self) {
        self.touch_flag_colliders = usize::MAX;
    }

    /// Applies the step's touch transitions to the physical edges (touching tracking),
    /// and settles them with the edges already begun (`changed`: the thawed ones).
    pub(super) fn apply_touch_events(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        events: &[TouchEvent],
        mut changed: Vec<EdgeId>,
    ) {
        let step = self.step;
        for ev in events {
            self.counters.collider_pairs += 1;
            let (Some(n1), Some(n2)) = (
                self.owner_of(graph, view, ev.c1),
                self.owner_of(graph, view, ev.c2),
            ) else {
                continue;
            };
            if n1 == n2 {
                continue;
            }
            let eid = if ev.started {
                if !screen.admits_pair(graph, view, (n1, n2), (ev.c1, ev.c2), false) {
                    continue;
                }
                match pairs::physical_edge_for(graph, n1, n2, step) {
                    Some(e) => e,
                    None => continue,
                }
            } else {
                // A held body's contact with what stands still left Rapier's narrow
                // phase when it was held, not the graph (`graph/frozen.rs`).
                match graph.edge_by_key(crate::graph::PairKey::of(n1, n2)) {
                    Some(e)
                        if graph.edge(e).is_some_and(|e| {
                            e.kind == EdgeKind::Physical && !graph.is_frozen(e)
                        }) =>
                    {
                        e
                    }
                    _ => continue,
                }
            };
            self.begin_touch_update(graph, eid, &mut changed);
            if let Some(e) = graph.edge_mut(eid) {
                let c = &mut e.cache;
                c.collider_pairs = if ev.started {
                    c.collider_pairs.saturating_add(1)
                } else {
                    c.collider_pairs.saturating_sub(1)
                };
                // The pair the edge's events name (`Edge::colliders`), *A*'s first.
                let named = if e.a == n1 {
                    [ev.c1, ev.c2]
                } else {
                    [ev.c2, ev.c1]
                };
                if ev.started {
                    e.meet_pair(named, true);
                } else {
                    e.pair_stopped(named);
                }
            }
        }
        self.settle_touch_edges(graph, view, &changed);
    }

    /// Reads the touching pairs of the given colliders (flagged late) or, with `all`,
    /// of the whole narrow phase, and sets the physical edges to them. O(their pairs),
    /// or O(pairs + edges) with `all`.
    pub(super) fn rescan_touching(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        events: &[TouchEvent],
        colliders: &[ColliderHandle],
        all: bool,
    ) {
        let mut tally = TouchTally::new(events, all);
        let nodes = self.read_touching(graph, view, screen, colliders, &mut tally);
        let TouchTally {
            counts, pre_flag, ..
        } = tally;
        let targets = touch_targets(graph, &nodes, &counts, all);
        let mut changed = Vec::new();
        // Edges this step's events changed already: settled again with the count read
        // here, which wins (after a switch from proximity tracking, or for a collider
        // flagged late, the events alone may have counted from a stale start).
        let mut again = Vec::new();
        self.set_touch_counts(graph, targets, &counts, &mut changed, &mut again);
        mark_pre_flag(graph, view, pre_flag);
        let settled_twice = !again.is_empty();
        changed.append(&mut again);
        self.settle_touch_edges(graph, view, &changed);
        if settled_twice {
            // Those edges are in the touched list twice (keep the first), or were
            // touched by the events and removed here (the rescan found no touching
            // pair left): drop those.
            let mut seen = std::collections::HashSet::new();
            self.touched
                .retain(|&e| graph.edge(e).is_some() && seen.insert(e));
        }
    }

    /// Reads the touching pairs into `tally`: every pair of the narrow phase with
    /// `tally.all`, else every pair of the owners of `colliders` and of the nodes whose
    /// colliders changed in place (and of any found so on the way), whose edges are then
    /// counted in full. Returns those nodes, sorted (none with `all`).
    fn read_touching(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        colliders: &[ColliderHandle],
        tally: &mut TouchTally,
    ) -> Vec<NodeId> {
        let mut nodes: Vec<NodeId> = Vec::new();
        if tally.all {
            // Room for an edge and a count per pair at once (a world read in full for
            // the first time creates one per touching pair): the pair count is known in
            // O(1).
            let pairs = view.narrow_phase.contact_pairs().size_hint().0;
            graph.reserve_edges(pairs.saturating_sub(graph.edge_count()));
            tally.counts.reserve(pairs);
            for pair in view.narrow_phase.contact_pairs() {
                tally.visit(self, graph, view, screen, pair);
            }
            return nodes;
        }
        for &c in colliders {
            if let Some(n) = self.owner_of(graph, view, c) {
                nodes.push(n);
            }
        }
        // Owners of colliders changed in place; a lookup below may find more
        // (a cached owner that no longer owns its collider): read those too.
        let mut own = Vec::new();
        let mut next = std::mem::take(&mut self.stale);
        next.append(&mut nodes);
        while !next.is_empty() {
            next.sort_unstable();
            next.dedup();
            next.retain(|n| nodes.binary_search(n).is_err());
            for &n in &next {
                if !colliders_of(graph, view, n, &mut own) {
                    continue;
                }
                for &c in &own {
                    for pair in view.narrow_phase.contact_pairs_with(c) {
                        tally.visit(self, graph, view, screen, pair);
                    }
                }
            }
            nodes.append(&mut next);
            nodes.sort_unstable();
            next = std::mem::take(&mut self.stale);
        }
        nodes
    }

    /// Sets each target edge's count of touching collider pairs to the one read, and
    /// the pair it names; an edge already in these terms is left alone, one this step's
    /// events changed goes to `again`, the others start their update into `changed`.
    fn set_touch_counts(
        &mut self,
        graph: &mut ContactGraph,
        targets: Vec<EdgeId>,
        counts: &TallyMap,
        changed: &mut Vec<EdgeId>,
        again: &mut Vec<EdgeId>,
    ) {
        let step = self.step;
        for eid in targets {
            let (want, name) = match counts.get(&eid) {
                Some(t) => (t.count, Some(t.named)),
                None => (0, None),
            };
            let Some(e) = graph.edge(eid) else { continue };
            // Kept only when already in touching tracking's terms: after proximity
            // tracking, an edge's contact count is of solver contacts, a proximate
            // edge need not touch, and an edge whose proximity just ended lingers
            // for the obsolete pass; here an edge exists only while it touches.
            let c = &e.cache;
            if want > 0
                && c.collider_pairs == want
                && c.contact_count == want
                && c.touching
                && c.proximity
            {
                if let (Some(n), Some(e)) = (name, graph.edge_mut(eid)) {
                    if e.named != n {
                        e.set_named(n);
                    }
                }
                continue;
            }
            if e.walk_stamp == step {
                again.push(eid);
            } else {
                self.begin_touch_update(graph, eid, changed);
            }
            if let Some(e) = graph.edge_mut(eid) {
                e.cache.collider_pairs = want;
                // A touching edge names a pair read now; one left without keeps the
                // pair named last.
                if let Some(n) = name {
                    e.set_named(n);
                }
            }
        }
    }

    /// Starts this step's update of a physical edge in touching tracking (once per
    /// step): shifts its state to `e_old`, keeping its count of touching collider
    /// pairs.
    pub(super) fn begin_touch_update(
        &mut self,
        graph: &mut ContactGraph,
        eid: EdgeId,
        changed: &mut Vec<EdgeId>,
    ) {
        let step = self.step;
        let Some(e) = graph.edge_mut(eid) else { return };
        if e.walk_stamp == step {
            return;
        }
        let pairs = e.cache.collider_pairs;
        e.cache.begin_update(false);
        e.cache.collider_pairs = pairs;
        e.begin_naming(true);
        e.walk_stamp = step;
        e.updated_step = step;
        changed.push(eid);
    }

    /// Ends the step's update of the changed edges: touching (and proximity, which is
    /// the same here) from the count; an edge left with no touching pair is removed
    /// and reported with its `Vanished` marks; the others are this step's touched
    /// edges. Both ends of an edge whose touching changed are regrouped. An edge that
    /// still touches while the pair it named stopped names the touching pair with the
    /// smallest handles, read from Rapier (`Edge::colliders`: O(the pairs of the
    /// colliders of the end with fewer colliders), only then).
    fn settle_touch_edges(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        changed: &[EdgeId],
    ) {
        for &eid in changed {
            let Some(e) = graph.edge_mut(eid) else {
                continue;
            };
            let touching = e.cache.collider_pairs > 0;
            e.cache.touching = touching;
            e.cache.proximity = touching;
            // No solver contact is read here: the count is of touching collider pairs.
            e.cache.contact_count = e.cache.collider_pairs;
            let was = e.cache.touching_old;
            if e.naming_unsettled() {
                let (a, b) = (e.a, e.b);
                if let Some(n) = super::details::smallest_touching_pair(graph, view, a, b) {
                    if let Some(e) = graph.edge_mut(eid) {
                        e.set_named(n);
                    }
                }
            }
            // A touch that began merges groups (the edge is touched); one that ended
            // leaves its group by the graph's record of the removal.
            if touching {
                self.touched.push(eid);
                self.counters.edges += 1;
            } else if let Some(e) = graph.remove_edge(eid) {
                if was {
                    self.removed_edges.push(e);
                }
            }
        }
    }
}

/// The edges a rescan sets: every physical edge with `all`, else those of the nodes
/// read, and every edge counted; frozen edges left out. O(their edges).
fn touch_targets(
    graph: &ContactGraph,
    nodes: &[NodeId],
    counts: &TallyMap,
    all: bool,
) -> Vec<EdgeId> {
    let mut targets: Vec<EdgeId> = if all {
        graph
            .edges()
            .filter(|(_, e)| e.kind == EdgeKind::Physical)
            .map(|(id, _)| id)
            .collect()
    } else {
        nodes
            .iter()
            .filter_map(|&n| graph.node(n))
            .flat_map(|n| n.edges.iter().copied())
            .filter(|&e| graph.edge(e).is_some_and(|e| e.kind == EdgeKind::Physical))
            .collect()
    };
    // Frozen edges (a held body's contacts with what stands still) have no Rapier
    // pair to count: they stay.
    targets.retain(|e| graph.edge(*e).is_none_or(|e| !graph.is_frozen(e)));
    targets.extend(counts.keys().copied());
    targets.sort_unstable();
    targets.dedup();
    targets
}

/// Bodies newly holding a pair that may have begun before the flag: their
/// disabled-collider signature starts from the set read now. O(those bodies' colliders).
fn mark_pre_flag(graph: &mut ContactGraph, view: &WorldView, mut pre_flag: Vec<NodeId>) {
    pre_flag.sort_unstable();
    pre_flag.dedup();
    for n in pre_flag {
        let sig = match graph.node(n).map(|n| (n.pre_flag_touch, n.source)) {
            Some((false, NodeSource::Body(h))) => view
                .bodies
                .get(h)
                .map(|rb| nodes::disabled_sig(view, rb.colliders())),
            _ => None,
        };
        if let (Some(sig), Some(node)) = (sig, graph.node_mut(n)) {
            node.pre_flag_touch = true;
            node.disabled_sig = sig;
        }
    }
}

/// Per physical edge, what a rescan counted ([`TouchTally::counts`]).
type TallyMap = std::collections::HashMap<EdgeId, PairTally, crate::graph::PairBuildHasher>;

/// A collider pair by raw handles, smaller first.
type RawPair = ((u32, u32), (u32, u32));

/// A set of collider pairs (only asked whether it holds one, never iterated).
type PairSet = std::collections::HashSet<RawPair, crate::graph::PairBuildHasher>;

/// The collider pair `(a, b)` as a [`RawPair`], either order.
fn raw_pair(a: ColliderHandle, b: ColliderHandle) -> RawPair {
    let (a, b) = (a.into_raw_parts(), b.into_raw_parts());
    (a.min(b), a.max(b))
}

/// What a rescan counted: per physical edge, its touching collider pairs and the pair
/// it is to name (`Edge::colliders`: the one named already if it touches, else the one
/// with the smallest handles), and the nodes holding a touching pair that may have
/// begun before its colliders were flagged.
struct TouchTally {
    all: bool,
    /// The collider pairs that sent `Started` this step.
    started: PairSet,
    /// Touching pairs met already: a pair between two rescanned nodes is met from
    /// both.
    seen: PairSet,
    /// Per physical edge, its touching collider pairs read and the pair it names
    /// (never iterated in hash order: the edges it sets are sorted first).
    counts: TallyMap,
    pre_flag: Vec<NodeId>,
}

/// One edge's touching collider pairs as read, and the pair it names.
struct PairTally {
    count: u32,
    named: [ColliderHandle; 2],
}

impl TouchTally {
    fn new(events: &[TouchEvent], all: bool) -> Self {
        let mut started = PairSet::with_capacity_and_hasher(events.len(), Default::default());
        started.extend(
            events
                .iter()
                .filter(|e| e.started)
                .map(|e| raw_pair(e.c1, e.c2)),
        );
        Self {
            all,
            started,
            seen: Default::default(),
            counts: TallyMap::default(),
            pre_flag: Vec::new(),
        }
    }

    /// Counts one narrow-phase pair if it touches, is admitted and was not met yet
    /// (each pair once unless `all`, which meets each once anyway).
    fn visit(
        &mut self,
        this: &mut Coherence,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        pair: &ContactPair,
    ) {
        // Touching first: most pairs of a pile do not, and need no lookup.
        if !pair.has_any_active_contact() {
            return;
        }
        if !self.all
            && !self.seen.insert((
                pair.collider1.into_raw_parts(),
                pair.collider2.into_raw_parts(),
            ))
        {
            return;
        }
        let (Some(n1), Some(n2)) = (
            this.owner_of(graph, view, pair.collider1),
            this.owner_of(graph, view, pair.collider2),
        ) else {
            return;
        };
        if n1 == n2 || !screen.admits_contact(graph, view, (n1, n2), pair) {
            return;
        }
        if let Some(e) = pairs::physical_edge_for(graph, n1, n2, this.step) {
            if let Some(edge) = graph.edge(e) {
                let named = if edge.a == n1 {
                    [pair.collider1, pair.collider2]
                } else {
                    [pair.collider2, pair.collider1]
                };
                self.counts
                    .entry(e)
                    .and_modify(|t| {
                        t.count += 1;
                        if edge.prefers_name(named, t.named) {
                            t.named = named;
                        }
                    })
                    .or_insert(PairTally { count: 1, named });
            }
        }
        if !self
            .started
            .contains(&raw_pair(pair.collider1, pair.collider2))
        {
            self.pre_flag.extend([n1, n2]);
        }
    }
}
