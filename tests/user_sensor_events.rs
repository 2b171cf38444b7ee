//! The user's own `EventHandler`, composed with the layer's through
//! `event_handler_with`, receives exactly the collision events plain Rapier sends,
//! sensor events included, although the layer widens sensors' collision types for its
//! triggers: a sensor on a fixed post over fixed ground and one
//! carried by a kinematic platform over fixed geometry make pairs plain Rapier never
//! reports. A handler wired by hand around `event_handler` does the same through
//! `user_event_filter`.

mod common;

use std::sync::Mutex;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, WorldView};

use common::build::*;

#[derive(Default)]
struct Recorder(Mutex<Vec<(bool, ColliderHandle, ColliderHandle, u32)>>);

impl EventHandler for Recorder {
    fn handle_collision_event(
        &self,
        _: &RigidBodySet,
        _: &ColliderSet,
        event: CollisionEvent,
        _: Option<&ContactPair>,
    ) {
        let e = match event {
            CollisionEvent::Started(a, b, f) => (true, a, b, f.bits()),
            CollisionEvent::Stopped(a, b, f) => (false, a, b, f.bits()),
        };
        self.0.lock().unwrap().push(e);
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

/// Ground, a sensor on a fixed post sunk into it, a kinematic platform carrying a
/// sensor across a fixed block, balls falling through both; every sensor flagged by
/// the user for collision events.
fn world() -> PhysicsWorld {
    let (mut world, _) = world_with_ground();
    let events = ActiveEvents::COLLISION_EVENTS;
    world.insert(
        fixed_at([-2.0, 0.6, 0.0]),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5)
            .sensor(true)
            .active_events(events),
    );
    fixed_box_at(&mut world, [2.0, 1.0, 0.0], 0.5);
    let platform = world.insert_body(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(0.0, 1.0, 0.0))
            .linvel(Vector::new(1.0, 0.0, 0.0)),
    );
    world.insert_collider(
        ColliderBuilder::cuboid(0.6, 0.6, 0.6)
            .sensor(true)
            .active_events(events),
        Some(platform),
    );
    for i in 0..6 {
        ball_at(
            &mut world,
            [-2.0 + 0.8 * i as f32, 3.0 + 0.5 * i as f32, 0.0],
            0.2,
        );
    }
    world
}

#[test]
fn the_users_handler_gets_rapiers_own_sensor_events_despite_widening() {
    let mut plain = world();
    let mut layered = world();
    let (mine, theirs) = (Recorder::default(), Recorder::default());
    let mut layer = ContactLayer::new();
    let mut widened_pairs = 0;
    for step in 0..240 {
        plain.step_with_events(&(), &mine);
        layer.pre_step((&mut layered).into());
        let all = Recorder::default();
        {
            let handler = layer.event_handler_with(&theirs);
            let both = Both(&handler, &all);
            layered.step_with_events(&layer.hooks(), &both);
        }
        layer.analyze(WorldView::from(&layered));
        layer.validate(&layered).unwrap();
        let a: Vec<_> = std::mem::take(&mut *mine.0.lock().unwrap());
        let b: Vec<_> = std::mem::take(&mut *theirs.0.lock().unwrap());
        widened_pairs += all.0.lock().unwrap().len() - b.len();
        assert_eq!(a, b, "step {step}");
        assert_eq!(
            common::pose_bits(&plain),
            common::pose_bits(&layered),
            "step {step}"
        );
    }
    assert!(
        widened_pairs > 0,
        "the scene makes sensor events only the widening causes"
    );
}

/// A handler wired by hand: the user's own calls the layer's for every event, and
/// handles itself what `filter` passes (`None`: everything, the composition the docs
/// refuse).
struct ByHand<'a> {
    layer: &'a rapier_contact_graph::coherence::TouchFeed,
    filter: Option<rapier_contact_graph::coherence::UserEventFilter<'a>>,
    mine: &'a Recorder,
}

impl EventHandler for ByHand<'_> {
    fn handle_collision_event(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        event: CollisionEvent,
        pair: Option<&ContactPair>,
    ) {
        self.layer
            .handle_collision_event(bodies, colliders, event, pair);
        if self
            .filter
            .is_none_or(|f| f.passes(bodies, colliders, &event))
        {
            self.mine
                .handle_collision_event(bodies, colliders, event, pair);
        }
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

/// The hand-wired composition with the layer's filter gets plain Rapier's events
/// exactly; without it, the events of the layer's flags and widening reach the
/// user's handler (which is why the docs support only the filtered one).
#[test]
fn a_handler_wired_by_hand_gets_rapiers_own_events_through_the_filter() {
    for filtered in [true, false] {
        let mut plain = world();
        let mut layered = world();
        let (mine, theirs) = (Recorder::default(), Recorder::default());
        let mut layer = ContactLayer::new();
        layer.logic_mut().set_trigger_widening(true);
        let mut extra = 0;
        for step in 0..240 {
            plain.step_with_events(&(), &mine);
            layer.pre_step((&mut layered).into());
            {
                let handler = ByHand {
                    layer: layer.event_handler(),
                    filter: filtered.then(|| layer.analysis().user_event_filter()),
                    mine: &theirs,
                };
                layered.step_with_events(&layer.hooks(), &handler);
            }
            layer.analyze(WorldView::from(&layered));
            layer.validate(&layered).unwrap();
            let a: Vec<_> = std::mem::take(&mut *mine.0.lock().unwrap());
            let b: Vec<_> = std::mem::take(&mut *theirs.0.lock().unwrap());
            if filtered {
                assert_eq!(a, b, "step {step}");
            }
            extra += b.len() - a.len().min(b.len());
        }
        assert_eq!(
            extra > 0,
            !filtered,
            "filtered {filtered}: {extra} extra events"
        );
    }
}

/// Two handlers in one: the layer's (with the user's) and a recorder of everything
/// Rapier sent.
struct Both<'a, A, B>(&'a A, &'a B);

impl<A: EventHandler, B: EventHandler> EventHandler for Both<'_, A, B> {
    fn handle_collision_event(
        &self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        event: CollisionEvent,
        pair: Option<&ContactPair>,
    ) {
        self.0
            .handle_collision_event(bodies, colliders, event, pair);
        self.1
            .handle_collision_event(bodies, colliders, event, pair);
    }

    fn handle_contact_force_event(
        &self,
        dt: Real,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        pair: &ContactPair,
        force: Real,
    ) {
        self.0
            .handle_contact_force_event(dt, bodies, colliders, pair, force);
    }

    fn handle_soft_body_tear_event(&self, soft: &SoftBodySet, event: &SoftBodyTearEvent) {
        self.0.handle_soft_body_tear_event(soft, event);
    }
}

/// Widening switched off while sensors overlap fixed geometry: the sensors get the
/// user's collision types back, Rapier re-evaluates their pairs, and the triggers are
/// read again (`validate()` at every step). Found by the structural snapshot
/// corruptions (a flipped `widen_sensors` flag); a geometric edge outlived its pair.
#[test]
fn widening_switched_off_gives_sensors_their_types_back() {
    let mut world = world();
    let mut layer = ContactLayer::new();
    for step in 0..120 {
        if step == 40 {
            layer.logic_mut().set_trigger_widening(false);
        }
        layer.step(&mut world);
        layer
            .validate(&world)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
    }
    assert!(world
        .colliders
        .iter()
        .filter(|(_, c)| c.is_sensor())
        .all(|(_, c)| c.active_collision_types() == ActiveCollisionTypes::default()));
}
