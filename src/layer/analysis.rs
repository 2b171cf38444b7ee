//! The layer's analysis seen from outside: what the last step read and found
//! ([`LayerAnalysis`], `layer.analysis()`), and how the analysis reads Rapier and
//! keeps its groups ([`LayerAnalysisMut`], `layer.analysis_mut()`). Diagnostics and
//! tuning, rarely needed by a program that only steps and asks by handle.

use rapier3d::prelude::{RigidBodyHandle, RigidBodySet};

use crate::coherence::{Coherence, RemovedNode, ScanPolicy};
use crate::events::EventBus;
use crate::graph::{Edge, EdgeId, NodeId};
use crate::Result;

use super::{ContactLayer, StepStats};

/// What the layer's last analysis read and found, and the predicates the layer's
/// groups and monitor use: [`ContactLayer::analysis`]. Every method is O(1) unless its
/// docs say otherwise.
#[derive(Clone, Copy, Debug)]
pub struct LayerAnalysis<'a> {
    pub(super) layer: &'a ContactLayer,
}

/// How the layer's analysis reads Rapier and keeps its contact groups:
/// [`ContactLayer::analysis_mut`]. Each setting holds until changed; none changes
/// Rapier's results.
#[derive(Debug)]
pub struct LayerAnalysisMut<'a> {
    pub(super) layer: &'a mut ContactLayer,
}

impl ContactLayer {
    /// What the last analysis read and found: statistics, the step's edge and node
    /// changes, the subscriptions' counters, and the predicates of the groups and the
    /// monitor (see [`LayerAnalysis`]). O(1).
    pub fn analysis(&self) -> LayerAnalysis<'_> {
        LayerAnalysis { layer: self }
    }

    /// How the analysis reads Rapier and keeps its groups: the pair walk, the
    /// per-edge contact details, the groups' split budget and settling, a full
    /// rescan (see [`LayerAnalysisMut`]). O(1).
    pub fn analysis_mut(&mut self) -> LayerAnalysisMut<'_> {
        LayerAnalysisMut { layer: self }
    }
}

impl<'a> LayerAnalysis<'a> {
    /// The statistics of the last step (what [`ContactLayer::step`] returned). O(1).
    pub fn stats(&self) -> StepStats {
        self.layer.stats
    }

    /// The index of the last analysed step (0 before the first). O(1).
    pub fn current_step(&self) -> u64 {
        self.layer.coherence.step()
    }

    /// Edges refreshed in the last step (their marks are valid), in the deterministic
    /// order of [`Coherence::touched_edges`]. O(1) to make, O(1) per edge.
    pub fn touched_edges(&self) -> impl Iterator<Item = (EdgeId, &'a Edge)> + 'a {
        let layer = self.layer;
        layer
            .coherence
            .touched_edges()
            .iter()
            .filter_map(move |&id| Some((id, layer.graph.edge(id)?)))
    }

    /// Edges removed in the last step with a node that left the world, each with a
    /// final `Vanished` mark for the state it had. O(1).
    pub fn removed_edges(&self) -> &'a [Edge] {
        self.layer.coherence.removed_edges()
    }

    /// Nodes removed in the last step. O(1).
    pub fn removed_nodes(&self) -> &'a [RemovedNode] {
        self.layer.coherence.removed_nodes()
    }

    /// Counters and lists of the last analysis (the tracking in effect, the pair
    /// walk's counters, the verification budget). O(1).
    pub fn coherence(&self) -> &'a Coherence {
        &self.layer.coherence
    }

    /// What the plausibility monitor reads of the last analysis (graph, groups,
    /// analysis, speed-ups), for a [`Monitor`](crate::monitor::Monitor) run outside
    /// the layer. O(1).
    pub fn view(&self) -> crate::monitor::AnalysisView<'a> {
        self.layer.analysis_view()
    }

    /// The subscriptions and their counters (sent, dropped). O(1).
    pub fn event_bus(&self) -> &'a EventBus {
        &self.layer.bus
    }

    /// Whether touching tracking is in effect for the next step: asked for (the
    /// default), no subscription to proximity or persist events, and the layer's
    /// event handler given to the last analysed step (always so with
    /// [`ContactLayer::step`]; see [`Tracking`](crate::coherence::Tracking)).
    /// O(subscriptions).
    pub fn touching_in_effect(&self) -> bool {
        self.layer.coherence.feed_connected() && self.layer.touching_wanted()
    }

    /// Whether contact groups are computed (the `groups` switch of the speed-ups; on
    /// without speed-ups). O(1).
    pub fn grouping(&self) -> bool {
        self.layer.grouping()
    }

    /// The bodies the speed-ups gave back to Rapier since the last analysis: released
    /// at the end of [`ContactLayer::step`] (or by a pre-step), dynamic again in the
    /// world, and read as woken by the next analysis. Until then the graph shows them
    /// as the last step saw them (held nodes of fixed bodies), and so does
    /// [`ContactLayer::validate`]. In the order given back. O(changes since the last
    /// analysis).
    pub fn given_back(&self) -> Vec<RigidBodyHandle> {
        self.layer
            .speedups
            .as_ref()
            .map(|s| s.given_back().collect())
            .unwrap_or_default()
    }

    /// Whether a node insulates groups: fixed and kinematic bodies, and sleepy bodies
    /// under subgrouping. `false` for a stale id. O(log sleepy bodies).
    pub fn insulates(&self, n: NodeId) -> bool {
        super::step::insulates(&self.layer.graph, n, self.layer.speedups.as_ref())
    }

    /// Whether the body `h` is *held* in place: fixated by the speed-ups (made fixed in
    /// Rapier until released) or asleep in Rapier (read from `bodies`). Not whether
    /// the layer knows the body: a removed handle answers `false`, and so does every
    /// handle of a set of another world (told as [`crate::Error::ForeignWorld`] says;
    /// a predicate has no error to give). This is the `held` predicate a
    /// [`crate::monitor::Monitor`] run outside the layer takes, and what the layer's
    /// own monitor uses. O(log fixated bodies).
    pub fn holds(&self, bodies: &RigidBodySet, h: RigidBodyHandle) -> bool {
        let layer = self.layer;
        if !layer.coherence.bodies_match(&layer.graph, bodies) {
            return false;
        }
        layer.fixates(h) || bodies.get(h).is_some_and(|b| b.is_sleeping())
    }

    /// Which of Rapier's collision events the user's own handler would have received
    /// without the layer's flags and sensor widening. A handler that calls the
    /// layer's [`ContactLayer::event_handler`] itself (wired by hand, rather than
    /// through [`ContactLayer::event_handler_with`]) handles only the events for which
    /// [`passes`](crate::coherence::UserEventFilter::passes) is true; otherwise it also
    /// receives the events the layer asked Rapier for. O(1) to make.
    pub fn user_event_filter(&self) -> crate::coherence::UserEventFilter<'a> {
        self.layer.user_event_filter()
    }

    /// The number of colliders carrying hook flags set by the layer (0 without rules).
    /// O(1).
    pub fn flagged_colliders(&self) -> usize {
        self.layer.logic.flagged_colliders()
    }

    /// Whether a node is supported against the gravity of the last analysed world
    /// (see [`ContactGraph::try_is_supported`](crate::ContactGraph::try_is_supported);
    /// any upward push counts), judged by the contact normals the edges keep: the
    /// node form of [`ContactLayer::supports_of_body`], as of the last analysed step.
    /// O(degree).
    ///
    /// The edges keep normals only under proximity tracking with the contact details
    /// on ([`Coherence::details_kept`]); otherwise this is
    /// [`Error::DetailsNotKept`](crate::Error::DetailsNotKept):
    /// [`ContactLayer::supports_of_body`] and [`ContactLayer::is_grounded`] read the
    /// normals from Rapier and answer under any tracking.
    pub fn is_supported(&self, node: NodeId) -> Result<bool> {
        let layer = self.layer;
        layer.graph.try_node(node)?;
        if !layer.coherence.details_kept() {
            return Err(crate::Error::DetailsNotKept);
        }
        layer.graph.try_is_supported(node, layer.gravity, 0.0)
    }
}

impl LayerAnalysisMut<'_> {
    /// How the analysis reads Rapier's pairs: walking the awake bodies' pairs, scanning
    /// every pair, or choosing per step ([`ScanPolicy::Auto`], the default). Both
    /// ways build the same graph (tested); the choice is only a matter of cost.
    /// O(1).
    pub fn set_scan_policy(&mut self, policy: ScanPolicy) {
        self.layer.coherence.set_scan_policy(policy);
    }

    /// Turns the per-edge contact details on (the default) or off (closest distance,
    /// contact count, deepest penetration, normal impulse), under proximity tracking
    /// (touching tracking copies none). A scene that needs only the marks, the
    /// touching state and the groups pays less per contact pair with them off. The
    /// node-based support query ([`LayerAnalysis::is_supported`]) needs them (the
    /// contact normals) and says so when they are missing;
    /// [`ContactLayer::supports_of_body`], [`ContactLayer::is_grounded`] and
    /// [`ContactLayer::contact_details`] read Rapier's and need neither. O(1).
    pub fn set_contact_details(&mut self, on: bool) {
        self.layer.coherence.set_contact_details(on);
    }

    /// Sets how many node expansions the local search after an ended contact may make
    /// before it defers the group's split ([`crate::Groups::DEFAULT_SPLIT_BUDGET`] by
    /// default, Rapier's own figure). A larger budget splits more groups at once, a
    /// smaller one bounds the cost of an ended contact more tightly. O(1).
    pub fn set_group_split_budget(&mut self, budget: u32) {
        self.layer.groups.set_split_budget(budget);
    }

    /// Finishes every deferred group split now, so that [`ContactLayer::groups`]
    /// equals a from-scratch traversal of the paper's Figs. 7–8 exactly. Without it, a
    /// group whose split the bounded local search could not settle is split by
    /// traversal in a later step (one per step, the sleepiest first), and meanwhile
    /// holds two or more whole groups (see [`crate::Groups::deferred`]). O(members +
    /// edges of the deferred groups); O(1) when none is deferred.
    pub fn settle_groups(&mut self) {
        let layer = &mut *self.layer;
        if layer.groups.deferred().is_empty() || !layer.grouping() {
            return;
        }
        let speedups = layer.speedups.as_ref();
        let step = layer.coherence.step();
        layer.groups.settle(&mut layer.graph, step, &|g, n| {
            super::step::insulates(g, n, speedups)
        });
        layer.stats.groups = layer.groups.stats();
    }

    /// Asks for a full scan of bodies and colliders at the next update, which also
    /// reads every node's pairs and every trigger again. Needed only after changing a
    /// *sleeping, fixed or passive* body, or static geometry, in place in a way Rapier
    /// does not wake it for (its type, moving a fixed body or a parentless collider, a
    /// sensor flag); "sleeping" as of the last step: a sleeping body woken (say, by a
    /// teleport) and turned fixed before the next step never shows in Rapier's active
    /// set; adding and removing bodies and colliders is detected, and so is a
    /// moved trigger. A collider moved to another body (`ColliderSet::set_parent`) or
    /// swapped for another is followed without it when Rapier wakes either side (a
    /// dynamic body); between fixed or sleeping bodies, within `colliders / 32` steps,
    /// or at once with it. It also drops the layer's lookup caches. O(1) here; that
    /// update costs O(nodes + pairs).
    pub fn request_full_sync(&mut self) {
        self.layer.coherence.request_full_sync();
    }
}
