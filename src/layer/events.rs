//! Subscriptions to the layer's events (paper §4, Table 3) on crossbeam channels.

use crossbeam_channel::Receiver;

use crate::events::{Event, Filter, SubscriptionId};
use crate::Result;

use super::ContactLayer;

impl ContactLayer {
    /// Subscribes to the events matching `filter` on an unbounded channel (see the
    /// contract in [`crate::events`]). O(1).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{events::{EventKind, Filter, KindSet}, ContactLayer};
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.5, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// let touches = layer.subscribe(Filter::kinds(KindSet::of(&[EventKind::ContactStarted])));
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert_eq!(touches.try_iter().count(), 1, "the ball landed once");
    /// ```
    pub fn subscribe(&mut self, filter: Filter) -> Receiver<Event> {
        self.bus.subscribe(filter).1
    }

    /// Subscribes on a channel of at most `capacity` events: when it is full, the newest
    /// events are dropped and counted ([`EventBus::dropped`](crate::events::EventBus::dropped)); the step never blocks.
    /// A capacity of 0 or above [`crate::events::MAX_CAPACITY`], or a filter naming a
    /// stale node, is an error. O(1).
    pub fn subscribe_bounded(
        &mut self,
        filter: Filter,
        capacity: usize,
    ) -> Result<Receiver<Event>> {
        if let Some(nodes) = filter.nodes() {
            for &n in nodes {
                self.graph.try_node(n)?;
            }
        }
        Ok(self.bus.subscribe_bounded(filter, capacity)?.1)
    }

    /// Subscribes and returns the subscription's id too (to unsubscribe or read its
    /// drop count in [`LayerAnalysis::event_bus`](super::LayerAnalysis::event_bus)).
    /// O(1).
    pub fn subscribe_with_id(&mut self, filter: Filter) -> (SubscriptionId, Receiver<Event>) {
        self.bus.subscribe(filter)
    }

    /// Removes a subscription (dropping the receiver does it too, lazily); `false` if
    /// there was none of that id. O(subscriptions).
    pub fn unsubscribe(&mut self, id: SubscriptionId) -> bool {
        self.bus.unsubscribe(id)
    }

    /// The events generated in the last step (of the kinds some subscription wants).
    /// O(1).
    pub fn last_events(&self) -> &[Event] {
        &self.events
    }

    /// The last step's events naming `body` (in [`Event::body1`] or
    /// [`Event::body2`]; see [`Filter::with_bodies`] for what that covers), in
    /// order. Only kinds some subscription wants are generated: subscribe first (a
    /// `Filter::with_bodies` subscription receives the same events). A body the layer
    /// has not seen, or a removed one, has none. O(the step's events).
    pub fn last_events_of_body(
        &self,
        body: rapier3d::prelude::RigidBodyHandle,
    ) -> impl Iterator<Item = &Event> + '_ {
        self.events
            .iter()
            .filter(move |e| e.body1 == Some(body) || e.body2 == Some(body))
    }
}
