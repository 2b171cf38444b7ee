//! Queries on the layer's last analysis: the graph, the groups, nodes of Rapier
//! handles, support, and `validate()`.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle, RigidBodySet};

use crate::graph::{ContactGraph, NodeId};
use crate::groups::Groups;
use crate::{Result, WorldView};

use super::ContactLayer;

impl ContactLayer {
    /// The contact graph, as of the last analysed step. O(1).
    pub fn graph(&self) -> &ContactGraph {
        &self.graph
    }

    /// The contact groups, as of the last analysed step. O(1).
    pub fn groups(&self) -> &Groups {
        &self.groups
    }

    /// What the plausibility monitor reads of the last analysis (graph, groups,
    /// analysis, speed-ups). O(1).
    pub(crate) fn analysis_view(&self) -> crate::monitor::AnalysisView<'_> {
        crate::monitor::AnalysisView {
            graph: &self.graph,
            groups: &self.groups,
            coherence: &self.coherence,
            speedups: self.speedups(),
        }
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
    /// let n = layer.node_of_body(&world.bodies, ball).unwrap();
    /// assert_eq!(layer.graph().touching(n).count(), 1);
    /// layer.validate(&world).unwrap();
    /// ```
    pub fn set_tracking(&mut self, tracking: crate::coherence::Tracking) {
        self.coherence.request_tracking(tracking);
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
    /// events [`LayerAnalysis::user_event_filter`](super::LayerAnalysis::user_event_filter) passes: the layer's collision-event flags
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
    pub(crate) fn user_event_filter(&self) -> crate::coherence::UserEventFilter<'_> {
        crate::coherence::UserEventFilter {
            flagged: self.coherence.touch_flagged(),
            widened: self.logic.widened(),
        }
    }

    /// The node of a body, checked against the world: the bridge from Rapier's
    /// handles to the node forms (rules, containers, [`Self::graph`]).
    /// `Err(UnknownBody)` for a body `bodies` lacks (removed, at once: the same answer
    /// as the by-handle queries, though the graph keeps its node until the next step),
    /// `Err(UnseenBody)` for one inserted since the last step, `Err(ForeignWorld)` for
    /// a set of another world ([`crate::Error::ForeignWorld`]). Unchecked, as of the
    /// last analysed step: [`ContactGraph::try_node_of_body`]. O(1).
    pub fn node_of_body(&self, bodies: &RigidBodySet, body: RigidBodyHandle) -> Result<NodeId> {
        self.node_of_live_body(bodies, body)?
            .ok_or(crate::Error::UnseenBody(body))
    }

    /// The node of a collider: the trigger node of a sensor, else its parent body's
    /// node, or its own for a parentless collider. `world` is a `&PhysicsWorld` or a
    /// [`WorldView`] of one's own sets. `Err(UnknownCollider)` for a collider the
    /// world lacks, `Err(UnknownBody)` for one whose parent it lacks,
    /// `Err(UnseenCollider)` for a collider the layer has not seen yet (a sensor or
    /// parentless collider inserted since the last step, or one on a body inserted
    /// since), `Err(ForeignWorld)` for another world ([`crate::Error::ForeignWorld`]).
    /// O(1).
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
        let unseen = crate::Error::UnseenCollider(collider);
        if c.is_sensor() {
            return self.graph.node_of_sensor(collider).ok_or(unseen);
        }
        match c.parent() {
            Some(b) => self.node_of_live_body(view.bodies, b)?.ok_or(unseen),
            None => self.graph.node_of_static_collider(collider).ok_or(unseen),
        }
    }

    /// Checks every invariant: the graph's own ([`ContactGraph::validate`]), the
    /// groups', and the graph against the world — one node per body and per static
    /// collider with the right kind, an edge with proximity for every Rapier pair of
    /// two nodes that Table 2 allows, the touching state equal to Rapier's, and no
    /// proximate edge without its Rapier pair. Before the first step there is nothing
    /// to hold against the world: `Ok`. After an edit of the world since the last
    /// step, the layer is behind the world until the next one, and says so. Another
    /// world (or a copy) is `Err(ForeignWorld)` ([`crate::Error::ForeignWorld`]), not
    /// checked against this layer. `world` is a `&PhysicsWorld` or a [`WorldView`] of
    /// one's own sets. O(nodes + edges + Rapier pairs).
    pub fn validate<'w>(&self, world: impl Into<WorldView<'w>>) -> Result<()> {
        let view = world.into();
        self.check_world(&view)?;
        crate::validate::validate_layer(self, &view)
    }

    /// Whether groups are computed (the `groups` switch of the speed-ups; on without
    /// speed-ups).
    pub(crate) fn grouping(&self) -> bool {
        match self.speedups() {
            Some(s) => s.config().groups,
            None => true,
        }
    }
}
