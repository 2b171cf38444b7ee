//! Refreshing a node: reading its state from Rapier (kind, awake, passive, sleep
//! events) and putting it on the step's walk, whose pairs are read.

use rapier3d::prelude::{ColliderHandle, RigidBody, RigidBodyHandle};

use crate::graph::{ContactGraph, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::util::rapier::pose_is_finite;
use crate::WorldView;

use super::*;

impl Coherence {
    /// Refreshes one node whatever its state, if not done this step: a body's pairs are
    /// read (it joins the walk), static geometry's too, a trigger is read from its side.
    /// A node whose object is gone is removed. Containers and logical nodes: nothing.
    /// O(1) for a node refreshed already (the common case of the bodies awake at the
    /// last update), checked here before the call that does the work.
    #[inline]
    pub(super) fn refresh_node(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        id: NodeId,
    ) {
        let step = self.step;
        if graph.node(id).is_some_and(|n| n.seen_step != step) {
            self.refresh_unseen(graph, groups, view, id);
        }
    }

    /// [`Self::refresh_node`] for a node in the graph not refreshed this step.
    fn refresh_unseen(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        view: &WorldView,
        id: NodeId,
    ) {
        let step = self.step;
        let Some(node) = graph.node(id) else { return };
        let source = node.source;
        if let NodeSource::Body(h) = source {
            if let Some(rb) = view.bodies.get(h) {
                nodes::ensure_node_of(graph, view, h, rb, &mut self.created);
                self.mark_refreshed(graph, view, id, h, rb, false);
                return;
            }
        }
        match source {
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

    /// Reads body `h` (`rb`, looked up by the caller) into its node `id` and puts the
    /// node on the step's walk, with its sensor colliders, unless it is on it
    /// already. O(the body's colliders).
    pub(super) fn mark_refreshed(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        id: NodeId,
        h: RigidBodyHandle,
        rb: &RigidBody,
        awake: bool,
    ) {
        let step = self.step;
        let finite = pose_is_finite(rb.position());
        let passive = self.is_passive(rb.is_enabled(), h);
        let sig = nodes::colliders_sig(rb.colliders());
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
            let disabled = match self.tracking() {
                Tracking::Touching if n.pre_flag_touch => {
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
            n.passive = passive;
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
            self.walk_sensors
                .extend(sensors_of(view, rb).map(|c| (id, c)));
            self.walk.push(id);
        }
    }

    /// Whether a body counts as passive: not `enabled` in Rapier, but not disabled by
    /// the speed-ups for the one step a held body spends on its way out of Rapier's
    /// active set. O(log parking).
    pub(super) fn is_passive(&self, enabled: bool, h: RigidBodyHandle) -> bool {
        !enabled
            && self
                .parking
                .binary_search_by_key(&h.into_raw_parts(), |p| p.into_raw_parts())
                .is_err()
    }
}

/// The body's sensor colliders: the look that gives a collider turned into a sensor
/// in place its trigger in the same step. O(the body's colliders).
pub(super) fn sensors_of<'a>(
    view: &'a WorldView,
    rb: &'a rapier3d::prelude::RigidBody,
) -> impl Iterator<Item = ColliderHandle> + 'a {
    rb.colliders()
        .iter()
        .copied()
        .filter(|&c| view.colliders.get(c).is_some_and(|c| c.is_sensor()))
}
