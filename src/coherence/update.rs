//! The analysis of one step (paper §3, Fig. 11): node upkeep, the round-robin
//! verification, removal of nodes, and the order in which the phases run.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::WorldView;

use super::*;

impl Coherence {
    /// Checks a few nodes and Rapier body and collider slots per step, round robin: a
    /// node whose object is gone is removed, a body whose type changed in place gets
    /// its kind, and a body without node gets one. It makes the graph consistent,
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

    /// Reports the edges a kind change dropped (ended, with `Vanished` marks) and
    /// regroups their ends.
    pub(crate) fn take_dropped(&mut self, graph: &mut ContactGraph, groups: &mut Groups) {
        let step = self.step;
        graph.drop_disallowed_edges();
        for n in std::mem::take(&mut graph.evicted) {
            self.remove_node(graph, groups, n);
        }
        for n in std::mem::take(&mut graph.kind_changed) {
            // A held body the user gave another type: Rapier computes its kept
            // contacts again (and reports them started): they are counted again.
            if graph.node(n).is_some_and(|n| n.is_held() && !n.kind().is_insulator()) {
                self.stale.push(n);
            }
            self.kind_changes += 1;
            groups.disturb(graph, n);
        }
        for mut e in std::mem::take(&mut graph.dropped) {
            groups.disturb(graph, e.a);
            groups.disturb(graph, e.b);
            if e.cache.proximity {
                e.cache.begin_update(true);
                e.updated_step = step;
                self.removed_edges.push(e);
            }
        }
    }

    pub(super) fn remove_node(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        id: NodeId,
    ) {
        let Some(node) = graph.node(id) else { return };
        let record = RemovedNode {
            id,
            kind: node.kind,
            source: node.source,
        };
        if let Some(g) = node.group {
            groups.dissolve(graph, g);
        }
        // Neighbours lose an edge: their groups must be rebuilt.
        let neighbours: Vec<NodeId> = graph.neighbors(id).map(|(m, _, _)| m).collect();
        for m in neighbours {
            groups.disturb(graph, m);
        }
        let step = self.step;
        for mut e in graph.remove_node(id) {
            e.cache.begin_update(true);
            e.updated_step = step;
            self.removed_edges.push(e);
        }
        self.removed_nodes.push(record);
    }

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
        // Saturating: a step count near u64::MAX comes only from restored bytes.
        self.step = self.step.saturating_add(1);
        let tracking = if touch.is_some() {
            Tracking::Touching
        } else {
            Tracking::Proximity
        };
        // The first update under touching tracking counts as a switch (its touching
        // pairs sent no `Started`); back to proximity, every pair is read again.
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
        self.witness.record(view.bodies, view.islands);

        // 1. Node upkeep.
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
        if self.idle_step(graph, view, screen, touch, switched || requested, &resized) {
            // Nothing awake now or at the last update, no transition, nothing asked
            // for, created or removed, no trigger: the full update would read nothing
            // and change nothing (its walk, `awake_prev` and counts are empty, as
            // they are already). Only the kind changes' drops are taken.
            self.take_dropped(graph, groups);
            return;
        }
        for h in view.islands.active_bodies() {
            let fixed = view.bodies.get(h).is_some_and(|b| b.is_fixed());
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
            let Some(id) = nodes::ensure_body_node(graph, view, h, &mut self.created) else {
                continue;
            };
            self.mark_refreshed(graph, view, id, h, true);
        }
        // Bodies that fell asleep, turned fixed or were disabled (awake at the last
        // update), the nodes the logic layer asks for (rule members of any kind, bodies
        // made passive or active), and bodies whose colliders were added or removed (a
        // fixed body losing its collider inside a trigger: nobody else would notice).
        let prev = std::mem::take(&mut self.awake_prev);
        for &id in prev.iter().chain(screen.force.iter()).chain(resized.iter()) {
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

        // 2. Edge insertion and marks. When at least half of the moving bodies were
        // refreshed, one sequential pass over Rapier's pair array beats walking each
        // body's adjacency (which reaches every pair twice); otherwise the walk keeps
        // the cost proportional to the refreshed bodies.
        let walk = std::mem::take(&mut self.walk);
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
            self.apply_touch_events(graph, view, screen, events);
            // A body disabled (made passive, or by Rapier's quarantine) loses its
            // pairs without a `Stopped`; one enabled again regains them; a body whose
            // collider was removed gets a `Stopped` that names a collider no longer
            // in Rapier (its owner unknown once the counts changed): their touching
            // pairs are counted again.
            self.stale.extend_from_slice(&self.passive_changed);
            self.stale.extend_from_slice(&resized);
            let late = std::mem::take(&mut self.touch_rescan);
            if requested || switched {
                self.stale.clear();
                self.rescan_touching(graph, view, screen, events, &[], true);
            } else if !late.is_empty() || !self.stale.is_empty() {
                self.rescan_touching(graph, view, screen, events, &late, false);
            }
            self.counters.bodies = walk.len();
        } else if scan {
            self.scan_all_pairs(graph, view, screen);
            self.counters.bodies = walk.len();
        } else {
            for &me in &walk {
                self.walk_pairs(graph, view, screen, me);
            }
        }
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

        // 3. Vanished edges and obsolete removal, for the refreshed bodies and the
        // triggers they carry.
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
        let physical = touch.is_none();
        if !scan {
            for &me in &walk {
                if physical || graph.node(me).is_some_and(|n| n.geometric_edges > 0) {
                    self.retire_unreached(graph, view, me, physical);
                }
            }
        }
        for &me in &triggers {
            self.retire_unreached(graph, view, me, physical);
        }
        self.triggers = triggers;

        // Groups change only where structure changed: a contact started or ended (a
        // merge or a split; an edge removed from the graph leaves its group by the
        // graph's own record), a body woke or slept (its group's sleep), became passive
        // (above), changed kind or appeared (in `take_dropped` and node upkeep: those
        // are rebuilt). A refreshed body without a group (first seen, released) is a
        // root too.
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
        for &me in &walk {
            let ungrouped = graph
                .node(me)
                .is_some_and(|n| n.kind.is_simulated() && n.group.is_none() && !n.passive);
            if ungrouped || self.passive_changed.contains(&me) {
                groups.disturb(graph, me);
            }
        }
        self.take_dropped(graph, groups);
        self.walk = walk;
        // Each edge is pushed once (guarded by its walk stamp) and no touched edge is
        // removed in the same step, so the list needs no sorting or filtering: its
        // order is Rapier's pair order, then the vanished edges, which is deterministic.
        debug_assert!(self.touched.iter().all(|&e| graph.edge(e).is_some()));
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

    /// Refreshes one node whatever its state, if not done this step: a body's pairs are
    /// read (it joins the walk), static geometry's too, a trigger is read from its side.
    /// A node whose object is gone is removed. Containers and logical nodes: nothing.
    pub(super) fn refresh_node(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        id: NodeId,
    ) {
        let step = self.step;
        let Some(node) = graph.node(id) else { return };
        if node.seen_step == step {
            return;
        }
        match node.source {
            NodeSource::Body(h) if view.bodies.contains(h) => {
                let _ = nodes::ensure_body_node(graph, view, h, &mut self.created);
                self.mark_refreshed(graph, view, id, h, false);
            }
            NodeSource::StaticCollider(c) if nodes::is_static_collider_node(view, c) => {
                if let Some(n) = graph.node_mut(id) {
                    n.seen_step = step;
                }
                self.walk.push(id);
            }
            NodeSource::Sensor(c) if view.colliders.get(c).is_some_and(|c| c.is_sensor()) => {
                self.pending_triggers.push(id);
            }
            NodeSource::Body(_) | NodeSource::StaticCollider(_) | NodeSource::Sensor(_) => {
                self.remove_node(graph, groups, id);
            }
            NodeSource::Container(_) | NodeSource::Layer(_) => {}
        }
    }

    pub(super) fn mark_refreshed(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        id: NodeId,
        h: RigidBodyHandle,
        awake: bool,
    ) {
        let step = self.step;
        let rb = view.bodies.get(h);
        let finite = rb.is_some_and(|rb| {
            rb.position().translation.is_finite() && rb.position().rotation.is_finite()
        });
        let enabled = rb.is_some_and(|rb| rb.is_enabled());
        let sig = rb.map_or(0, |rb| nodes::colliders_sig(rb.colliders()));
        let resigned = graph
            .node(id)
            .is_some_and(|n| n.seen_step != step && n.collider_sig != 0 && n.collider_sig != sig);
        if resigned {
            self.colliders_moved(graph, view, id, h);
        }
        if let Some(n) = graph.node_mut(id) {
            if n.seen_step == step {
                return;
            }
            // Under touching tracking, a collider of this body disabled or enabled
            // again in place: its pairs went or come without a `Stopped` Rapier would
            // send (those of pairs touching before the layer flagged them), so they
            // are counted again. Proximity tracking reads the pairs of refreshed
            // bodies anyway.
            // Only bodies with such pairs pay for the signature (`Node::pre_flag_touch`):
            // every other touching pair of theirs sent `Started`, so Rapier sends
            // its `Stopped` too.
            let disabled = match (rb, self.tracking()) {
                (Some(rb), Tracking::Touching) if n.pre_flag_touch => {
                    Some(nodes::disabled_sig(view, rb.colliders()))
                }
                _ => None,
            };
            if let Some(disabled) = disabled.filter(|&d| d != n.disabled_sig) {
                n.disabled_sig = disabled;
                self.stale.push(id);
            }
            n.collider_sig = sig;
            let was_passive = n.passive;
            n.seen_step = step;
            let was_awake = n.awake;
            n.awake = awake && !matches!(n.kind, NodeKind::Fixed);
            if was_awake != n.awake && n.group.is_some() {
                self.awake_flips.push(id);
            }
            n.non_finite = !finite;
            n.passive = !enabled
                && self
                    .parking
                    .binary_search_by_key(&h.into_raw_parts(), |p| p.into_raw_parts())
                    .is_err();
            if was_passive != n.passive {
                self.passive_changed.push(id);
            }
            // Sleep events report changes of a simulated, non-passive body's state
            // against the last reported one: a body created this step starts (no
            // event), a passive spell or a time as a fixed body reports nothing, and
            // the events alternate.
            if n.kind.is_simulated() && !n.passive {
                match n.reported_awake {
                    None => n.reported_awake = Some(n.awake),
                    Some(r) if r != n.awake && n.born_step != step => {
                        n.reported_awake = Some(n.awake);
                        self.sleep_changes.push((id, n.awake));
                    }
                    Some(_) => n.reported_awake = Some(n.awake),
                }
            }
            if let Some(rb) = rb {
                self.walk_sensors
                    .extend(sensors_of(view, rb).map(|c| (id, c)));
            }
            self.walk.push(id);
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
    fn colliders_moved(
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
    fn same_world(&mut self, view: &WorldView) -> bool {
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

/// The body's sensor colliders: the look that gives a collider turned into a sensor
/// in place its trigger in the same step. O(the body's colliders).
fn sensors_of<'a>(
    view: &'a WorldView,
    rb: &'a rapier3d::prelude::RigidBody,
) -> impl Iterator<Item = ColliderHandle> + 'a {
    rb.colliders()
        .iter()
        .copied()
        .filter(|&c| view.colliders.get(c).is_some_and(|c| c.is_sensor()))
}
