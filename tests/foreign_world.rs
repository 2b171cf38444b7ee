//! A layer answers for the world it analysed, never for another one. Two worlds built
//! alike have the same handles: a query given the other world's sets (or a copy of
//! the world) is `Err(ForeignWorld)`, never the analysed world's answer; the same
//! world moved to another variable, or edited since the last step (a body inserted,
//! its storage grown), still answers. Written as a Rapier user writes it.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Error, Touching, WorldView};

use common::build::*;

/// What the queries are asked about.
#[derive(Clone, Copy)]
struct Handles {
    ground: RigidBodyHandle,
    ball: RigidBodyHandle,
    ball_collider: ColliderHandle,
    sensor: ColliderHandle,
}

/// A ball landing on the ground inside a parentless sensor box. Every call builds the
/// same world with the same handles.
fn world() -> (PhysicsWorld, Handles) {
    let (mut world, ground) = world_with_ground();
    let (ball, ball_collider) = ball_at(&mut world, [0.0, 1.5, 0.0], 0.5);
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 1.0, 1.0)
            .translation(Vector::new(0.0, 1.0, 0.0))
            .sensor(true),
        None,
    );
    (
        world,
        Handles {
            ground,
            ball,
            ball_collider,
            sensor,
        },
    )
}

/// Every query that takes a set or a world, asked about `h` of `w`: each answer
/// turned into `Ok(text)` or the error.
fn ask(
    layer: &ContactLayer,
    w: &PhysicsWorld,
    h: Handles,
) -> Vec<(&'static str, Result<String, Error>)> {
    let text = |r: Result<String, Error>| r;
    let dbg = |x: &dyn std::fmt::Debug| format!("{x:?}");
    vec![
        (
            "touching_body",
            text(layer.touching_body(&w.bodies, h.ball).map(|v| dbg(&v))),
        ),
        (
            "supports_of_body",
            text(layer.supports_of_body(w, h.ball, 0.5).map(|v| dbg(&v))),
        ),
        (
            "contact_details",
            text(
                layer
                    .contact_details(w, h.ball, Touching::Body(h.ground))
                    .map(|c| dbg(&c.map(|c| (c.touching, c.normal)))),
            ),
        ),
        (
            "sensor_contents",
            text(
                layer
                    .sensor_contents(&w.colliders, h.sensor)
                    .map(|v| dbg(&v)),
            ),
        ),
        (
            "sensors_containing",
            text(layer.sensors_containing(&w.bodies, h.ball).map(|v| dbg(&v))),
        ),
        (
            "group_of_body",
            text(layer.group_of_body(&w.bodies, h.ball).map(|v| dbg(&v))),
        ),
        (
            "is_grounded",
            text(layer.is_grounded(w, h.ball).map(|g| dbg(&g))),
        ),
        (
            "node_of_body",
            text(layer.node_of_body(&w.bodies, h.ball).map(|n| dbg(&n))),
        ),
        (
            "node_of_collider",
            text(layer.node_of_collider(w, h.ball_collider).map(|n| dbg(&n))),
        ),
        (
            "node_of_collider (view)",
            text(
                layer
                    .node_of_collider(WorldView::from(w), h.sensor)
                    .map(|n| dbg(&n)),
            ),
        ),
        ("validate", text(layer.validate(w).map(|()| "ok".into()))),
        (
            "validate (view)",
            text(layer.validate(&WorldView::from(w)).map(|()| "ok".into())),
        ),
    ]
}

fn assert_all_ok(answers: &[(&str, Result<String, Error>)], what: &str) {
    for (q, a) in answers {
        assert!(a.is_ok(), "{what}: {q} answered {a:?}");
    }
}

fn assert_all_foreign(answers: &[(&str, Result<String, Error>)], what: &str) {
    for (q, a) in answers {
        assert_eq!(a, &Err(Error::ForeignWorld), "{what}: {q}");
    }
}

fn settled(steps: usize) -> (ContactLayer, PhysicsWorld, Handles) {
    let (mut a, h) = world();
    let mut layer = ContactLayer::new();
    for _ in 0..steps {
        layer.step(&mut a);
    }
    (layer, a, h)
}

/// The layer stepped on A, asked with B's sets (B built alike, the handles valid in
/// both, B stepped alike by a layer of its own so that even its contacts are A's):
/// every query is `Err(ForeignWorld)`; with A's, every query answers.
#[test]
fn every_query_refuses_another_worlds_sets() {
    let (layer, a, h) = settled(120);
    let (mut b, hb) = world();
    assert_eq!(
        (hb.ball, hb.sensor),
        (h.ball, h.sensor),
        "the handles coincide"
    );
    let mut layer_b = ContactLayer::new();
    for _ in 0..120 {
        layer_b.step(&mut b);
    }
    let mine = ask(&layer, &a, h);
    assert_all_ok(&mine, "world A");
    // The answers say something: the ball rests on the ground inside the sensor.
    let touching = layer.touching_body(&a.bodies, h.ball).unwrap();
    assert_eq!(touching, vec![Touching::Body(h.ground)]);
    assert_eq!(
        layer.sensor_contents(&a.colliders, h.sensor).unwrap(),
        vec![Touching::Body(h.ball)]
    );
    assert_all_foreign(&ask(&layer, &b, h), "world B");
    // B's own layer answers for B, and refuses A.
    assert_all_ok(&ask(&layer_b, &b, h), "B's layer on B");
    assert_all_foreign(&ask(&layer_b, &a, h), "B's layer on A");
    // Mixed sets: A's bodies with B's colliders.
    let mixed = WorldView {
        colliders: &b.colliders,
        ..WorldView::from(&a)
    };
    assert_eq!(
        layer.supports_of_body(mixed, h.ball, 0.0),
        Err(Error::ForeignWorld)
    );
    assert_eq!(layer.validate(&mixed), Err(Error::ForeignWorld));
    // The error says what to do.
    let msg = Error::ForeignWorld.to_string();
    assert!(msg.contains("not the one the layer last analysed"), "{msg}");
    assert!(msg.contains("pass the world the layer steps"), "{msg}");
}

/// Another world never stepped: the same refusal (nothing about it depends on what
/// the other world holds).
#[test]
fn a_world_never_stepped_is_refused_too() {
    let (layer, _a, h) = settled(60);
    let (b, _) = world();
    assert_all_foreign(&ask(&layer, &b, h), "fresh world B");
}

/// A copy of the analysed world's sets is another world: its contacts may drift apart
/// from the original's from the next step on.
#[test]
fn a_copy_of_the_world_is_another_world() {
    let (layer, a, h) = settled(60);
    let (bodies, colliders) = (a.bodies.clone(), a.colliders.clone());
    assert_eq!(
        layer.touching_body(&bodies, h.ball),
        Err(Error::ForeignWorld)
    );
    // A collider set alone is told by its colliders' shapes, which a copy made with
    // `clone` shares: the documented limit (`Error::ForeignWorld`), pinned here.
    assert_eq!(
        layer.sensor_contents(&colliders, h.sensor),
        layer.sensor_contents(&a.colliders, h.sensor)
    );
    let copy = WorldView {
        bodies: &bodies,
        colliders: &colliders,
        ..WorldView::from(&a)
    };
    assert_eq!(
        layer.contact_details(copy, h.ball, Touching::Body(h.ground)),
        Err(Error::ForeignWorld)
    );
    assert_all_ok(&ask(&layer, &a, h), "the original");
}

/// `holds` is a predicate (no error to give): another world's bodies are not held.
#[test]
fn holds_answers_false_for_another_world() {
    let (layer, a, h) = settled(400);
    assert!(a.bodies[h.ball].is_sleeping(), "the ball fell asleep");
    assert!(layer.analysis().holds(&a.bodies, h.ball));
    let (mut b, _) = world();
    let mut layer_b = ContactLayer::new();
    for _ in 0..400 {
        layer_b.step(&mut b);
    }
    assert!(b.bodies[h.ball].is_sleeping());
    assert!(!layer.analysis().holds(&b.bodies, h.ball));
    assert!(layer_b.analysis().holds(&b.bodies, h.ball));
}

/// Moving the world value (into another variable, a box, a struct) moves no body:
/// the same world answers as before.
#[test]
fn the_same_world_moved_still_answers() {
    let (mut layer, a, h) = settled(120);
    let before = ask(&layer, &a, h);
    let w2 = a;
    assert_eq!(ask(&layer, &w2, h), before);
    let boxed = Box::new(w2);
    assert_eq!(ask(&layer, &boxed, h), before);
    struct Game {
        _score: u32,
        world: PhysicsWorld,
    }
    let mut game = Game {
        _score: 0,
        world: *boxed,
    };
    assert_eq!(ask(&layer, &game.world, h), before);
    layer.step(&mut game.world);
    assert_all_ok(&ask(&layer, &game.world, h), "stepped after the move");
}

/// A world that gained bodies since the last step (enough to grow Rapier's storage,
/// which moves every body) is the same world: the new body answers empty, the others
/// as at the last step; after the next step everything answers.
#[test]
fn a_world_that_grew_since_the_last_step_still_answers() {
    let (mut layer, mut a, h) = settled(120);
    let before = layer.touching_body(&a.bodies, h.ball).unwrap();
    let first = |w: &PhysicsWorld| w.bodies.iter().next().map(|(_, b)| b as *const _ as usize);
    let at_first = first(&a);
    let (one, _) = ball_at(&mut a, [3.0, 1.0, 0.0], 0.25);
    assert_eq!(layer.touching_body(&a.bodies, one), Ok(vec![]));
    assert_eq!(layer.touching_body(&a.bodies, h.ball), Ok(before.clone()));
    assert_eq!(layer.group_of_body(&a.bodies, one), Ok(vec![]));
    let mut added = vec![one];
    for i in 0..200 {
        let x = -4.0 + 0.04 * i as Real;
        added.push(ball_at(&mut a, [x, 4.0 + (i % 7) as Real, 3.0], 0.1).0);
    }
    assert_ne!(first(&a), at_first, "Rapier's body storage grew and moved");
    assert_eq!(layer.touching_body(&a.bodies, h.ball), Ok(before));
    for &b in &added {
        assert_eq!(layer.touching_body(&a.bodies, b), Ok(vec![]));
        assert_eq!(layer.sensors_containing(&a.bodies, b), Ok(vec![]));
    }
    assert!(layer.supports_of_body(&a, h.ball, 0.5).is_ok());
    assert!(layer.sensor_contents(&a.colliders, h.sensor).is_ok());
    layer.step(&mut a);
    assert_all_ok(&ask(&layer, &a, h), "after the next step");
    // A body removed since the last step is unknown, not another world's.
    let gone = added[5];
    a.remove_body(gone);
    assert_eq!(
        layer.touching_body(&a.bodies, gone),
        Err(Error::UnknownBody(gone))
    );
    let queries: Vec<_> = ask(&layer, &a, h)
        .into_iter()
        .filter(|(q, _)| !q.starts_with("validate"))
        .collect();
    assert_all_ok(&queries, "after a removal");
    // `validate` says the layer is behind the world until the next step, not that
    // the world is another.
    assert!(matches!(layer.validate(&a), Err(Error::Invariant(_))));
}

/// The same world edited until no body the layer read is left (the bodies it read
/// removed, Rapier's storage grown and moved, as many bodies as before) still answers:
/// with nothing to compare, the check takes the set for the analysed one.
#[test]
fn the_same_world_edited_until_nothing_read_remains_still_answers() {
    let (mut layer, mut a, h) = settled(30);
    let count = a.bodies.len();
    let first = |w: &PhysicsWorld| w.bodies.iter().next().map(|(_, b)| b as *const _ as usize);
    let at_first = first(&a);
    a.remove_body(h.ball);
    a.remove_body(h.ground);
    let added: Vec<RigidBodyHandle> = (0..200)
        .map(|i| ball_at(&mut a, [-4.0 + 0.04 * i as Real, 4.0, 3.0], 0.1).0)
        .collect();
    for &b in &added[..added.len() - count] {
        a.remove_body(b);
    }
    assert_eq!(a.bodies.len(), count);
    assert_ne!(first(&a), at_first, "Rapier's body storage moved");
    let (one, two) = (added[added.len() - 2], added[added.len() - 1]);
    assert_eq!(layer.touching_body(&a.bodies, one), Ok(vec![]));
    assert_eq!(
        layer.touching_body(&a.bodies, h.ball),
        Err(Error::UnknownBody(h.ball))
    );
    assert_eq!(
        layer.logic_mut().set_body_disabled(&a.bodies, two, true),
        Err(Error::UnseenBody(two))
    );
    layer.step(&mut a);
    assert_eq!(
        layer.logic_mut().set_body_disabled(&a.bodies, two, true),
        Ok(())
    );
    // A copy of it, whose bodies have the handles the layer read, is still told apart.
    let copy = a.bodies.clone();
    assert_eq!(layer.touching_body(&copy, one), Err(Error::ForeignWorld));
    assert!(layer.touching_body(&a.bodies, one).is_ok());
}

/// Before its first step a layer has analysed nothing: no world to refuse, and the
/// documented empty answers for bodies it has not seen.
#[test]
fn before_the_first_step_nothing_is_refused() {
    let (a, h) = world();
    let (b, _) = world();
    let layer = ContactLayer::new();
    for w in [&a, &b] {
        assert_eq!(layer.touching_body(&w.bodies, h.ball), Ok(vec![]));
        assert_eq!(layer.sensor_contents(&w.colliders, h.sensor), Ok(vec![]));
        assert_eq!(layer.validate(w), Ok(()));
    }
}

/// Empty worlds: nothing to tell apart and nothing to ask about; the layer stepped on
/// one validates against another.
#[test]
fn empty_worlds() {
    let mut a = PhysicsWorld::new();
    let b = PhysicsWorld::new();
    let mut layer = ContactLayer::new();
    for _ in 0..3 {
        layer.step(&mut a);
    }
    assert_eq!(layer.validate(&a), Ok(()));
    assert_eq!(layer.validate(&b), Ok(()));
}

/// A layer stepped on another world keeps its documented behaviour: it reads that
/// world in full and follows it; from then on the new world answers and the old one
/// is refused.
#[test]
fn a_layer_stepped_on_another_world_follows_it() {
    let (mut layer, a, h) = settled(120);
    let (mut b, _) = world();
    // B's ball still falls: at the first step on B, nothing touches it.
    layer.step(&mut b);
    assert_all_ok(&ask(&layer, &b, h), "the world stepped now");
    assert_eq!(layer.touching_body(&b.bodies, h.ball), Ok(vec![]));
    assert_all_foreign(&ask(&layer, &a, h), "the world stepped before");
    for _ in 0..120 {
        layer.step(&mut b);
    }
    assert_eq!(
        layer.touching_body(&b.bodies, h.ball),
        Ok(vec![Touching::Body(h.ground)])
    );
    layer.validate(&b).unwrap();
}
