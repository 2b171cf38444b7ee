//! The user's own `EventHandler` beside the layer's: [`UserEventFilter`] says which of
//! Rapier's collision events the user would have received without the layer, and
//! [`WithUser`] composes the two handlers with it.
//!
//! The layer changes what Rapier reports: touching tracking adds
//! `ActiveEvents::COLLISION_EVENTS` to colliders that lack it, and trigger widening
//! ([`LayerLogicMut::set_trigger_widening`](crate::LayerLogicMut::set_trigger_widening))
//! widens sensors' collision types. Both make Rapier send events the user never
//! asked for. Two compositions keep them from the user's handler:
//! - [`ContactLayer::event_handler_with`](crate::ContactLayer::event_handler_with):
//!   the layer's handler wraps the user's and forwards only what passes the filter;
//! - wired by hand (the user's handler calls the layer's
//!   [`event_handler`](crate::ContactLayer::event_handler) for every event): the
//!   user's handler must handle itself only the events for which
//!   [`LayerAnalysis::user_event_filter`](crate::LayerAnalysis::user_event_filter)
//!   `.passes(..)` is true. Without that check it receives the layer's extra events;
//!   no other composition is supported.

use std::collections::{BTreeMap, HashMap};

use rapier3d::dynamics::RigidBodyType;
use rapier3d::dynamics::{SoftBodySet, SoftBodyTearEvent};
use rapier3d::geometry::{
    ActiveCollisionTypes, Collider, ColliderSet, CollisionEvent, CollisionEventFlags, ContactPair,
};
use rapier3d::math::Real;
use rapier3d::pipeline::{ActiveEvents, EventHandler};
use rapier3d::prelude::{ColliderHandle, RigidBodySet};

use super::TouchFeed;

/// Which of Rapier's collision events the user would have received without the
/// layer's flags and widening. Made by
/// [`LayerAnalysis::user_event_filter`](crate::LayerAnalysis::user_event_filter) for a
/// handler wired by hand (see the module docs); [`WithUser`] uses it.
#[derive(Clone, Copy)]
pub struct UserEventFilter<'a> {
    pub(crate) flagged: &'a BTreeMap<(u32, u32), ColliderHandle>,
    pub(crate) widened: &'a HashMap<ColliderHandle, ActiveCollisionTypes>,
}

impl UserEventFilter<'_> {
    /// Whether Rapier would have sent `event` to the user's handler without the
    /// layer: one of its colliders has `COLLISION_EVENTS` by the user's doing (or was
    /// removed and never flagged by the layer), and, for a sensor event, the pair
    /// passes the collision types the user gave the colliders. Pass the sets Rapier
    /// passed to the handler. O(log flagged colliders).
    pub fn passes(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        event: &CollisionEvent,
    ) -> bool {
        let (c1, c2, flags) = match *event {
            CollisionEvent::Started(a, b, f) | CollisionEvent::Stopped(a, b, f) => (a, b, f),
        };
        if flags.contains(CollisionEventFlags::SENSOR)
            && !self.users_types_pass(bodies, colliders, c1, c2)
        {
            return false;
        }
        let flagged = |c: ColliderHandle| self.flagged.contains_key(&c.into_raw_parts());
        let users = |c: ColliderHandle| {
            !flagged(c)
                && colliders
                    .get(c)
                    .is_some_and(|co| co.active_events().contains(ActiveEvents::COLLISION_EVENTS))
        };
        // A removed collider is gone from the set: Rapier sent the event because of
        // the other one's flag, or of the removed one's, which the layer never set
        // unless it is in `flagged`.
        let removed = |c: ColliderHandle| !colliders.contains(c) && !flagged(c);
        users(c1) || users(c2) || removed(c1) || removed(c2)
    }

    /// Whether Rapier pairs the two colliders under the user's own collision types
    /// (the layer's widening undone). O(1).
    fn users_types_pass(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        c1: ColliderHandle,
        c2: ColliderHandle,
    ) -> bool {
        let (Some(co1), Some(co2)) = (colliders.get(c1), colliders.get(c2)) else {
            return true; // a removed collider: Rapier's own event
        };
        let ty = |co: &Collider| {
            co.parent()
                .and_then(|p| bodies.get(p))
                .map_or(RigidBodyType::Fixed, |rb| rb.body_type())
        };
        let (t1, t2) = (ty(co1), ty(co2));
        let types = |c, co: &Collider| {
            self.widened
                .get(&c)
                .copied()
                .unwrap_or(co.active_collision_types())
        };
        types(c1, co1).test(t1, t2) || types(c2, co2).test(t1, t2)
    }
}

/// The layer's [`TouchFeed`] together with the user's own `EventHandler`: the layer
/// gets every touch transition, the user exactly the events Rapier would send them
/// without the layer ([`UserEventFilter`]; every contact-force event, whose flag the
/// layer never sets). Made by
/// [`ContactLayer::event_handler_with`](crate::ContactLayer::event_handler_with).
pub struct WithUser<'a, H: ?Sized> {
    pub(crate) feed: &'a TouchFeed,
    pub(crate) filter: UserEventFilter<'a>,
    pub(crate) user: &'a H,
}

impl<H: EventHandler + ?Sized> EventHandler for WithUser<'_, H> {
    fn handle_collision_event(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        event: CollisionEvent,
        contact_pair: Option<&ContactPair>,
    ) {
        self.feed
            .handle_collision_event(bodies, colliders, event, contact_pair);
        if self.filter.passes(bodies, colliders, &event) {
            self.user
                .handle_collision_event(bodies, colliders, event, contact_pair);
        }
    }

    fn handle_contact_force_event(
        &self,
        dt: Real,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        contact_pair: &ContactPair,
        total_force_magnitude: Real,
    ) {
        self.user.handle_contact_force_event(
            dt,
            bodies,
            colliders,
            contact_pair,
            total_force_magnitude,
        );
    }

    fn handle_soft_body_tear_event(&self, soft_bodies: &SoftBodySet, event: &SoftBodyTearEvent) {
        self.user.handle_soft_body_tear_event(soft_bodies, event);
    }
}
