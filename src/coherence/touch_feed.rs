//! Touch transitions from Rapier's own collision events: [`Tracking`] and the layer's
//! [`TouchFeed`]. The design is written out on [`Tracking`]; the user's own handler
//! beside the layer's is `user_events.rs`.

use std::collections::BTreeMap;
use std::sync::Mutex;

use rapier3d::dynamics::{SoftBodySet, SoftBodyTearEvent};
use rapier3d::geometry::{ColliderSet, CollisionEvent, CollisionEventFlags, ContactPair};
use rapier3d::math::Real;
use rapier3d::pipeline::{ActiveEvents, EventHandler};
use rapier3d::prelude::{ColliderHandle, RigidBodySet};

use crate::graph::{ContactGraph, EdgeId, EdgeKind};
use crate::WorldView;

use super::*;

/// How the layer follows contacts.
///
/// # Why
/// In [`Tracking::Proximity`] the analysis reads every pair of every awake body each
/// step (paper §3.2's marks need the narrow-phase state of each overlap), which costs
/// a large share of a Rapier step on a falling pile (`docs/results.md`). Rapier
/// already knows when a collider pair starts and stops touching and reports it, for
/// free and without changing any result, as `CollisionEvent::Started` / `Stopped` to
/// the `EventHandler` given to its step, for pairs where either collider has
/// `ActiveEvents::COLLISION_EVENTS` (`docs/rapier-notes.md`). In touching tracking
/// the layer is that event handler ([`TouchFeed`]) and the per-step work on contacts
/// is proportional to the events, not to the awake pairs.
///
/// # When it is in effect
/// Touching tracking is the default. It is in effect for a step when all of these
/// hold (otherwise the layer tracks proximity for that step, and each switch reads
/// the pairs once):
/// - it is asked for ([`ContactLayer::set_tracking`](crate::ContactLayer::set_tracking));
/// - no subscription asks for proximity or persist events (the events module's
///   `KindSet::NEEDS_EVERY_PAIR`). The speed-ups and the monitor run under either
///   tracking: what they read besides the touching edges (what holds a body up, the
///   awake bodies' contact depths) they read from Rapier's narrow phase for the
///   bodies concerned, the same figures under both, so that they decide and judge the
///   same and the world is the same bit for bit (`tests/speedups_under_touching.rs`,
///   `tests/monitor_under_touching.rs`);
/// - **the layer's event handler reaches Rapier's step.**
///   [`ContactLayer::step`](crate::ContactLayer::step) passes it itself. A user who
///   steps Rapier by hand passes
///   [`ContactLayer::event_handler`](crate::ContactLayer::event_handler) (or
///   [`event_handler_with`](crate::ContactLayer::event_handler_with), which also
///   forwards Rapier's events to the user's own handler). The layer notes that one
///   of them was called since the last analysis; a hand-stepped loop that never asks
///   for them keeps proximity tracking (and its colliders' flags untouched), and one
///   that stops asking is read in full at the next analysis and goes back to
///   proximity tracking. The flags are set from the pre-step after the first step
///   that passed the handler (that step's touching pairs are read once, as at every
///   switch).
///
/// [`LayerAnalysis::touching_in_effect`](crate::LayerAnalysis::touching_in_effect) says
/// which applies to the next step.
///
/// # What the graph holds, and what it costs
/// - Physical edges are exactly the touching body pairs (the paper's contact edges);
///   no proximity edges and no persist events (nothing reads a pair that did not
///   change). Each edge counts its touching collider pairs
///   (`ContactCache::collider_pairs`): `Started` adds one, `Stopped` takes one, and
///   the edge goes when none is left.
/// - The contact details of an edge (distances, normals, impulses) are not copied:
///   [`ContactLayer::contact_details`](crate::ContactLayer::contact_details) and
///   [`ContactLayer::supports_of_body`](crate::ContactLayer::supports_of_body) read
///   them from Rapier's narrow phase when asked. `ContactCache::contact_count` counts the
///   touching collider pairs, not the solver contacts.
/// - Per step: O(events + awake bodies) for the analysis, plus the group changes of
///   the bodies whose contacts changed.
/// - Pairs that were touching before the feed was attached never send `Started`: the
///   touching pairs are read once from the narrow phase when touching tracking starts
///   and on [`LayerAnalysisMut::request_full_sync`](crate::LayerAnalysisMut::request_full_sync)
///   (O(pairs), on request only).
///
/// # The flags it sets, and the user's events
/// The layer adds `ActiveEvents::COLLISION_EVENTS` to every collider that lacks it
/// (all of them when the collider count changes, a few slots round robin otherwise:
/// [`Coherence::verify_budget`]) and
/// remembers which; it takes the flag off those again when the layer's handler no
/// longer reaches Rapier's step and when the layer is detached, not when proximity
/// tracking takes over (a flag written to a collider Rapier has stepped alters the
/// order Rapier handles pairs in). A collider that it finds unflagged has its touching
/// pairs read at once, so a collider inserted while another was removed loses no
/// contact. The flag changes no trajectory bit (tested). A user's own `EventHandler`
/// must then see only the events Rapier would have sent without the layer:
/// [`WithUser`](super::WithUser) forwards an event only when one of its colliders carries the flag by
/// the user's own doing.
///
/// Switching the flag off on a collider the layer flagged, while touching tracking is
/// on, hides that collider's contacts from the layer (like any change Rapier does not
/// report: call `request_full_sync`).
///
/// # Rejected
/// - Proximity tracking as the default: it costs a large share of a Rapier step on
///   falling piles, for proximity edges and persist events most users never read.
/// - Reading `contact_pairs()` (all pairs) every step: on a settled pile, far more
///   than Rapier's sleeping step (measured: `docs/rapier-notes.md`).
/// - Switching to touching tracking whatever the stepping: a hand-stepped loop that
///   does not pass the layer's handler would silently see no contact at all.
/// - A crossbeam channel as the queue: a `Mutex<Vec>` drained once per step does the
///   same with one allocation kept across steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Tracking {
    /// Every narrow-phase pair of an awake body is read each step: proximity and
    /// touching edges, contact details, persist events. In effect whenever touching
    /// tracking is not (see above); the speed-ups and the monitor do not need it.
    Proximity,
    /// The default. Touching edges only, driven by Rapier's collision events:
    /// proximity and persistence at the price of their use. In effect under the
    /// conditions above; proximity tracking otherwise.
    #[default]
    Touching,
}

/// One touch transition of a collider pair, as Rapier reported it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TouchEvent {
    pub c1: ColliderHandle,
    pub c2: ColliderHandle,
    pub started: bool,
}

/// The layer's `EventHandler`: collects the touch transitions of the step for the
/// analysis. Pass it (or [`WithUser`](super::WithUser)) to Rapier's step when stepping Rapier yourself
/// with touching tracking on. Cheap: one push per event, under a mutex.
#[derive(Debug, Default)]
pub struct TouchFeed {
    queue: Mutex<Vec<TouchEvent>>,
}

impl TouchFeed {
    fn push(&self, event: CollisionEvent) {
        let (c1, c2, flags, started) = match event {
            CollisionEvent::Started(a, b, f) => (a, b, f, true),
            CollisionEvent::Stopped(a, b, f) => (a, b, f, false),
        };
        if flags.contains(CollisionEventFlags::SENSOR) {
            return;
        }
        // A poisoned lock only means a panic elsewhere; the queue itself is intact.
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        q.push(TouchEvent { c1, c2, started });
    }

    /// Takes the step's events, in the order Rapier sent them.
    pub(crate) fn drain(&self, out: &mut Vec<TouchEvent>) {
        let mut q = self.queue.lock().unwrap_or_else(|e| e.into_inner());
        out.clear();
        out.append(&mut q);
    }
}

impl EventHandler for TouchFeed {
    fn handle_collision_event(
        &self,
        _bodies: &RigidBodySet,
        _colliders: &ColliderSet,
        event: CollisionEvent,
        _contact_pair: Option<&ContactPair>,
    ) {
        self.push(event);
    }

    fn handle_contact_force_event(
        &self,
        _dt: Real,
        _bodies: &RigidBodySet,
        _colliders: &ColliderSet,
        _contact_pair: &ContactPair,
        _total_force_magnitude: Real,
    ) {
    }

    fn handle_soft_body_tear_event(&self, _soft_bodies: &SoftBodySet, _event: &SoftBodyTearEvent) {}
}

impl Coherence {
    /// The tracking in effect at the last update ([`Tracking::Proximity`] before the
    /// first).
    pub fn tracking(&self) -> Tracking {
        self.tracking.unwrap_or(Tracking::Proximity)
    }

    /// Whether the layer's event handler was given to the last analysed step (see
    /// [`Tracking`]).
    pub fn feed_connected(&self) -> bool {
        self.feed_connected
    }

    pub(crate) fn set_feed_connected(&mut self, connected: bool) {
        self.feed_connected = connected;
    }

    /// The tracking asked for (in effect while nothing needs every pair read: see
    /// [`Tracking`]).
    pub fn requested_tracking(&self) -> Tracking {
        self.tracking_requested
    }

    pub(crate) fn request_tracking(&mut self, tracking: Tracking) {
        self.tracking_requested = tracking;
    }

    /// The colliders the layer gave `COLLISION_EVENTS`, by raw handle.
    pub(crate) fn touch_flagged(&self) -> &BTreeMap<(u32, u32), ColliderHandle> {
        &self.touch_flagged
    }

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
            self.touch_flag_colliders = usize::MAX;
            return;
        }
        let budget = self.verify_budget();
        let flagged = &mut self.touch_flagged;
        let rescan = &mut self.touch_rescan;
        // Read first: `ColliderSet::get_mut` marks a collider modified for Rapier's
        // next step, so only a collider that needs the flag is written.
        let mut flag = |c: ColliderHandle, colliders: &mut ColliderSet| {
            let lacks = colliders
                .get(c)
                .is_some_and(|co| !co.active_events().contains(ActiveEvents::COLLISION_EVENTS));
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

    /// Applies the step's touch transitions to the physical edges (touching tracking).
    pub(super) fn apply_touch_events(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        events: &[TouchEvent],
    ) {
        let step = self.step;
        let mut changed: Vec<EdgeId> = Vec::new();
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
        let step = self.step;
        let mut counts: BTreeMap<EdgeId, u32> = BTreeMap::new();
        // Per edge counted: the touching pair to name (`Edge::colliders`): the one
        // named already if it touches, else the one with the smallest handles.
        let mut names: BTreeMap<EdgeId, [ColliderHandle; 2]> = BTreeMap::new();
        // The collider pairs that sent `Started` this step; a touching pair counted
        // here without one may have begun before its colliders were flagged.
        let key = |a: ColliderHandle, b: ColliderHandle| {
            let (a, b) = (a.into_raw_parts(), b.into_raw_parts());
            (a.min(b), a.max(b))
        };
        let started: std::collections::HashSet<_> = events
            .iter()
            .filter(|e| e.started)
            .map(|e| key(e.c1, e.c2))
            .collect();
        let mut pre_flag: Vec<NodeId> = Vec::new();
        // A pair between two rescanned nodes is met from both: counted once.
        let mut seen: std::collections::BTreeSet<((u32, u32), (u32, u32))> = Default::default();
        let mut visit = |this: &mut Self, graph: &mut ContactGraph, pair: &ContactPair| {
            if !all
                && !seen.insert((
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
            if pair.has_any_active_contact() {
                if let Some(e) = pairs::physical_edge_for(graph, n1, n2, step) {
                    *counts.entry(e).or_insert(0) += 1;
                    if let Some(edge) = graph.edge(e) {
                        let named = if edge.a == n1 {
                            [pair.collider1, pair.collider2]
                        } else {
                            [pair.collider2, pair.collider1]
                        };
                        names
                            .entry(e)
                            .and_modify(|n| {
                                if edge.prefers_name(named, *n) {
                                    *n = named;
                                }
                            })
                            .or_insert(named);
                    }
                }
                if !started.contains(&key(pair.collider1, pair.collider2)) {
                    pre_flag.extend([n1, n2]);
                }
            }
        };
        // The nodes whose every pair is read (the owners of the late colliders), so
        // that their edges are counted in full.
        let mut nodes: Vec<NodeId> = Vec::new();
        if all {
            for pair in view.narrow_phase.contact_pairs() {
                visit(self, graph, pair);
            }
        } else {
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
                            visit(self, graph, pair);
                        }
                    }
                }
                nodes.append(&mut next);
                nodes.sort_unstable();
                next = std::mem::take(&mut self.stale);
            }
        }
        // The edges to set: every physical edge with `all`, else those of the nodes
        // read; each counts 0 unless counted.
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
        let mut changed = Vec::new();
        // Edges this step's events changed already: settled again with the count read
        // here, which wins (after a switch from proximity tracking, or for a collider
        // flagged late, the events alone may have counted from a stale start).
        let mut again = Vec::new();
        for eid in targets {
            let want = counts.get(&eid).copied().unwrap_or(0);
            let name = names.get(&eid).copied();
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
                self.begin_touch_update(graph, eid, &mut changed);
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
        // Bodies newly holding a pair that may have begun before the flag: their
        // disabled-collider signature starts from the set read now.
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

    /// Starts this step's update of a physical edge in touching tracking (once per
    /// step): shifts its state to `e_old`, keeping its count of touching collider
    /// pairs.
    fn begin_touch_update(
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
