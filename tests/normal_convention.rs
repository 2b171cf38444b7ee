//! One normal convention: a normal points from the first thing named to the second,
//! as Rapier's manifold normal points from its `collider1` to its `collider2`. An
//! event's normal points from `body1` towards `body2`, an edge's cached normal from
//! its *A* (the events' `node1`) to its *B*, and `contact_details(w, body, other)`
//! from `body` towards `other`; so for one contact they agree, asked from either
//! side. Written as a Rapier user writes it: a ball resting on a box.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, Touching};

use common::build::*;

fn close(a: Vector, b: Vector) -> bool {
    (a - b).length() < 1e-3
}

/// A fixed box, then a ball dropped onto it (`box_first`), or the other way round:
/// the order decides which is `body1` in the events.
fn ball_on_box(box_first: bool) -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle) {
    let mut world = PhysicsWorld::new();
    let insert_box = |w: &mut PhysicsWorld| fixed_box_at(w, [0.0, 0.5, 0.0], 0.5).0;
    if box_first {
        let b = insert_box(&mut world);
        let ball = ball_at(&mut world, [0.0, 1.8, 0.0], 0.25).0;
        (world, b, ball)
    } else {
        let ball = ball_at(&mut world, [0.0, 1.8, 0.0], 0.25).0;
        let b = insert_box(&mut world);
        (world, b, ball)
    }
}

/// The ball lands on the box and rests: the event's normal, the edge's, and
/// `contact_details` from each side name one direction, up from the box, under both
/// trackings and whichever body is `body1`.
#[test]
fn events_details_and_the_edge_agree_for_a_ball_on_a_box() {
    for tracking in [Tracking::Proximity, Tracking::Touching] {
        for box_first in [true, false] {
            let what = format!("{tracking:?}, box first: {box_first}");
            let (mut world, box_body, ball) = ball_on_box(box_first);
            let mut layer = ContactLayer::with_tracking(tracking);
            let kinds = match tracking {
                Tracking::Proximity => KindSet::CONTACT,
                Tracking::Touching => KindSet::COLLISION_EVENTS,
            };
            let rx = layer.subscribe(Filter::kinds(kinds).with_bodies(&[ball]));
            let up = Vector::new(0.0, 1.0, 0.0);
            let mut started = None;
            for _ in 0..120 {
                layer.step(&mut world);
                for e in rx.try_iter() {
                    if !matches!(
                        e.kind,
                        EventKind::ContactStarted | EventKind::ContactPersisted
                    ) {
                        continue;
                    }
                    // From `body1` towards `body2`.
                    let from_box = e.body1 == Some(box_body);
                    assert_eq!(from_box, box_first, "{what}: body1 is the first inserted");
                    let expected = if from_box { up } else { -up };
                    assert!(close(e.normal, expected), "{what}: {e:?}");
                    if e.kind == EventKind::ContactStarted {
                        started = Some(e);
                    }
                }
            }
            let e = started.expect("the ball landed");
            // `contact_details` from each side: the box towards the ball is up.
            let from_box = layer
                .contact_details(&world, box_body, Touching::Body(ball))
                .unwrap()
                .expect("they touch");
            let from_ball = layer
                .contact_details(&world, ball, Touching::Body(box_body))
                .unwrap()
                .expect("they touch");
            assert!(close(from_box.normal, up), "{what}: {:?}", from_box.normal);
            assert!(
                close(from_ball.normal, -up),
                "{what}: {:?}",
                from_ball.normal
            );
            // The push (what the first does to the second) follows: the box pushes
            // the ball up.
            assert!(from_box.push.y > 0.0 && from_ball.push.y < 0.0, "{what}");
            // The event's normal is `contact_details` asked from `body1`.
            let (b1, b2) = (e.body1.unwrap(), e.body2.unwrap());
            let d = layer
                .contact_details(&world, b1, Touching::Body(b2))
                .unwrap()
                .unwrap();
            assert!(close(d.normal, e.normal), "{what}");
            // The edge: A is the events' `node1`; its cached normal, kept under
            // proximity tracking, points from A to B.
            let g = layer.graph();
            let edge = g
                .edge(g.edge_between(e.node1, e.node2.unwrap()).unwrap())
                .unwrap();
            assert_eq!(edge.a(), e.node1, "{what}");
            if tracking == Tracking::Proximity {
                assert!(close(edge.cache().normal, e.normal), "{what}");
                assert!(close(edge.cache().normal, d.normal), "{what}");
            }
        }
    }
}

/// Static geometry (a parentless collider) has no body: the convention is the same,
/// from `node1`'s collider towards `node2`'s in the events, and from the ball towards
/// the collider in `contact_details`.
#[test]
fn a_ball_on_static_geometry() {
    let mut world = PhysicsWorld::new();
    let ground = static_ground(&mut world);
    let (ball, _) = ball_at(&mut world, [0.0, 1.5, 0.0], 0.25);
    let mut layer = ContactLayer::new();
    let rx = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS));
    for _ in 0..120 {
        layer.step(&mut world);
    }
    let e = rx
        .try_iter()
        .find(|e| e.kind == EventKind::ContactStarted)
        .expect("landed");
    // The ground's node came second here (the bodies are read before the
    // parentless colliders): the ball is `node1`, and the normal points down, to the
    // ground.
    let up = Vector::new(0.0, 1.0, 0.0);
    let from_ground = e.collider1 == Some(ground);
    assert!(from_ground || e.collider2 == Some(ground), "{e:?}");
    let expected = if from_ground { up } else { -up };
    assert!(close(e.normal, expected), "{e:?}");
    let d = layer
        .contact_details(&world, ball, Touching::Collider(ground))
        .unwrap()
        .unwrap();
    assert!(
        close(d.normal, Vector::new(0.0, -1.0, 0.0)),
        "{:?}",
        d.normal
    );
}

/// A ball pressed against a wall from the side: the convention is not "up", it is
/// "from the first towards the second".
#[test]
fn a_sideways_contact() {
    let (mut world, _) = world_with_ground();
    let (wall, _) = fixed_box_at(&mut world, [2.0, 1.0, 0.0], 0.5);
    let (ball, _) = ball_at(&mut world, [1.2, 0.75, 0.0], 0.25);
    world.bodies[ball].set_linvel(Vector::new(3.0, 0.0, 0.0), true);
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let rx = layer.subscribe(Filter::kinds(KindSet::CONTACT).with_bodies(&[wall]));
    let mut seen = false;
    for _ in 0..30 {
        layer.step(&mut world);
        for e in rx.try_iter() {
            if e.kind == EventKind::ContactStopped {
                continue;
            }
            seen = true;
            // The wall was inserted before the ball: it is `body1`, and the normal
            // points from it towards the ball, along -x.
            assert_eq!((e.body1, e.body2), (Some(wall), Some(ball)));
            assert!(e.normal.x < -0.99, "{e:?}");
            if let Some(d) = layer
                .contact_details(&world, ball, Touching::Body(wall))
                .unwrap()
            {
                if d.touching {
                    assert!(d.normal.x > 0.99, "{:?}", d.normal);
                }
            }
        }
    }
    assert!(seen, "the ball hit the wall");
}
