//! Subscriptions filtered by Rapier handle (`Filter::with_bodies`,
//! `Filter::with_colliders`) and `last_events_of_body`, written from a Rapier user's
//! side: the events of one body, and what fired one sensor, under both trackings.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, Event};

use common::build::*;

/// Two balls dropped on the ground, the second through a parentless sensor.
fn scene() -> (
    PhysicsWorld,
    RigidBodyHandle,
    RigidBodyHandle,
    ColliderHandle,
) {
    let (mut world, _) = world_with_ground();
    let (a, _) = ball_at(&mut world, [0.0, 1.5, 0.0], 0.5);
    let (b, _) = ball_at(&mut world, [3.0, 4.0, 0.0], 0.5);
    let sensor = world.insert_collider(
        ColliderBuilder::ball(0.6)
            .sensor(true)
            .translation(Vector::new(3.0, 2.5, 0.0)),
        None,
    );
    (world, a, b, sensor)
}

fn run(tracking: Tracking) {
    let (mut world, a, b, sensor) = scene();
    let mut layer = ContactLayer::new();
    layer.set_tracking(tracking);
    let all = layer.subscribe(Filter::kinds(KindSet::CONTACT | KindSet::SENSOR));
    let of_a = layer.subscribe(Filter::kinds(KindSet::CONTACT).with_bodies(&[a]));
    let of_sensor = layer.subscribe(Filter::kinds(KindSet::SENSOR).with_colliders(&[sensor]));
    let (mut seen_a, mut seen_sensor) = (Vec::new(), Vec::new());
    for _ in 0..120 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        let step: Vec<Event> = all.try_iter().collect();
        let got_a: Vec<Event> = of_a.try_iter().collect();
        let got_sensor: Vec<Event> = of_sensor.try_iter().collect();
        // Exactly the step's events naming the body, in order; the same as the query.
        let want_a: Vec<Event> = step
            .iter()
            .filter(|e| KindSet::CONTACT.contains(e.kind))
            .filter(|e| e.body1 == Some(a) || e.body2 == Some(a))
            .copied()
            .collect();
        assert_eq!(got_a, want_a);
        let queried: Vec<Event> = layer
            .last_events_of_body(a)
            .filter(|e| KindSet::CONTACT.contains(e.kind))
            .copied()
            .collect();
        assert_eq!(queried, want_a);
        // Exactly the trigger events of that sensor.
        let want_sensor: Vec<Event> = step
            .iter()
            .filter(|e| KindSet::SENSOR.contains(e.kind))
            .filter(|e| e.collider1 == Some(sensor))
            .copied()
            .collect();
        assert_eq!(got_sensor, want_sensor);
        seen_a.extend(got_a);
        seen_sensor.extend(got_sensor);
    }
    // Ball a landed (a touch with the ground) and never met ball b.
    assert!(seen_a.iter().any(|e| e.kind == EventKind::ContactStarted));
    assert!(seen_a
        .iter()
        .all(|e| e.body1 != Some(b) && e.body2 != Some(b)));
    // Ball b fell through the sensor: it entered, then left.
    let kinds: Vec<(EventKind, Option<RigidBodyHandle>)> =
        seen_sensor.iter().map(|e| (e.kind, e.body2)).collect();
    assert_eq!(
        kinds,
        [
            (EventKind::SensorStarted, Some(b)),
            (EventKind::SensorStopped, Some(b))
        ]
    );
}

#[test]
fn a_body_filter_receives_exactly_that_bodys_events_under_proximity_tracking() {
    run(Tracking::Proximity);
}

#[test]
fn a_body_filter_receives_exactly_that_bodys_events_under_touching_tracking() {
    run(Tracking::Touching);
}

/// Restrictions add up: a body and a collider restriction together pass the events
/// of either.
#[test]
fn body_and_collider_restrictions_add_up() {
    let (mut world, a, b, sensor) = scene();
    let mut layer = ContactLayer::new();
    let both = layer.subscribe(Filter::all().with_bodies(&[a]).with_colliders(&[sensor]));
    let all = layer.subscribe(Filter::all());
    let mut n = 0;
    for _ in 0..120 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        let want: Vec<Event> = all
            .try_iter()
            .filter(|e| e.body1 == Some(a) || e.body2 == Some(a) || e.collider1 == Some(sensor))
            .collect();
        let got: Vec<Event> = both.try_iter().collect();
        assert_eq!(got, want);
        n += got.len();
        // Ball b's own touch with the ground is in neither restriction.
        assert!(got
            .iter()
            .all(|e| e.collider1 == Some(sensor) || (e.body2 != Some(b) && e.body1 != Some(b))));
    }
    assert!(n > 0);
}

/// A touch begins with its contact normal (from `node1` to `node2`) and the solver's normal
/// impulse: the ball landing on the ground is pushed up. Proximity tracking copies
/// them from the edge, touching tracking and details off read them from Rapier: the
/// three twin worlds give the same bits.
#[test]
fn touch_events_carry_the_contact_normal_and_impulse_under_both_trackings() {
    let begins = |tracking: Tracking, details: bool| {
        let (mut world, a, _, _) = scene();
        let mut layer = ContactLayer::new();
        layer.set_tracking(tracking);
        layer.analysis_mut().set_contact_details(details);
        let rx = layer
            .subscribe(Filter::kinds(KindSet::of(&[EventKind::ContactStarted])).with_bodies(&[a]));
        for _ in 0..120 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
        rx.try_iter().collect::<Vec<Event>>()
    };
    let copied = begins(Tracking::Proximity, true);
    assert_eq!(copied.len(), 1, "the ball lands once: {copied:?}");
    let e = copied[0];
    // The ground (inserted first) is the pair's A: the normal points up, into the ball.
    assert_eq!(e.body2, Some(scene().1));
    assert!(e.normal.y > 0.99, "normal {:?}", e.normal);
    assert!(e.impulse > 0.0, "impulse {}", e.impulse);
    for (tracking, details) in [(Tracking::Touching, true), (Tracking::Proximity, false)] {
        let read = begins(tracking, details);
        assert_eq!(read.len(), 1);
        assert_eq!(
            read[0].normal.to_array(),
            e.normal.to_array(),
            "{tracking:?}"
        );
        assert_eq!(
            read[0].impulse.to_bits(),
            e.impulse.to_bits(),
            "{tracking:?}"
        );
    }
}
