//! Touch transitions from Rapier's own collision events, the public side: [`Tracking`]
//! and the layer's [`TouchFeed`]. The touch update itself is `touch_update.rs`; the
//! user's own handler beside the layer's is `user_events.rs`.

use std::collections::BTreeMap;
use std::sync::Mutex;

use rapier3d::dynamics::{SoftBodySet, SoftBodyTearEvent};
use rapier3d::geometry::{ColliderSet, CollisionEvent, CollisionEventFlags, ContactPair};
use rapier3d::math::Real;
use rapier3d::pipeline::EventHandler;
use rapier3d::prelude::{ColliderHandle, RigidBodySet};

use super::*;

/// How the layer follows contacts.
///
/// **What.** Under [`Tracking::Touching`] (the default) the layer is Rapier's
/// `EventHandler` ([`TouchFeed`]): touch transitions come from Rapier's
/// `CollisionEvent::Started` / `Stopped`, for which the layer adds
/// `ActiveEvents::COLLISION_EVENTS` to colliders lacking it (taken off again when its
/// handler no longer reaches the step, and on detach; [`WithUser`](super::WithUser)
/// hides them from a user's own handler). Under [`Tracking::Proximity`] every pair of
/// every awake body is read each step.
///
/// **When.** Touching tracking is in effect for a step when it is asked for
/// ([`ContactLayer::set_tracking`](crate::ContactLayer::set_tracking)), no subscription
/// needs every pair (proximity or persist events), and the layer's handler reaches
/// Rapier's step ([`ContactLayer::step`](crate::ContactLayer::step) passes it; a
/// hand-stepped loop passes [`ContactLayer::event_handler`](crate::ContactLayer::event_handler)).
/// Otherwise the layer tracks proximity;
/// [`LayerAnalysis::touching_in_effect`](crate::LayerAnalysis::touching_in_effect) says
/// which applies. The speed-ups and the monitor decide the same under both.
///
/// **Why and cost.** Reading every awake pair costs a large share of a Rapier step on
/// a falling pile; Rapier reports touch transitions for free and without changing any
/// result. Under touching tracking the analysis is O(events + awake bodies) per step;
/// the graph holds touching edges only (no proximity edges, no persist events), and
/// contact details are read from Rapier when asked. Design and rejected alternatives:
/// `docs/ARCHITECTURE.md` ("Touching tracking").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Tracking {
    /// Every narrow-phase pair of an awake body is read each step: proximity and
    /// touching edges, contact details, persist events. In effect whenever touching
    /// tracking is not (see above).
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
}
