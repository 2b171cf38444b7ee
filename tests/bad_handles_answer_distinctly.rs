//! The four bad handles a Rapier user can pass, each answered with its own error (or
//! the documented empty answer), never another body's answer, never a panic: a handle
//! of another world, a removed body, a body the layer has not seen yet, and a
//! collider that is not a sensor asked as one. A removed body answers the same by
//! handle and through its node, at once and after the next step. Every query and
//! every call that takes a handle is asked; `validate()` after every step.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Error, Touching};

use common::audit::{fingerprint, no_panic};
use common::build::*;

/// What a test asks about: a ground, two balls resting on it, a parentless sensor
/// around the first ball, a static block.
struct Scene {
    world: PhysicsWorld,
    ground: RigidBodyHandle,
    ball: RigidBodyHandle,
    ball_collider: ColliderHandle,
    other: RigidBodyHandle,
    sensor: ColliderHandle,
    block: ColliderHandle,
}

fn scene() -> Scene {
    let (mut world, ground) = world_with_ground();
    let (ball, ball_collider) = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5);
    let (other, _) = ball_at(&mut world, [2.0, 1.0, 0.0], 0.5);
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 1.0, 1.0)
            .translation(Vector::new(0.0, 1.0, 0.0))
            .sensor(true),
        None,
    );
    let block = world.insert_collider(
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).translation(Vector::new(-3.0, 1.0, 0.0)),
        None,
    );
    Scene {
        world,
        ground,
        ball,
        ball_collider,
        other,
        sensor,
        block,
    }
}

fn settled(steps: usize) -> (Scene, ContactLayer) {
    let mut s = scene();
    let mut layer = ContactLayer::new();
    for _ in 0..steps {
        layer.step(&mut s.world);
        layer.validate(&s.world).unwrap();
    }
    (s, layer)
}

/// Every call that takes a body handle, asked about `body` of `world` (with `partner`
/// where a call names two), each answer as text or the error. The calls that would
/// change the layer (a rule, a composite) are given only bad handles here.
fn ask_body(
    layer: &mut ContactLayer,
    world: &PhysicsWorld,
    body: RigidBodyHandle,
    partner: RigidBodyHandle,
) -> Vec<(&'static str, Result<String, Error>)> {
    let dbg = |x: &dyn std::fmt::Debug| format!("{x:?}");
    no_panic("queries by body handle", || {
        vec![
            (
                "touching_body",
                layer.touching_body(&world.bodies, body).map(|v| dbg(&v)),
            ),
            (
                "supports_of_body",
                layer.supports_of_body(world, body, 0.0).map(|v| dbg(&v)),
            ),
            (
                "is_grounded",
                layer.is_grounded(world, body).map(|g| dbg(&g)),
            ),
            (
                "contact_details",
                layer
                    .contact_details(world, body, Touching::Body(partner))
                    .map(|c| dbg(&c.map(|c| c.touching))),
            ),
            (
                "sensors_containing",
                layer
                    .sensors_containing(&world.bodies, body)
                    .map(|v| dbg(&v)),
            ),
            (
                "group_of_body",
                layer.group_of_body(&world.bodies, body).map(|v| dbg(&v)),
            ),
            (
                "node_of_body",
                layer.node_of_body(&world.bodies, body).map(|n| dbg(&n)),
            ),
            (
                "logic_mut().ignore_pair",
                layer
                    .logic_mut()
                    .ignore_pair(world, body, partner)
                    .map(|n| dbg(&n)),
            ),
            (
                "logic_mut().set_body_disabled",
                layer
                    .logic_mut()
                    .set_body_disabled(&world.bodies, body, true)
                    .map(|()| "queued".to_string()),
            ),
            (
                "logic_mut().declare_composite",
                layer
                    .logic_mut()
                    .declare_composite(world, &[partner, body])
                    .map(|n| dbg(&n)),
            ),
        ]
    })
}

fn assert_all(answers: &[(&str, Result<String, Error>)], expected: &Error, what: &str) {
    for (q, a) in answers {
        assert_eq!(a.as_ref(), Err(expected), "{what}: {q}");
    }
}

#[test]
fn a_removed_body_is_unknown_by_handle_and_by_node_at_once_and_after_the_step() {
    let (mut s, mut layer) = settled(60);
    let node = layer.node_of_body(&s.world.bodies, s.ball).unwrap();
    s.world.remove_body(s.ball);
    let removed = Error::UnknownBody(s.ball);
    let unchanged = fingerprint(&layer);
    let before = ask_body(&mut layer, &s.world, s.ball, s.other);
    assert_eq!(
        fingerprint(&layer),
        unchanged,
        "the refused calls changed nothing"
    );
    assert_all(&before, &removed, "removed, before the next step");
    // The graph is the last step's until the next one: its node is still there, but
    // the bridge from the handle says what the by-handle queries say.
    assert!(layer.graph().node(node).is_some());
    assert_eq!(
        layer.node_of_collider(&s.world, s.ball_collider),
        Err(Error::UnknownCollider(s.ball_collider))
    );
    layer.step(&mut s.world);
    layer.validate(&s.world).unwrap();
    assert!(layer.graph().node(node).is_none(), "gone with the step");
    let after = ask_body(&mut layer, &s.world, s.ball, s.other);
    assert_eq!(before, after, "the same answers after the step");
}

#[test]
fn a_body_not_seen_yet_answers_empty_and_its_node_is_unseen() {
    let (mut s, mut layer) = settled(30);
    let (fresh, fresh_collider) = ball_at(&mut s.world, [0.0, 1.0, 4.0], 0.5);
    let dbg = |x: &dyn std::fmt::Debug| format!("{x:?}");
    // The documented empty answers.
    assert_eq!(layer.touching_body(&s.world.bodies, fresh), Ok(vec![]));
    assert_eq!(layer.supports_of_body(&s.world, fresh, 0.0), Ok(vec![]));
    assert_eq!(layer.is_grounded(&s.world, fresh), Ok(false));
    assert_eq!(
        layer.contact_details(&s.world, fresh, Touching::Body(s.ground)),
        Ok(None)
    );
    assert_eq!(layer.sensors_containing(&s.world.bodies, fresh), Ok(vec![]));
    assert_eq!(layer.group_of_body(&s.world.bodies, fresh), Ok(vec![]));
    // Calls that need its node: their own error.
    let unseen = Error::UnseenBody(fresh);
    assert_eq!(
        layer.node_of_body(&s.world.bodies, fresh),
        Err(unseen.clone())
    );
    assert_eq!(
        layer
            .logic_mut()
            .ignore_pair(&s.world, fresh, s.ground)
            .map(|n| dbg(&n)),
        Err(unseen.clone())
    );
    assert_eq!(
        layer
            .logic_mut()
            .declare_composite(&s.world, &[fresh, s.ball]),
        Err(unseen.clone())
    );
    assert_eq!(
        layer
            .logic_mut()
            .set_body_disabled(&s.world.bodies, fresh, true),
        Err(unseen)
    );
    assert_eq!(
        layer.node_of_collider(&s.world, fresh_collider),
        Err(Error::UnseenCollider(fresh_collider))
    );
    let new_sensor = s.world.insert_collider(
        ColliderBuilder::ball(0.3)
            .sensor(true)
            .translation(Vector::new(5.0, 3.0, 0.0)),
        None,
    );
    assert_eq!(
        layer.node_of_collider(&s.world, new_sensor),
        Err(Error::UnseenCollider(new_sensor))
    );
    assert_eq!(
        layer.sensor_contents(&s.world.colliders, new_sensor),
        Ok(vec![])
    );
    // The next step sees them.
    layer.step(&mut s.world);
    layer.validate(&s.world).unwrap();
    assert!(layer.node_of_body(&s.world.bodies, fresh).is_ok());
    assert!(layer.node_of_collider(&s.world, new_sensor).is_ok());
}

#[test]
fn a_collider_that_is_not_a_sensor_asked_as_one_is_not_a_sensor() {
    let (s, layer) = settled(30);
    for c in [s.ball_collider, s.block] {
        assert_eq!(
            no_panic("sensor_contents", || layer
                .sensor_contents(&s.world.colliders, c)),
            Err(Error::NotASensor(c))
        );
    }
    // The sensor itself answers: the ball rests inside it.
    assert_eq!(
        layer.sensor_contents(&s.world.colliders, s.sensor),
        Ok(vec![Touching::Body(s.ball)])
    );
}

#[test]
fn another_worlds_handles_are_foreign_even_where_they_are_valid() {
    let (s, mut layer) = settled(30);
    let (mut b, mut layer_b) = settled(30);
    assert_eq!((b.ball, b.other), (s.ball, s.other), "the handles coincide");
    let answers = ask_body(&mut layer, &b.world, s.ball, s.other);
    assert_all(&answers, &Error::ForeignWorld, "world B asked of A's layer");
    assert_eq!(
        layer.node_of_collider(&b.world, s.ball_collider),
        Err(Error::ForeignWorld)
    );
    // B's colliders have shapes of their own (not clones of A's): told apart too.
    assert_eq!(
        layer.sensor_contents(&b.world.colliders, s.sensor),
        Err(Error::ForeignWorld)
    );
    // B's own layer answers for B.
    layer_b.step(&mut b.world);
    layer_b.validate(&b.world).unwrap();
    assert!(layer_b.is_grounded(&b.world, b.ball).unwrap());
}

#[test]
fn the_four_errors_are_distinct_and_say_what_is_wrong() {
    let (s, _) = settled(1);
    let errors = [
        (Error::ForeignWorld, "not the one the layer last analysed"),
        (Error::UnknownBody(s.ball), "removed"),
        (Error::UnseenBody(s.ball), "inserted since"),
        (Error::UnseenCollider(s.sensor), "inserted since"),
        (Error::NotASensor(s.ball_collider), "not a sensor"),
    ];
    for (i, (e, says)) in errors.iter().enumerate() {
        assert!(e.to_string().contains(says), "{e}");
        for (f, _) in &errors[i + 1..] {
            assert_ne!(e, f);
        }
    }
}
