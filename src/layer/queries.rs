//! Queries on the layer's last analysis: the graph, the groups, nodes of Rapier
//! handles, support, and `validate()`.

use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

use crate::coherence::{Coherence, RemovedNode, ScanPolicy};
use crate::graph::{ContactGraph, Edge, EdgeId, NodeId, NodeKind};
use crate::groups::Groups;
use crate::{Result, WorldView};

use super::{ContactLayer, StepStats};

impl ContactLayer {
    /// The contact graph.
    pub fn graph(&self) -> &ContactGraph {
        &self.graph
    }

    /// The contact groups.
    pub fn groups(&self) -> &Groups {
        &self.groups
    }

    /// The statistics of the last step.
    pub fn stats(&self) -> StepStats {
        self.stats
    }

    /// The index of the last analysed step.
    pub fn current_step(&self) -> u64 {
        self.coherence.step()
    }

    /// Edges refreshed in the last step (their marks are valid), in the deterministic
    /// order of [`Coherence::touched_edges`].
    pub fn touched_edges(&self) -> impl Iterator<Item = (EdgeId, &Edge)> + '_ {
        self.coherence
            .touched_edges()
            .iter()
            .filter_map(|&id| Some((id, self.graph.edge(id)?)))
    }

    /// Edges removed in the last step with a node that left the world, each with a
    /// final `Vanished` mark for the state it had.
    pub fn removed_edges(&self) -> &[Edge] {
        self.coherence.removed_edges()
    }

    /// Nodes removed in the last step.
    pub fn removed_nodes(&self) -> &[RemovedNode] {
        self.coherence.removed_nodes()
    }

    /// Counters and lists of the last analysis.
    pub fn coherence(&self) -> &Coherence {
        &self.coherence
    }

    /// What the plausibility monitor reads of the last analysis (graph, groups,
    /// analysis, speed-ups). O(1).
    pub fn analysis_view(&self) -> crate::monitor::AnalysisView<'_> {
        crate::monitor::AnalysisView {
            graph: &self.graph,
            groups: &self.groups,
            coherence: &self.coherence,
            speedups: self.speedups(),
        }
    }

    /// How the analysis reads Rapier's pairs: walking the awake bodies' pairs, scanning
    /// every pair, or choosing per step ([`ScanPolicy::Auto`], the default). Both
    /// ways build the same graph (tested); the choice is only a matter of cost.
    /// O(1).
    pub fn set_scan_policy(&mut self, policy: ScanPolicy) {
        self.coherence.set_scan_policy(policy);
    }

    /// How the layer follows contacts (see [`Tracking`](crate::coherence::Tracking)):
    /// [`Tracking::Touching`](crate::coherence::Tracking::Touching) (the default)
    /// keeps touching edges only and takes their beginnings and ends from Rapier's
    /// collision events, at a cost proportional to the events, while nothing needs
    /// more: no subscription to proximity or persist events,
    /// and the layer's event handler reaches Rapier's step. Otherwise the layer tracks
    /// proximity meanwhile; each switch costs one full read of the pairs at the next
    /// update. [`Tracking::Proximity`](crate::coherence::Tracking::Proximity) reads
    /// every pair of every awake body each step, always: proximity edges, per-step
    /// contact details and persist events whether subscribed or not.
    ///
    /// With touching tracking, [`Self::step`] hands Rapier the layer's event handler;
    /// users who step Rapier themselves pass [`Self::event_handler`] (or
    /// [`Self::event_handler_with`] to keep their own) to Rapier's step. The layer adds
    /// `ActiveEvents::COLLISION_EVENTS` to the colliders lacking it and takes it off
    /// again when touching tracking ends. O(1) here.
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::coherence::Tracking;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.1, 5.0));
    /// let (ball, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.set_tracking(Tracking::Touching);
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// let n = layer.node_of_body(ball).unwrap();
    /// assert_eq!(layer.graph().touching(n).count(), 1);
    /// layer.validate(&world).unwrap();
    /// ```
    pub fn set_tracking(&mut self, tracking: crate::coherence::Tracking) {
        self.coherence.request_tracking(tracking);
    }

    /// Whether touching tracking is in effect for the next step: asked for (the
    /// default), no subscription to proximity or persist events, and the layer's
    /// event handler given to the last
    /// analysed step (always so with [`Self::step`]; see
    /// [`Tracking`](crate::coherence::Tracking)). O(subscriptions).
    pub fn touching_in_effect(&self) -> bool {
        self.coherence.feed_connected() && self.touching_wanted()
    }

    /// Touching tracking asked for, and nothing that needs every pair read: no
    /// subscription to proximity or persist events. (The speed-ups and the monitor
    /// read what they need from Rapier for the bodies concerned.)
    pub(crate) fn touching_wanted(&self) -> bool {
        self.coherence.requested_tracking() == crate::coherence::Tracking::Touching
            && !self
                .bus
                .wanted()
                .intersects(crate::events::KindSet::NEEDS_EVERY_PAIR)
    }

    /// The layer's Rapier event handler, for users who step Rapier themselves: pass it
    /// to Rapier's step with [`Self::hooks`], every step. Calling it tells the layer
    /// that its handler reaches Rapier's step, which lets touching tracking (the
    /// default) go on from the next step (see
    /// [`Tracking`](crate::coherence::Tracking)); a loop that never calls it is
    /// tracked by proximity. To give Rapier's events to a handler of one's own too,
    /// use [`Self::event_handler_with`], or, wiring the two by hand, handle only the
    /// events [`Self::user_event_filter`] passes: the layer's collision-event flags
    /// and sensor widening make Rapier send events the user never asked for. O(1).
    pub fn event_handler(&self) -> &crate::coherence::TouchFeed {
        self.feed_lent
            .store(true, std::sync::atomic::Ordering::Relaxed);
        &self.touch_feed
    }

    /// The layer's event handler together with the user's own: the layer gets the
    /// touch transitions, `user` exactly the events Rapier would send it without the
    /// layer's flags (see [`WithUser`](crate::coherence::WithUser)). O(1) to make;
    /// O(log flagged colliders) per event.
    pub fn event_handler_with<'a, H: rapier3d::pipeline::EventHandler + ?Sized>(
        &'a self,
        user: &'a H,
    ) -> crate::coherence::WithUser<'a, H> {
        crate::coherence::WithUser {
            feed: self.event_handler(),
            filter: self.user_event_filter(),
            user,
        }
    }

    /// Which of Rapier's collision events the user's own handler would have received
    /// without the layer's flags and sensor widening. A handler that calls the
    /// layer's [`Self::event_handler`] itself (wired by hand, rather than through
    /// [`Self::event_handler_with`]) handles only the events for which
    /// [`passes`](crate::coherence::UserEventFilter::passes) is true; otherwise it also
    /// receives the events the layer asked Rapier for. O(1) to make.
    pub fn user_event_filter(&self) -> crate::coherence::UserEventFilter<'_> {
        crate::coherence::UserEventFilter {
            flagged: self.coherence.touch_flagged(),
            widened: self.logic.widened(),
        }
    }

    /// Turns the per-edge contact details on (the default) or off (closest distance,
    /// contact count, deepest penetration, normal impulse), under proximity tracking
    /// (touching tracking copies none). A scene that needs only the marks, the
    /// touching state and the groups pays less per contact pair with them off. The
    /// node-based support query ([`Self::is_supported`]) needs them (the contact
    /// normals) and says so when they are missing; [`Self::supports_of_body`] and
    /// [`Self::contact_details`] read Rapier's and need neither.
    pub fn set_contact_details(&mut self, on: bool) {
        self.coherence.set_contact_details(on);
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
    /// or at once with it. It also drops the layer's lookup caches. That update costs
    /// O(nodes + pairs).
    pub fn request_full_sync(&mut self) {
        self.coherence.request_full_sync();
    }

    /// The node of a body. O(1).
    pub fn node_of_body(&self, body: RigidBodyHandle) -> Result<NodeId> {
        self.graph.try_node_of_body(body)
    }

    /// The node of a collider: the trigger node of a sensor, else its parent body's
    /// node, or its own for a parentless collider. `world` is a `&PhysicsWorld` or a
    /// [`WorldView`] of one's own sets; `Err(ForeignWorld)` for another world
    /// ([`crate::Error::ForeignWorld`]). O(1).
    pub fn node_of_collider<'w>(
        &self,
        world: impl Into<WorldView<'w>>,
        collider: ColliderHandle,
    ) -> Result<NodeId> {
        let view = world.into();
        self.check_world(&view)?;
        let c = view
            .colliders
            .get(collider)
            .ok_or(crate::Error::UnknownCollider(collider))?;
        if let Some(t) = self.graph.node_of_sensor(collider) {
            return Ok(t);
        }
        match c.parent() {
            Some(b) => self.graph.try_node_of_body(b),
            None => self
                .graph
                .node_of_static_collider(collider)
                .ok_or(crate::Error::UnknownCollider(collider)),
        }
    }

    /// Whether a node is supported against the gravity of the last analysed world
    /// (see [`ContactGraph::try_is_supported`]; any upward push counts), judged by the
    /// contact normals the edges keep. O(degree).
    ///
    /// The edges keep normals only under proximity tracking with the contact details
    /// on ([`Coherence::details_kept`](crate::coherence::Coherence::details_kept));
    /// otherwise this is [`Error::DetailsNotKept`](crate::Error::DetailsNotKept):
    /// [`Self::supports_of_body`] reads the normals from Rapier and answers under any
    /// tracking.
    pub fn is_supported(&self, node: NodeId) -> Result<bool> {
        self.graph.try_node(node)?;
        if !self.coherence.details_kept() {
            return Err(crate::Error::DetailsNotKept);
        }
        self.graph.try_is_supported(node, self.gravity, 0.0)
    }

    /// Whether `node` is of a given kind; an error for a stale id. O(1).
    pub fn kind_of(&self, node: NodeId) -> Result<NodeKind> {
        Ok(self.graph.try_node(node)?.kind())
    }

    /// Checks every invariant: the graph's own ([`ContactGraph::validate`]), the
    /// groups', and the graph against the world — one node per body and per static
    /// collider with the right kind, an edge with proximity for every Rapier pair of
    /// two nodes that Table 2 allows, the touching state equal to Rapier's, and no
    /// proximate edge without its Rapier pair. Before the first step there is nothing
    /// to hold against the world: `Ok`. After an edit of the world since the last
    /// step, the layer is behind the world until the next one, and says so. Another
    /// world (or a copy) is `Err(ForeignWorld)` ([`crate::Error::ForeignWorld`]), not
    /// checked against this layer. O(nodes + edges + Rapier pairs).
    pub fn validate(&self, world: &PhysicsWorld) -> Result<()> {
        self.validate_view(&WorldView::from(world))
    }

    /// Whether groups are computed (the `groups` switch of the speed-ups; on without
    /// speed-ups).
    pub fn grouping(&self) -> bool {
        match self.speedups() {
            Some(s) => s.config().groups,
            None => true,
        }
    }

    /// Whether a node insulates groups: fixed and scripted bodies, and sleepy bodies
    /// under subgrouping.
    pub fn insulates(&self, n: NodeId) -> bool {
        super::step::insulates(&self.graph, n, self.speedups.as_ref())
    }

    /// [`Self::validate`] for a world given by its parts.
    pub fn validate_view(&self, view: &WorldView) -> Result<()> {
        self.check_world(view)?;
        crate::validate::validate_layer(self, view)
    }
}
