//! The analysis of one step (paper §3, Fig. 11): [`Coherence::update`] runs its
//! phases in order, each a function here (node upkeep, the walk, edge insertion and
//! marks, triggers, vanished edges, group changes), with the idle test. Node removal
//! is `removal.rs`, the round-robin verification `verify.rs`, refreshing a node
//! `refresh.rs`, the collider-owner cache and the world's identity `owners.rs`.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::WorldView;

use super::refresh::sensors_of;
use super::*;

impl Coherence {
    /// Runs the analysis of one step. `step` must grow by one per call. `screen`
    /// carries the logical test of Fig. 4 (rules) and the nodes the logic layer wants
    /// refreshed even if asleep (rule members, bodies made passive or active).
    /// An idle step ([`Self::idle_step`]) stops after the verification.
    pub(crate) fn update(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        screen: &Screen,
        touch: Option<&[TouchEvent]>,
    ) {
        // 0. A new step: the step's lists emptied, the tracking in effect noted.
        let (tracking, switched) = self.begin_update(graph, view, touch);
        if touch.is_none() {
            // Bodies given back have their pairs read again by the walk.
            self.restale_released();
        }
        // 1. Node upkeep: a full scan when the counts changed or on request, and the
        // round-robin verification.
        let (requested, resized) = self.upkeep_nodes(graph, groups, view, tracking);
        if self.idle_step(graph, view, screen, touch, switched || requested, &resized) {
            // Nothing awake now or at the last update, no transition, nothing asked
            // for, created or removed, no trigger: the full update would read nothing
            // and change nothing (its walk, `awake_prev` and counts are empty, as
            // they are already). Only the kind changes' drops are taken.
            self.take_dropped(graph, groups);
            return;
        }
        // 2. The walk: the bodies awake now or at the last update, those asked for,
        // stale and new (every node on request).
        self.refresh_nodes(graph, groups, view, screen, touch, requested, &resized);
        let walk = std::mem::take(&mut self.walk);
        // 3. Edge insertion and marks (§3.1–3.2, Figs. 3 and 5).
        let full = requested || switched;
        let scan = self.insert_edges(graph, view, screen, touch, &walk, full, &resized);
        // 4. Trigger volumes.
        self.read_triggers(graph, view, screen, &walk);
        // 5. Vanished edges and obsolete removal (§3.1).
        self.retire_vanished(graph, view, touch.is_none(), scan, &walk);
        // 6. What the groups must redo.
        self.mark_group_changes(graph, groups, &walk);
        self.take_dropped(graph, groups);
        self.walk = walk;
        // Each edge is pushed once (guarded by its walk stamp) and no touched edge is
        // removed in the same step, so the list needs no sorting or filtering: its
        // order is Rapier's pair order, then the vanished edges, which is deterministic.
        debug_assert!(self.touched.iter().all(|&e| graph.edge(e).is_some()));
    }

    /// Phase 0: a new step's index, the step's lists emptied, the tracking in effect
    /// and whether it switched (the first update under touching tracking counts as a
    /// switch: its touching pairs sent no `Started`; back to proximity, every pair is
    /// read again). O(1).
    fn begin_update(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        touch: Option<&[TouchEvent]>,
    ) -> (Tracking, bool) {
        // Saturating: a step count near u64::MAX comes only from restored bytes.
        self.step = self.step.saturating_add(1);
        let tracking = if touch.is_some() {
            Tracking::Touching
        } else {
            Tracking::Proximity
        };
        let switched = self.tracking != Some(tracking);
        if self.tracking == Some(Tracking::Touching) && tracking == Tracking::Proximity {
            self.force_full_sync = true;
        }
        self.tracking = Some(tracking);
        let step = self.step;
        graph.clock = step;
        self.touched.clear();
        self.removed_edges.clear();
        self.removed_nodes.clear();
        self.created.clear();
        self.sleep_changes.clear();
        self.passive_changed.clear();
        self.awake_flips.clear();
        self.kind_changes = 0;
        self.counters = WalkCounters {
            unseen_step: std::mem::take(&mut self.unseen_step),
            ..WalkCounters::default()
        };
        self.witness.record(view.bodies, view.islands, view.dt);
        (tracking, switched)
    }

    /// Phase 1: node upkeep. A full scan of bodies and colliders when their counts
    /// changed, on request, or for another world; then the round-robin verification.
    /// Returns whether a full read was requested and the bodies whose collider count
    /// changed. O(verify budget), O(bodies + colliders) on a full scan.
    fn upkeep_nodes(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        tracking: Tracking,
    ) -> (bool, Vec<NodeId>) {
        self.pending_triggers.clear();
        let counts_changed = self.known_bodies != Some(view.bodies.len())
            || self.known_colliders != view.colliders.len();
        // Another world with the same counts (one layer stepping two worlds) is read
        // in full, as after `request_full_sync`. Under touching tracking also with
        // other counts: the other world's touching pairs sent no `Started` to the
        // layer (proximity tracking reads the pairs of the resynchronised nodes).
        if !self.same_world(view) && (!counts_changed || tracking == Tracking::Touching) {
            self.force_full_sync = true;
        }
        let requested = self.force_full_sync;
        let mut resized = Vec::new();
        if counts_changed || requested {
            self.force_full_sync = false;
            // The lookup caches may name colliders that changed owner or slot.
            self.owners.clear();
            self.pair_slots.clear();
            let gone = nodes::full_sync(graph, view, &mut self.created, &mut resized);
            for id in gone {
                self.remove_node(graph, groups, id);
            }
            self.known_bodies = Some(view.bodies.len());
            self.known_colliders = view.colliders.len();
        }
        self.verify_some(graph, groups, view);
        self.walk.clear();
        self.walk_sensors.clear();
        self.integrated = 0;
        (requested, resized)
    }

    /// Phase 2: refreshes the bodies Rapier integrated, those awake at the last
    /// update, those the logic layer asks for, stale owners (proximity tracking), the
    /// nodes created this step and, on request, every node. O(refreshed nodes), O(nodes)
    /// on request.
    #[allow(clippy::too_many_arguments)]
    // Long: collects the nodes to refresh from each source the doc lists, then refreshes them once.
    fn refresh_nodes(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        screen: &Screen,
        touch: Option<&[TouchEvent]>,
        requested: bool,
        resized: &[NodeId],
    ) {
        for h in view.islands.active_bodies() {
            // Each body is looked up once: its node and refresh read it from here.
            let rb = view.bodies.get(h);
            let fixed = rb.is_some_and(|b| b.is_fixed());
            if !fixed {
                self.integrated += 1;
            }
            // Rapier keeps a body turned fixed in its active set: once the graph has it
            // as fixed, there is nothing to refresh (it does not move).
            if fixed
                && graph
                    .node_of_body(h)
                    .and_then(|n| graph.node(n))
                    .is_some_and(|n| n.kind == NodeKind::Fixed && n.seen_step != 0)
            {
                continue;
            }
            let Some(rb) = rb else { continue };
            let id = nodes::ensure_node_of(graph, view, h, rb, &mut self.created);
            self.mark_refreshed(graph, view, id, h, rb, true);
        }
        // Bodies that fell asleep, turned fixed or were disabled (awake at the last
        // update), the nodes the logic layer asks for (rule members of any kind, bodies
        // made passive or active), bodies whose colliders were added or removed (a
        // fixed body losing its collider inside a trigger: nobody else would notice),
        // and those the verification found disabled or enabled in place.
        let prev = std::mem::take(&mut self.awake_prev);
        let recheck = std::mem::take(&mut self.recheck);
        for &id in prev
            .iter()
            .chain(screen.force.iter())
            .chain(resized.iter())
            .chain(recheck.iter())
        {
            self.refresh_node(graph, groups, view, id);
        }
        // Owners of colliders changed in place (found by a refresh above, the
        // round-robin check or the last update's lookups): their pairs are read again,
        // until no refresh finds another. Under touching tracking their touching pairs
        // are counted again instead (below).
        if touch.is_none() {
            while let Some(id) = self.stale.pop() {
                self.refresh_node(graph, groups, view, id);
            }
        }
        // Nodes created this step are refreshed once whatever their state: a body
        // Rapier put to sleep in its very first step (a huge dt), or new static
        // geometry, still has its pairs read.
        for i in 0..self.created.len() {
            let id = self.created[i];
            self.refresh_node(graph, groups, view, id);
        }
        // A requested full sync refreshes everything: the user changed a sleeping or
        // fixed body (or static geometry) in place, which no Rapier list tells. O(nodes
        // + pairs), on request only.
        if requested {
            let all: Vec<NodeId> = graph.nodes().map(|(id, _)| id).collect();
            for id in all {
                self.refresh_node(graph, groups, view, id);
            }
        }
        self.awake_prev = prev;
        self.awake_prev.clear();
        for &id in &self.walk {
            if graph.node(id).is_some_and(|n| n.awake) {
                self.awake_prev.push(id);
            }
        }
        self.take_dropped(graph, groups);
        // Nodes created this step (e.g. a new fixed body) have no pairs walked from
        // them, but their pairs with awake bodies are walked from the other side.
        for i in 0..self.created.len() {
            let id = self.created[i];
            groups.disturb(graph, id);
        }
    }

    /// Phase 3: edge insertion and marks. Under touching tracking from Rapier's
    /// events (the touching pairs read in full on a switch or request, and for the
    /// nodes that need it); under proximity tracking, when at least half of the moving
    /// bodies were refreshed, one sequential pass over Rapier's pair array (it beats
    /// walking each body's adjacency, which reaches every pair twice), otherwise the
    /// walk, so that the cost stays proportional to the refreshed bodies. Returns
    /// whether the pass over all pairs ran. O(events) or O(refreshed bodies' pairs),
    /// O(pairs) for the pass.
    #[allow(clippy::too_many_arguments)]
    fn insert_edges(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        touch: Option<&[TouchEvent]>,
        walk: &[NodeId],
        full: bool,
        resized: &[NodeId],
    ) -> bool {
        let moving = graph.count_of_kind(NodeKind::Dynamic)
            + graph.count_of_kind(NodeKind::Link)
            + graph.count_of_kind(NodeKind::Kinematic);
        let scan = match self.scan {
            // Nothing refreshed (everything asleep or held): nothing to scan.
            ScanPolicy::Auto => !walk.is_empty() && 2 * walk.len() >= moving,
            ScanPolicy::Scan => true,
            ScanPolicy::Walk => false,
        };
        // Touching tracking reads no pair: Rapier's events say what changed (the
        // touching pairs are read once when it starts, on request, and for colliders
        // flagged late).
        let scan = scan && touch.is_none();
        if let Some(events) = touch {
            let thawed = self.thaw_edges(graph);
            // A full read sets every touching pair below: the events would only be
            // applied to be read over (the first update under touching tracking).
            let apply = if full { &[][..] } else { events };
            self.apply_touch_events(graph, view, screen, apply, thawed);
            // A body disabled (made passive, or by Rapier's quarantine) loses its
            // pairs without a `Stopped`; one enabled again regains them; a body whose
            // collider was removed gets a `Stopped` that names a collider no longer
            // in Rapier (its owner unknown once the counts changed): their touching
            // pairs are counted again.
            self.stale.extend_from_slice(&self.passive_changed);
            self.stale.extend_from_slice(resized);
            // New nodes whose pairs may be older than the node: a collider a removed
            // body left behind (static geometry now) touches what it touched, and
            // Rapier sends no `Started` for it.
            let created = self.created.iter().copied().filter(|&n| {
                graph
                    .node(n)
                    .is_some_and(|n| matches!(n.source, NodeSource::StaticCollider(_)))
            });
            self.stale.extend(created);
            let mut late = std::mem::take(&mut self.touch_rescan);
            // Colliders of new nodes that lack the layer's flag (inserted while as many
            // were removed, so the count the pre-step compares did not change): their
            // touching pairs are read now, and the next pre-step flags every collider.
            // So are those of new nodes flagged by someone else: a body another layer
            // stepped into contact, and to sleep, since this layer's last step leaves
            // its witness nothing to notice.
            let (unflagged, foreign) = self.unheard_of_created(graph, view);
            if !unflagged.is_empty() {
                self.force_touch_flags();
                late.extend(unflagged);
            }
            late.extend(foreign);
            if full {
                self.stale.clear();
                self.rescan_touching(graph, view, screen, events, &[], true);
            } else if !late.is_empty() || !self.stale.is_empty() {
                self.rescan_touching(graph, view, screen, events, &late, false);
            }
            self.counters.bodies = walk.len();
        } else if scan {
            self.touch_rescan.clear();
            self.scan_all_pairs(graph, view, screen);
            self.counters.bodies = walk.len();
        } else {
            // Proximity tracking reads the pairs itself: colliders flagged late need no
            // rescan.
            self.touch_rescan.clear();
            for &me in walk {
                self.walk_pairs(graph, view, screen, me);
            }
        }
        scan
    }

    /// Phase 4: trigger volumes. O(the refreshed and new bodies' colliders + the
    /// triggers read).
    fn read_triggers(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        walk: &[NodeId],
    ) {
        let step = self.step;
        // Trigger volumes: the triggers carried by refreshed bodies, the new ones and
        // those asked for are read from their side; then the triggers whose sensor
        // collider changed (moved with a fixed or passive carrier, or parentless);
        // then the refreshed and new bodies' colliders meet the other triggers. The
        // refreshed bodies' colliders are always looked at, so that a collider turned
        // into a sensor gets its trigger in the same step: O(their colliders).
        self.triggers.clear();
        // The walk's sensor colliders were noted as their bodies joined it
        // (`mark_refreshed`).
        let mut sensors: Vec<ColliderHandle> = self
            .walk_sensors
            .drain(..)
            .filter(|&(me, _)| {
                graph
                    .node(me)
                    .is_some_and(|n| matches!(n.source, NodeSource::Body(_)))
            })
            .map(|(_, c)| c)
            .collect();
        // Held bodies just parked are not refreshed (their frozen contacts stay), but
        // Rapier paired their colliders anew in this step: their sensor pairs are read.
        let parked: Vec<NodeId> = self
            .parked_now
            .iter()
            .filter_map(|&h| graph.node_of_body(h))
            .filter(|&n| graph.node(n).is_some_and(|n| n.seen_step != step))
            .collect();
        for &me in &parked {
            if let Some(NodeSource::Body(h)) = graph.node(me).map(|n| n.source) {
                if let Some(rb) = view.bodies.get(h) {
                    sensors.extend(sensors_of(view, rb));
                }
            }
        }
        let mut to_read: Vec<NodeId> = sensors
            .into_iter()
            .filter_map(|c| nodes::ensure_trigger_node(graph, view, c, &mut self.created))
            .collect();
        let created_now = self.created.clone();
        to_read.extend(
            created_now
                .iter()
                .copied()
                .filter(|&n| graph.node(n).is_some_and(|n| n.kind == NodeKind::Sensor)),
        );
        to_read.append(&mut self.pending_triggers);
        for t in to_read {
            self.walk_trigger(graph, view, screen, t);
        }
        self.read_changed_triggers(graph, view, screen);
        if graph.count_of_kind(NodeKind::Sensor) > 0 {
            for &me in walk.iter().chain(&created_now).chain(&parked) {
                self.walk_body_sensors(graph, view, screen, me);
            }
        }
    }

    /// Phase 5: vanished edges and obsolete removal, for the refreshed bodies and the
    /// triggers they carry. O(their edges), O(edges) after the pass over all pairs.
    fn retire_vanished(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        physical: bool,
        scan: bool,
        walk: &[NodeId],
    ) {
        let step = self.step;
        let triggers = std::mem::take(&mut self.triggers);
        if scan {
            // One sequential pass over the edge arena instead of each refreshed node's
            // edges (random access, every edge twice): the scan already cost O(pairs).
            self.dead.clear();
            for (eid, e) in graph.edges() {
                let dynamic = matches!(e.kind, EdgeKind::Physical | EdgeKind::Geometric);
                if !dynamic || e.walk_stamp == step {
                    continue;
                }
                let refreshed = |n| {
                    graph
                        .node(n)
                        .is_some_and(|n: &crate::Node| n.seen_step == step)
                };
                if refreshed(e.a) || refreshed(e.b) {
                    self.dead.push(eid);
                }
            }
            for i in 0..self.dead.len() {
                let eid = self.dead[i];
                self.retire(graph, view, eid);
            }
        }
        // Under touching tracking physical edges follow Rapier's events alone, so a
        // refreshed body's edges need a look only if one of them is geometric (it is
        // inside a trigger): an O(1) count per awake body, none without a trigger.
        if !scan {
            for &me in walk {
                if physical || graph.node(me).is_some_and(|n| n.geometric_edges > 0) {
                    self.retire_unreached(graph, view, me, physical);
                }
            }
        }
        for &me in &triggers {
            self.retire_unreached(graph, view, me, physical);
        }
        self.triggers = triggers;
    }

    /// Phase 6: tells the groups what changed. O(touched edges + walk).
    fn mark_group_changes(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        walk: &[NodeId],
    ) {
        // Groups change only where structure changed: a contact started or ended (a
        // merge or a split; an edge removed from the graph leaves its group by the
        // graph's own record), a body woke or slept (its group's sleep), became passive
        // (above), changed kind or appeared (in `take_dropped` and node upkeep: those
        // are rebuilt). A refreshed body without a group (first seen, released) joins
        // the groups around it.
        for &eid in &self.touched {
            let Some(e) = graph.edge(eid) else {
                continue;
            };
            if e.kind == EdgeKind::Physical && e.cache.touching != e.cache.touching_old {
                groups.touch_changed(eid, e.cache.touching);
            }
        }
        for &n in &self.awake_flips {
            groups.awake_changed(n);
        }
        for &me in walk {
            let ungrouped = graph
                .node(me)
                .is_some_and(|n| n.kind.is_simulated() && n.group.is_none() && !n.passive);
            if self.passive_changed.contains(&me) {
                groups.disturb(graph, me);
            } else if ungrouped {
                groups.membership_changed(me);
            }
        }
    }

    /// Whether this step is idle for the analysis (see [`Self::update`]): Rapier's
    /// active set is empty and was at the last update, no touch began or ended, no
    /// node is asked for, stale, new or removed, no held body is parked or unparked in
    /// this step, and the scene has no trigger (whose sensor colliders are compared
    /// with their last state each step). O(1).
    fn idle_step(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        screen: &Screen,
        touch: Option<&[TouchEvent]>,
        resync: bool,
        resized: &[NodeId],
    ) -> bool {
        !resync
            && resized.is_empty()
            && touch.is_none_or(|t| t.is_empty())
            && view.islands.num_active_bodies() == 0
            && self.awake_prev.is_empty()
            && screen.force.is_empty()
            && self.stale.is_empty()
            && self.recheck.is_empty()
            && self.touch_rescan.is_empty()
            && self.created.is_empty()
            && self.removed_nodes.is_empty()
            && self.parking.is_empty()
            && self.parked_now.is_empty()
            && self.trigger_states.is_empty()
            && graph.count_of_kind(NodeKind::Sensor) == 0
    }

    /// Retires the edges of `me` that no pair reached this step: its geometric edges,
    /// and with `physical` (proximity tracking) its physical ones too.
    /// O(its degree).
    fn retire_unreached(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        me: NodeId,
        physical: bool,
    ) {
        let step = self.step;
        self.dead.clear();
        let Some(node) = graph.node(me) else { return };
        for &eid in &node.edges {
            let Some(e) = graph.edge(eid) else { continue };
            let dynamic = match e.kind {
                EdgeKind::Physical => physical,
                EdgeKind::Geometric => true,
                _ => false,
            };
            if dynamic && e.walk_stamp != step {
                self.dead.push(eid);
            }
        }
        for i in 0..self.dead.len() {
            let eid = self.dead[i];
            self.retire(graph, view, eid);
        }
    }

    /// Sets the held bodies that are disabled for this step on their way out of
    /// Rapier's active set, and those enabled again for this step after it. O(n log n).
    pub(crate) fn set_parking(
        &mut self,
        parking: impl Iterator<Item = RigidBodyHandle>,
        parked_now: &[RigidBodyHandle],
    ) {
        self.parking.clear();
        self.parking.extend(parking);
        self.parking.sort_unstable_by_key(|h| h.into_raw_parts());
        self.parked_now.clear();
        self.parked_now.extend_from_slice(parked_now);
    }
}
