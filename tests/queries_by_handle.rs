//! Queries by Rapier handle, from the user's side: what touches a
//! body, what holds it up, what is inside a sensor, which sensors a body is in, a
//! body's contact group. Checked against Rapier's own narrow phase at every step; a
//! body inserted since the last step answers empty, a removed one is an error.

mod common;

use std::collections::BTreeSet;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Error, Touching};

use common::build::*;

/// A ground body, a parentless ledge, balls falling on both, and a sensor box on the
/// ground the balls fall into.
fn scene() -> (
    PhysicsWorld,
    Vec<RigidBodyHandle>,
    ColliderHandle,
    ColliderHandle,
) {
    let (mut world, _) = world_with_ground();
    let ledge = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.2, 1.0).translation(Vector::new(3.0, 1.5, 0.0)),
        None,
    );
    let (_, sensor) = world.insert(
        fixed_at([-2.0, 1.0, 0.0]),
        ColliderBuilder::cuboid(1.0, 0.5, 1.0).sensor(true),
    );
    let mut balls = Vec::new();
    for (i, x) in [-2.2, -1.8, 0.0, 0.3, 3.0, 3.2].into_iter().enumerate() {
        balls.push(ball_at(&mut world, [x, 2.0 + 0.7 * i as f32, 0.0], 0.3).0);
    }
    (world, balls, sensor, ledge)
}

#[test]
fn touching_bodies_are_rapiers_touching_pairs_at_every_step() {
    let (mut world, balls, sensor, _) = scene();
    let mut layer = ContactLayer::new();
    let (mut checked, mut held) = (0, 0);
    for step in 0..240 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        for (h, _) in world.bodies.iter() {
            let ours: BTreeSet<String> = layer
                .touching_body(&world.bodies, h)
                .unwrap()
                .iter()
                .map(|t| format!("{t:?}"))
                .collect();
            assert_eq!(ours, rapier_touching(&world, h), "step {step}, body {h:?}");
            checked += ours.len();
        }
        // Sensor contents against Rapier's intersections, both ways.
        let inside: BTreeSet<(u32, u32)> = world
            .narrow_phase
            .intersection_pairs_with(sensor)
            .filter(|(_, _, hit)| *hit)
            .filter_map(|(a, b, _)| world.colliders[if a == sensor { b } else { a }].parent())
            .map(|h| h.into_raw_parts())
            .collect();
        let ours: BTreeSet<(u32, u32)> = layer
            .sensor_contents(&world.colliders, sensor)
            .unwrap()
            .into_iter()
            .filter_map(|t| match t {
                Touching::Body(b) => Some(b.into_raw_parts()),
                Touching::Collider(_) => None,
            })
            .collect();
        assert_eq!(ours, inside, "step {step}: inside the sensor");
        held += inside.len();
        for &b in &balls {
            let in_sensor = layer.sensors_containing(&world.bodies, b).unwrap() == vec![sensor];
            assert_eq!(
                in_sensor,
                inside.contains(&b.into_raw_parts()),
                "step {step}: {b:?} in the sensor"
            );
        }
    }
    assert!(
        checked > 0 && held > 0,
        "the scene makes contacts and fills the sensor"
    );
}

#[test]
fn a_resting_ball_is_held_up_by_the_ground_and_grouped_with_what_it_touches() {
    let (mut world, balls, _, ledge) = scene();
    let ground = world.bodies.iter().next().unwrap().0;
    let mut layer = ContactLayer::new();
    for _ in 0..300 {
        layer.step(&mut world);
    }
    layer.validate(&world).unwrap();
    // Balls 2 and 3 land on the ground, balls 4 and 5 on the ledge.
    let supports = layer.supports_of_body(&world, balls[2], 0.5).unwrap();
    assert!(supports.contains(&Touching::Body(ground)), "{supports:?}");
    let on_ledge = layer.supports_of_body(&world, balls[4], 0.5).unwrap();
    assert!(
        on_ledge.contains(&Touching::Collider(ledge)),
        "{on_ledge:?}"
    );
    for &b in &balls {
        let group = layer.group_of_body(&world.bodies, b).unwrap();
        if !group.is_empty() {
            assert!(group.contains(&b), "a body is in its own group");
        }
        for t in layer.touching_body(&world.bodies, b).unwrap() {
            if let Touching::Body(other) = t {
                if world.bodies[other].is_dynamic() && !group.is_empty() {
                    assert!(
                        group.contains(&other),
                        "touching dynamic bodies share a group"
                    );
                }
            }
        }
    }
    assert!(
        layer
            .group_of_body(&world.bodies, ground)
            .unwrap()
            .is_empty(),
        "a fixed body insulates: in no group"
    );
}

#[test]
fn new_bodies_answer_empty_and_removed_ones_are_errors() {
    let (mut world, balls, sensor, ledge) = scene();
    let mut layer = ContactLayer::new();
    for _ in 0..60 {
        layer.step(&mut world);
    }
    // Inserted since the last step, overlapping the ground: no contacts yet.
    let (new, _) = ball_at(&mut world, [0.0, 0.6, 2.0], 0.3);
    assert_eq!(layer.touching_body(&world.bodies, new), Ok(Vec::new()));
    assert_eq!(layer.supports_of_body(&world, new, 0.0), Ok(Vec::new()));
    assert_eq!(layer.sensors_containing(&world.bodies, new), Ok(Vec::new()));
    assert_eq!(layer.group_of_body(&world.bodies, new), Ok(Vec::new()));
    // Removed (before or after the next step): an error naming the handle.
    world.remove_body(balls[0]);
    assert_eq!(
        layer.touching_body(&world.bodies, balls[0]),
        Err(Error::UnknownBody(balls[0]))
    );
    layer.step(&mut world);
    for query in [
        layer.touching_body(&world.bodies, balls[0]),
        layer.supports_of_body(&world, balls[0], 0.0),
    ] {
        assert_eq!(query, Err(Error::UnknownBody(balls[0])));
    }
    assert_eq!(
        layer.group_of_body(&world.bodies, balls[0]),
        Err(Error::UnknownBody(balls[0]))
    );
    // A collider that is not a sensor, or not in the world.
    assert_eq!(
        layer.sensor_contents(&world.colliders, ledge),
        Err(Error::NotASensor(ledge))
    );
    assert!(Error::NotASensor(ledge)
        .to_string()
        .contains("is not a sensor"));
    world.remove_collider(sensor);
    assert_eq!(
        layer.sensor_contents(&world.colliders, sensor),
        Err(Error::UnknownCollider(sensor))
    );
    assert!(matches!(
        layer.supports_of_body(&world, balls[1], f32::NAN),
        Err(Error::NonFinite(_))
    ));
}

/// Events carry Rapier's handles: a trigger event names the sensor collider that
/// fired and the body that entered; a touch with static geometry names its collider.
#[test]
fn events_name_the_sensor_and_the_static_collider() {
    use rapier_contact_graph::events::{EventKind, Filter, KindSet};
    let (mut world, balls, sensor, ledge) = scene();
    let mut layer = ContactLayer::new();
    let rx = layer.subscribe(Filter::kinds(KindSet::SENSOR | EventKind::ContactStarted));
    for _ in 0..240 {
        layer.step(&mut world);
    }
    let events: Vec<_> = rx.try_iter().collect();
    let enters: Vec<_> = events
        .iter()
        .filter(|e| e.kind == EventKind::SensorStarted)
        .collect();
    assert!(!enters.is_empty(), "balls fall into the sensor");
    for e in &enters {
        assert_eq!(e.collider1, Some(sensor), "{e:?}");
    }
    assert!(
        enters
            .iter()
            .any(|e| e.body2.is_some_and(|b| balls.contains(&b))),
        "a ball's entry names the ball"
    );
    let on_ledge = events.iter().any(|e| {
        e.kind == EventKind::ContactStarted
            && (e.collider1 == Some(ledge) || e.collider2 == Some(ledge))
    });
    assert!(on_ledge, "a touch with the ledge names its collider");
    // A contact event names the collider pair Rapier reported: a collider of each
    // body (`collider1` of `body1`), as Rapier's `CollisionEvent` does.
    for e in events
        .iter()
        .filter(|e| e.kind == EventKind::ContactStarted)
    {
        let owner = |c: Option<ColliderHandle>| c.and_then(|c| world.colliders[c].parent());
        assert!(e.collider1.is_some() && e.collider2.is_some(), "{e:?}");
        assert_eq!(owner(e.collider1), e.body1, "{e:?}");
        assert_eq!(owner(e.collider2), e.body2, "{e:?}");
    }
}

/// Contact details on demand: `contact_details` and `supports_of_body` read Rapier's
/// narrow phase, so touching tracking (which copies no detail into the graph)
/// answers exactly what proximity tracking with its per-edge details answers, at
/// every step of twin worlds (the flag touching tracking sets changes no trajectory
/// bit); and `contact_details` equals the edge's per-step copy, oriented from the
/// body asked about.
#[test]
fn contact_details_on_demand_equal_the_per_step_copy_under_both_trackings() {
    use rapier_contact_graph::coherence::Tracking;
    let (mut w1, balls, _, ledge) = scene();
    let (mut w2, _, _, _) = scene();
    let mut proximity = ContactLayer::with_tracking(Tracking::Proximity);
    let mut touching = ContactLayer::new();
    let mut compared = 0;
    for _ in 0..150 {
        proximity.step(&mut w1);
        touching.step(&mut w2);
        proximity.validate(&w1).unwrap();
        touching.validate(&w2).unwrap();
        assert!(touching.analysis().touching_in_effect());
        for &b in &balls {
            let s1 = proximity.supports_of_body(&w1, b, 0.5).unwrap();
            let s2 = touching.supports_of_body(&w2, b, 0.5).unwrap();
            assert_eq!(s1, s2, "supports of {b:?}");
            for other in proximity.touching_body(&w1.bodies, b).unwrap() {
                let d1 = proximity.contact_details(&w1, b, other).unwrap().unwrap();
                let d2 = touching.contact_details(&w2, b, other).unwrap().unwrap();
                let key = |c: &rapier_contact_graph::ContactCache| {
                    (
                        c.touching,
                        c.contact_count,
                        c.min_distance.to_bits(),
                        c.normal_impulse.to_bits(),
                        c.normal.to_array().map(f32::to_bits),
                        c.push.to_array().map(f32::to_bits),
                    )
                };
                assert_eq!(key(&d1), key(&d2));
                // The per-step copy, oriented from the edge's A to B.
                let n = proximity.graph().try_node_of_body(b).unwrap();
                let m = match other {
                    Touching::Body(h) => proximity.graph().try_node_of_body(h).unwrap(),
                    Touching::Collider(c) => proximity.graph().node_of_static_collider(c).unwrap(),
                };
                let e = proximity.graph().edge_between(n, m).unwrap();
                let cache = proximity.graph().edge(e).unwrap().cache();
                let sign = if n.index() < m.index() { 1.0 } else { -1.0 };
                assert_eq!(cache.contact_count, d1.contact_count);
                assert_eq!(cache.min_distance.to_bits(), d1.min_distance.to_bits());
                assert_eq!((cache.normal * sign).to_array(), d1.normal.to_array());
                compared += 1;
            }
        }
    }
    assert!(compared > 100, "only {compared} contacts compared");
    // Not near: no contact pair. Unknown handles: errors.
    assert_eq!(
        proximity
            .contact_details(&w1, balls[0], Touching::Collider(ledge))
            .unwrap(),
        None
    );
    let gone = balls[1];
    w1.remove_body(gone);
    assert!(matches!(
        proximity.contact_details(&w1, gone, Touching::Body(balls[0])),
        Err(Error::UnknownBody(_))
    ));
    assert!(matches!(
        proximity.supports_of_body(&w1, gone, 0.0),
        Err(Error::UnknownBody(_))
    ));
}
