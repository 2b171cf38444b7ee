//! Touching tracking: the graph follows Rapier's own collision events. It changes no
//! trajectory bit, reports the same touch beginnings and ends as proximity tracking,
//! validates on every scene, keeps the user's events and flags as the user set them,
//! and switches to and from proximity tracking cleanly.

mod common;

use std::collections::BTreeSet;
use std::sync::Mutex;

use rapier3d::dynamics::{SoftBodySet, SoftBodyTearEvent};
use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes as scenes;

fn touching_layer() -> ContactLayer {
    let mut layer = ContactLayer::new();
    layer.set_tracking(Tracking::Touching);
    layer
}

#[test]
fn touching_tracking_changes_no_trajectory_bit() {
    let mut plain = scenes::sphere_pile(300, 2);
    let mut layered = scenes::sphere_pile(300, 2);
    let mut layer = touching_layer();
    for step in 0..400 {
        plain.world.step();
        common::step_validated(&mut layered, &mut layer, step);
        if step % 50 == 49 {
            assert_eq!(
                common::pose_bits(&plain.world),
                common::pose_bits(&layered.world),
                "step {step}"
            );
        }
    }
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Touching);
}

/// The touch events of a step as a set of (kind, body, body), bodies in order.
fn touch_set(layer: &ContactLayer) -> BTreeSet<(u8, (u32, u32), (u32, u32))> {
    layer
        .last_events()
        .iter()
        .filter(|e| {
            matches!(
                e.kind,
                EventKind::ContactStarted | EventKind::ContactStopped
            )
        })
        .map(|e| {
            let a = e.body1.map_or((u32::MAX, 0), |h| h.into_raw_parts());
            let b = e.body2.map_or((u32::MAX, 0), |h| h.into_raw_parts());
            (e.kind as u8, a.min(b), a.max(b))
        })
        .collect()
}

#[test]
fn touch_events_are_those_of_proximity_tracking() {
    for (name, build) in [
        (
            "sphere_pile",
            (|| scenes::sphere_pile(200, 4)) as fn() -> scenes::Scene,
        ),
        ("toppling_stack", scenes::toppling_stack),
        ("two_piles", scenes::two_piles_with_wall),
        ("kinematic_platform", scenes::kinematic_platform),
    ] {
        let mut a = build();
        let mut b = build();
        let mut proximity = ContactLayer::new();
        let mut touching = touching_layer();
        // Begin and end only: a subscription to persist events would need proximity
        // tracking.
        let begin_end = KindSet::of(&[EventKind::ContactStarted, EventKind::ContactStopped]);
        let _ra = proximity.subscribe(Filter::kinds(begin_end));
        let _rb = touching.subscribe(Filter::kinds(begin_end));
        let mut seen = 0;
        for step in 0..300 {
            common::step_validated(&mut a, &mut proximity, step);
            common::step_validated(&mut b, &mut touching, step);
            let (sa, sb) = (touch_set(&proximity), touch_set(&touching));
            assert_eq!(sa, sb, "{name}: step {step}");
            seen += sa.len();
            // The same touching body pairs in both graphs.
            let pairs = |l: &ContactLayer| -> BTreeSet<_> {
                l.graph()
                    .edges()
                    .filter(|(_, e)| e.is_touching())
                    .map(|(_, e)| {
                        let (x, y) = (e.a().index(), e.b().index());
                        (x.min(y), x.max(y))
                    })
                    .collect()
            };
            assert_eq!(pairs(&proximity), pairs(&touching), "{name}: step {step}");
        }
        assert!(seen > 0, "{name}: some touches began or ended");
        assert_eq!(
            touching.analysis().coherence().tracking(),
            Tracking::Touching,
            "{name}"
        );
        // No proximity events, no persist events, in touching tracking.
        assert!(touching.last_events().iter().all(|e| !matches!(
            e.kind,
            EventKind::ProximityStarted | EventKind::ProximityStopped
        )));
    }
}

#[test]
fn every_scene_validates_under_touching_tracking() {
    for mut scene in [
        scenes::ball_on_box(),
        scenes::kinematic_platform(),
        scenes::trigger_ledge(),
        scenes::two_piles_with_wall(),
        scenes::toppling_stack(),
        scenes::pendulum_wall(),
        scenes::sphere_stack(8),
    ] {
        let mut layer = touching_layer();
        common::run_validated(&mut scene, &mut layer, 0, 300);
    }
}

/// An `EventHandler` that records every collision event, as a user's would.
#[derive(Default)]
struct Recorder(Mutex<Vec<CollisionEvent>>);

impl EventHandler for Recorder {
    fn handle_collision_event(
        &self,
        _: &RigidBodySet,
        _: &ColliderSet,
        event: CollisionEvent,
        _: Option<&ContactPair>,
    ) {
        self.0.lock().unwrap().push(event);
    }
    fn handle_contact_force_event(
        &self,
        _: Real,
        _: &RigidBodySet,
        _: &ColliderSet,
        _: &ContactPair,
        _: Real,
    ) {
    }
    fn handle_soft_body_tear_event(&self, _: &SoftBodySet, _: &SoftBodyTearEvent) {}
}

/// A pile where the user flagged every third collider for collision events.
fn flagged_pile() -> scenes::Scene {
    let mut scene = scenes::sphere_pile(120, 9);
    let handles: Vec<ColliderHandle> = scene.world.colliders.iter().map(|(h, _)| h).collect();
    for (i, h) in handles.into_iter().enumerate() {
        if i % 3 == 0 {
            scene.world.colliders[h].set_active_events(ActiveEvents::COLLISION_EVENTS);
        }
    }
    scene
}

fn events_flags(world: &PhysicsWorld) -> Vec<(ColliderHandle, ActiveEvents)> {
    world
        .colliders
        .iter()
        .map(|(h, c)| (h, c.active_events()))
        .collect()
}

#[test]
fn the_users_handler_gets_exactly_rapiers_events_and_flags_come_back() {
    let mut plain = flagged_pile();
    let mut layered = flagged_pile();
    let before = events_flags(&layered.world);
    let (mine, theirs) = (Recorder::default(), Recorder::default());
    let mut layer = touching_layer();
    for step in 0..300 {
        plain.world.step_with_events(&(), &mine);
        layer.pre_step((&mut layered.world).into());
        let handler = layer.event_handler_with(&theirs);
        layered.world.step_with_events(&layer.hooks(), &handler);
        layer.analyze(WorldView::from(&layered.world));
        layer.validate(&layered.world).unwrap();
        let key = |e: &CollisionEvent| match *e {
            CollisionEvent::Started(a, b, f) => (true, a, b, f.bits()),
            CollisionEvent::Stopped(a, b, f) => (false, a, b, f.bits()),
        };
        let a: Vec<_> = mine.0.lock().unwrap().drain(..).map(|e| key(&e)).collect();
        let b: Vec<_> = theirs
            .0
            .lock()
            .unwrap()
            .drain(..)
            .map(|e| key(&e))
            .collect();
        assert_eq!(a, b, "step {step}");
        assert_eq!(
            common::pose_bits(&plain.world),
            common::pose_bits(&layered.world),
            "step {step}"
        );
    }
    // Every collider flagged while tracking touches, and while proximity tracking
    // runs after it (a flag taken off a collider Rapier stepped would count as a
    // change to Rapier); the user's flags once the layer is detached.
    let all_flagged = |w: &PhysicsWorld| {
        w.colliders
            .iter()
            .all(|(_, c)| c.active_events().contains(ActiveEvents::COLLISION_EVENTS))
    };
    assert!(all_flagged(&layered.world));
    layer.set_tracking(Tracking::Proximity);
    common::run_validated(&mut layered, &mut layer, 300, 1);
    assert!(all_flagged(&layered.world));
    layer.detach((&mut layered.world).into());
    assert_eq!(events_flags(&layered.world), before);
}

#[test]
fn tracking_switches_back_and_forth_and_with_the_speedups() {
    let mut scene = scenes::sphere_pile(150, 6);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 60);
    layer.set_tracking(Tracking::Touching);
    common::run_validated(&mut scene, &mut layer, 60, 60);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Touching);
    // A persist subscription needs every pair: proximity tracking while it lasts.
    let (id, rx) =
        layer.subscribe_with_id(Filter::kinds(KindSet::of(&[EventKind::ContactPersisted])));
    common::run_validated(&mut scene, &mut layer, 120, 60);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Proximity);
    assert!(rx.try_iter().count() > 0);
    layer.unsubscribe(id);
    common::run_validated(&mut scene, &mut layer, 180, 60);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Touching);
    layer.set_tracking(Tracking::Proximity);
    common::run_validated(&mut scene, &mut layer, 240, 60);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Proximity);
}

#[test]
fn colliders_added_and_removed_between_steps_keep_their_touches() {
    let mut scene = scenes::sphere_pile(100, 8);
    let mut layer = touching_layer();
    common::run_validated(&mut scene, &mut layer, 0, 150);
    // Remove one ball and drop another in the same pause: the collider count stays.
    let victim = scene
        .world
        .bodies
        .iter()
        .find(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .unwrap();
    scene.world.remove_body(victim);
    scene.world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.3, 0.0)),
        ColliderBuilder::ball(0.25),
    );
    common::run_validated(&mut scene, &mut layer, 150, 150);
}

#[test]
fn touching_tracking_yields_while_someone_asks_for_proximity() {
    let mut scene = scenes::sphere_pile(100, 3);
    let mut layer = ContactLayer::new();
    layer.set_tracking(Tracking::Touching);
    let touches = layer.subscribe(Filter::kinds(
        KindSet::CONTACT.without(KindSet::of(&[EventKind::ContactPersisted])),
    ));
    common::run_validated(&mut scene, &mut layer, 0, 50);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Touching);
    assert!(touches.try_iter().count() > 0);
    let (id, proximity) = layer.subscribe_with_id(Filter::kinds(KindSet::PROXIMITY));
    common::run_validated(&mut scene, &mut layer, 50, 50);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Proximity);
    assert!(proximity.try_iter().count() > 0);
    assert!(layer.unsubscribe(id));
    common::run_validated(&mut scene, &mut layer, 100, 50);
    assert_eq!(layer.analysis().coherence().tracking(), Tracking::Touching);
}
