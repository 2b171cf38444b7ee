//! Trigger volumes (paper Table 1, V): which bodies are inside each sensor, from
//! Rapier's intersection pairs, and the Enter/Exit marks.

use rapier3d::prelude::ColliderHandle;

use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeSource};
use crate::WorldView;

use super::*;

impl Coherence {
    /// Reads the intersection pairs of one trigger (its sensor collider) into
    /// geometric edges, and marks the trigger as read this step.
    pub(super) fn walk_trigger(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        t: NodeId,
    ) {
        let step = self.step;
        let Some(node) = graph.node_mut(t) else {
            return;
        };
        let NodeSource::Sensor(sensor) = node.source else {
            return;
        };
        if node.seen_step == step {
            return;
        }
        node.seen_step = step;
        self.triggers.push(t);
        if let Some(c) = view.colliders.get(sensor) {
            self.trigger_states.insert(t, TriggerState::of(c));
        }
        for (c1, c2, intersecting) in view.narrow_phase.intersection_pairs_with(sensor) {
            let oc = if c1 == sensor { c2 } else { c1 };
            if view.colliders.get(oc).is_none_or(|c| c.is_sensor()) {
                continue; // trigger–trigger pairs are ignored (Table 2)
            }
            self.counters.collider_pairs += 1;
            if intersecting {
                self.feed_trigger(graph, view, screen, t, oc);
            }
        }
    }

    /// Reads again the triggers not read this step whose sensor collider changed since
    /// their last read (see [`TriggerState`]), and forgets removed triggers.
    /// O(triggers).
    pub(super) fn read_changed_triggers(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
    ) {
        if self.trigger_states.is_empty() {
            return;
        }
        let step = self.step;
        let mut stale = Vec::new();
        let mut changed = Vec::new();
        for (&t, state) in &self.trigger_states {
            let Some(node) = graph.node(t) else {
                stale.push(t);
                continue;
            };
            let NodeSource::Sensor(c) = node.source else {
                stale.push(t);
                continue;
            };
            if node.seen_step == step {
                continue;
            }
            // A removed sensor's node goes with the node upkeep.
            if view
                .colliders
                .get(c)
                .is_some_and(|c| TriggerState::of(c) != *state)
            {
                changed.push(t);
            }
        }
        for t in stale {
            self.trigger_states.remove(&t);
        }
        for t in changed {
            if let Some(NodeSource::Sensor(c)) = graph.node(t).map(|n| n.source) {
                let _ = nodes::ensure_trigger_node(graph, view, c, &mut self.created);
            }
            self.walk_trigger(graph, view, screen, t);
        }
    }

    /// Reads the intersection pairs of a body's (or static collider's) non-sensor
    /// colliders with triggers not read this step.
    pub(super) fn walk_body_sensors(
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
        for &ch in &colliders {
            if view.colliders.get(ch).is_none_or(|c| c.is_sensor()) {
                continue;
            }
            for (c1, c2, intersecting) in view.narrow_phase.intersection_pairs_with(ch) {
                let sensor = if c1 == ch { c2 } else { c1 };
                let known = self.created.len();
                let Some(t) = nodes::ensure_trigger_node(graph, view, sensor, &mut self.created)
                else {
                    continue;
                };
                if self.created.len() != known {
                    // A trigger first seen here: read all of it from its side now.
                    self.walk_trigger(graph, view, screen, t);
                }
                if graph.node(t).is_some_and(|n| n.seen_step == step) {
                    continue; // read from the trigger's side
                }
                self.counters.collider_pairs += 1;
                if intersecting {
                    self.feed_trigger(graph, view, screen, t, ch);
                }
            }
        }
        self.scratch_colliders = colliders;
    }

    /// Adds one intersecting sensor–collider pair to the geometric edge of the trigger
    /// and the collider's owner.
    pub(super) fn feed_trigger(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        screen: &Screen,
        t: NodeId,
        body_collider: ColliderHandle,
    ) {
        let step = self.step;
        let Some(b) = self.owner_of(graph, view, body_collider) else {
            return;
        };
        let sensor = match graph.node(t).map(|n| n.source) {
            Some(NodeSource::Sensor(c)) => c,
            _ => return,
        };
        if !screen.admits_pair(graph, view, (t, b), (sensor, body_collider), true) {
            return;
        }
        let Some(eid) = graph.ensure_edge(t, b, EdgeKind::Geometric, step) else {
            return;
        };
        let Some(e) = graph.edge_mut(eid) else { return };
        if e.kind != EdgeKind::Geometric {
            return;
        }
        if e.walk_stamp != step {
            e.cache.begin_update(false);
            e.begin_naming(false);
            e.walk_stamp = step;
            e.updated_step = step;
            self.touched.push(eid);
            self.counters.edges += 1;
        }
        e.cache.proximity = true;
        e.cache.collider_pairs += 1;
        // The pair the trigger's events name (`Edge::colliders`), *A*'s first.
        let named = if e.a == t {
            [sensor, body_collider]
        } else {
            [body_collider, sensor]
        };
        e.meet_pair(named, true);
    }
}
