//! Contact and sensor events name the collider pair Rapier reported, as Rapier's own
//! `CollisionEvent::Started(c1, c2, _)` does, oriented as the event's bodies
//! (`collider1` is `body1`'s); so `Filter::with_colliders` receives contacts as it
//! receives sensor events. Two bodies touching through several collider pairs send one
//! event per change, naming one pair by a documented rule (`Event::collider1`): the
//! same under touching and proximity tracking and under both pair walks. Written as a
//! Rapier user writes it.

mod common;

use std::collections::{BTreeMap, BTreeSet, HashMap};

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::{ScanPolicy, Tracking};
use rapier_contact_graph::events::{Event, EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, EdgeKind};

use common::build::*;

type Pair = (ColliderHandle, ColliderHandle);

fn raw(p: Pair) -> ((u32, u32), (u32, u32)) {
    (p.0.into_raw_parts(), p.1.into_raw_parts())
}

/// A box resting on the ground and a ball falling onto it.
struct BallOnBox {
    world: PhysicsWorld,
    box_body: RigidBodyHandle,
    box_collider: ColliderHandle,
    ball: RigidBodyHandle,
    ball_collider: ColliderHandle,
}

fn ball_on_box() -> BallOnBox {
    let mut world = PhysicsWorld::new();
    let (box_body, box_collider) = fixed_box_at(&mut world, [0.0, 0.5, 0.0], 0.5);
    let (ball, ball_collider) = ball_at(&mut world, [0.0, 2.0, 0.0], 0.25);
    BallOnBox {
        world,
        box_body,
        box_collider,
        ball,
        ball_collider,
    }
}

/// The case: a ball landing on a box. `ContactStarted` names the box's
/// collider and the ball's (the box is `body1`), and a subscription by the ball's
/// collider receives it, under either tracking.
#[test]
fn a_ball_landing_on_a_box_names_both_colliders() {
    for tracking in [Tracking::Touching, Tracking::Proximity] {
        let mut s = ball_on_box();
        let mut layer = ContactLayer::with_tracking(tracking);
        let by_collider = layer
            .subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_colliders(&[s.ball_collider]));
        let by_box = layer
            .subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_colliders(&[s.box_collider]));
        for _ in 0..120 {
            layer.step(&mut s.world);
        }
        let started: Vec<Event> = by_collider
            .try_iter()
            .filter(|e| e.kind == EventKind::ContactStarted)
            .collect();
        assert_eq!(started.len(), 1, "{tracking:?}: one landing {started:?}");
        let e = started[0];
        assert_eq!((e.body1, e.body2), (Some(s.box_body), Some(s.ball)));
        assert_eq!(
            (e.collider1, e.collider2),
            (Some(s.box_collider), Some(s.ball_collider)),
            "{tracking:?}"
        );
        assert_eq!(
            by_box.try_iter().collect::<Vec<_>>(),
            vec![e],
            "the box's collider names the same event"
        );
        // The ball leaves: `ContactStopped` names the same pair.
        s.world.bodies[s.ball].set_linvel(Vector::new(0.0, 6.0, 0.0), true);
        for _ in 0..10 {
            layer.step(&mut s.world);
        }
        let stopped: Vec<Event> = by_collider.try_iter().collect();
        assert_eq!(stopped.len(), 1, "{tracking:?}: {stopped:?}");
        assert_eq!(stopped[0].kind, EventKind::ContactStopped);
        assert_eq!(
            (stopped[0].collider1, stopped[0].collider2),
            (Some(s.box_collider), Some(s.ball_collider))
        );
    }
}

/// A removed body's contacts stop naming its (now removed) collider, as Rapier's
/// `Stopped` event with its `REMOVED` flag does.
#[test]
fn a_removed_body_stops_its_contacts_by_name() {
    let mut s = ball_on_box();
    let mut layer = ContactLayer::new();
    let rx = layer
        .subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_colliders(&[s.ball_collider]));
    for _ in 0..120 {
        layer.step(&mut s.world);
    }
    assert_eq!(rx.try_iter().count(), 1);
    s.world.remove_body(s.ball);
    layer.step(&mut s.world);
    let stopped: Vec<Event> = rx.try_iter().collect();
    assert_eq!(stopped.len(), 1, "{stopped:?}");
    assert_eq!(stopped[0].kind, EventKind::ContactStopped);
    assert_eq!(stopped[0].collider2, Some(s.ball_collider));
    assert_eq!(stopped[0].collider1, Some(s.box_collider));
}

/// Sensor events name the sensor and the collider that entered or left it; a
/// subscription by that collider receives its sensor events and its contacts.
#[test]
fn sensor_events_name_the_collider_inside() {
    let (mut world, ground) = world_with_ground();
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.5, 1.0)
            .translation(Vector::new(0.0, 2.0, 0.0))
            .sensor(true),
        None,
    );
    let ground_collider = world.bodies[ground].colliders()[0];
    let (ball, ball_collider) = ball_at(&mut world, [0.0, 4.0, 0.0], 0.25);
    let mut layer = ContactLayer::new();
    let rx =
        layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_colliders(&[ball_collider]));
    for _ in 0..150 {
        layer.step(&mut world);
    }
    let events: Vec<Event> = rx.try_iter().collect();
    let kinds: Vec<EventKind> = events.iter().map(|e| e.kind).collect();
    assert_eq!(
        kinds,
        vec![
            EventKind::SensorStarted,
            EventKind::SensorStopped,
            EventKind::ContactStarted
        ],
        "{events:?}"
    );
    for e in &events[..2] {
        assert_eq!(
            (e.collider1, e.collider2),
            (Some(sensor), Some(ball_collider))
        );
        assert_eq!(e.body2, Some(ball));
    }
    assert_eq!(
        (events[2].collider1, events[2].collider2),
        (Some(ground_collider), Some(ball_collider))
    );
}

/// Compound bodies (two balls each) landing on a floor of three tiles of one fixed
/// body, jumping, and landing again: several collider pairs per pair of bodies.
fn compound_scene() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = PhysicsWorld::new();
    let floor = world.insert_body(RigidBodyBuilder::fixed());
    for x in [-2.2, 0.0, 2.2] {
        world.insert_collider(
            ColliderBuilder::cuboid(1.0, 0.25, 3.0).translation(Vector::new(x, 0.0, 0.0)),
            Some(floor),
        );
    }
    // Two long bars lying across the middle tile's edges: each touches two tiles
    // through one collider, and the middle tile's drop (`run_compound`) takes one of
    // its touching pairs away while the other stays.
    for z in [-2.0, 2.0] {
        let h =
            world.insert_body(RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.45, z)));
        world.insert_collider(ColliderBuilder::cuboid(1.6, 0.2, 0.2), Some(h));
    }
    let mut bodies = Vec::new();
    for i in 0..6 {
        let x = -2.5 + i as Real;
        let tilt = 0.15 * (i % 3) as Real - 0.15;
        let h = world.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, 1.0 + 0.4 * i as Real, 0.6 * (i % 2) as Real))
                .rotation(Vector::new(0.0, 0.7 * i as Real, tilt)),
        );
        for dx in [-0.45, 0.45] {
            world.insert_collider(
                ColliderBuilder::ball(0.3).translation(Vector::new(dx, 0.0, 0.0)),
                Some(h),
            );
        }
        bodies.push(h);
    }
    (world, bodies)
}

/// The collider pairs touching in Rapier now, each as (lower handle, higher).
fn rapier_touching(world: &PhysicsWorld) -> BTreeSet<((u32, u32), (u32, u32))> {
    world
        .narrow_phase
        .contact_pairs()
        .filter(|p| p.has_any_active_contact())
        .map(|p| {
            let (a, b) = (p.collider1.into_raw_parts(), p.collider2.into_raw_parts());
            (a.min(b), a.max(b))
        })
        .collect()
}

fn unordered(p: Pair) -> ((u32, u32), (u32, u32)) {
    let (a, b) = raw(p);
    (a.min(b), a.max(b))
}

/// Who owns a collider: its body, or itself.
fn owner(world: &PhysicsWorld, c: ColliderHandle) -> Option<RigidBodyHandle> {
    world.colliders.get(c).and_then(|c| c.parent())
}

/// Runs the compound scene under `tracking` and `policy`, checking every contact
/// event's collider pair against Rapier as it goes; returns the contact starts and
/// stops as (step, kind, body1, body2, collider1, collider2).
/// A contact start or stop: step, kind, `body1`, `body2`, the collider pair named.
type Change = (
    u64,
    EventKind,
    Option<RigidBodyHandle>,
    Option<RigidBodyHandle>,
    Pair,
);

/// Per step, each touching edge (by its nodes' sources) with the pair it names.
type Names = Vec<Vec<(String, ((u32, u32), (u32, u32)))>>;

fn run_compound(tracking: Tracking, policy: ScanPolicy) -> (Vec<Change>, Names) {
    let (mut world, bodies) = compound_scene();
    let mut layer = ContactLayer::with_tracking(tracking);
    layer.analysis_mut().set_scan_policy(policy);
    let kinds = match tracking {
        Tracking::Touching => KindSet::COLLISION_EVENTS,
        Tracking::Proximity => KindSet::CONTACT | KindSet::PROXIMITY,
    };
    let rx = layer.subscribe(Filter::kinds(kinds));
    // What each pair of bodies named at the last step (the persisted events tell).
    let mut named: HashMap<(Option<RigidBodyHandle>, Option<RigidBodyHandle>), Pair> =
        HashMap::new();
    let mut before = rapier_touching(&world);
    let mut out = Vec::new();
    let mut edge_names: BTreeMap<String, Pair> = BTreeMap::new();
    let mut names_per_step = Vec::new();
    for step in 0..400u64 {
        if step == 200 {
            for &b in &bodies {
                world.bodies[b].set_linvel(Vector::new(0.3, 4.0, 0.0), true);
            }
        }
        if step == 320 {
            // The middle tile drops in place: the pairs on it stop, those on the
            // other tiles go on.
            let tile = world.colliders.iter().nth(1).map(|(h, _)| h).unwrap();
            world.colliders[tile]
                .set_position_wrt_parent(Pose::from_translation(Vector::new(0.0, -1.0, 0.0)));
            for (_, rb) in world.bodies.iter_mut() {
                rb.wake_up(true);
            }
        }
        layer.step(&mut world);
        let now = rapier_touching(&world);
        // Every touching edge names a pair touching now; the one named at the last step
        // if it still touches.
        let g = layer.graph();
        let mut edges_now = BTreeMap::new();
        for (_, e) in g
            .edges()
            .filter(|(_, e)| e.is_touching() && e.kind() == EdgeKind::Physical)
        {
            let pair = e.colliders().expect("a touching edge names a pair");
            assert!(now.contains(&unordered(pair)), "step {step}: {pair:?}");
            let key = (
                g.node(e.a()).unwrap().source(),
                g.node(e.b()).unwrap().source(),
            );
            let key = format!("{key:?}");
            if let Some(&last) = edge_names.get(&key) {
                if now.contains(&unordered(last)) {
                    assert_eq!(pair, last, "step {step}: kept while it touches");
                }
            }
            edges_now.insert(key, pair);
        }
        names_per_step.push(
            edges_now
                .iter()
                .map(|(k, p)| (k.clone(), raw(*p)))
                .collect::<Vec<_>>(),
        );
        edge_names = edges_now;
        for e in rx.try_iter() {
            let pair = (
                e.collider1.expect("collider1 named"),
                e.collider2.expect("collider2 named"),
            );
            // Oriented as the bodies.
            assert_eq!(owner(&world, pair.0).or(e.body1), e.body1, "{e:?}");
            assert_eq!(owner(&world, pair.1).or(e.body2), e.body2, "{e:?}");
            let bodies_key = (e.body1, e.body2);
            match e.kind {
                EventKind::ContactStarted => {
                    // The touching pair of the two bodies with the smallest handles.
                    let of = |b: Option<RigidBodyHandle>| -> Vec<ColliderHandle> {
                        b.map(|b| world.bodies[b].colliders().to_vec())
                            .unwrap_or_default()
                    };
                    let smallest = of(e.body1)
                        .into_iter()
                        .flat_map(|c1| of(e.body2).into_iter().map(move |c2| (c1, c2)))
                        .filter(|&p| now.contains(&unordered(p)))
                        .min_by_key(|&p| raw(p));
                    assert_eq!(Some(pair), smallest, "step {step}: {e:?}");
                    named.insert(bodies_key, pair);
                }
                EventKind::ContactPersisted => {
                    assert!(now.contains(&unordered(pair)), "step {step}: {e:?}");
                    // Kept while it touches.
                    if let Some(&last) = named.get(&bodies_key) {
                        if now.contains(&unordered(last)) {
                            assert_eq!(pair, last, "step {step}: {e:?}");
                        }
                    }
                    named.insert(bodies_key, pair);
                }
                EventKind::ContactStopped => {
                    // One of the pairs that touched at the last step.
                    assert!(before.contains(&unordered(pair)), "step {step}: {e:?}");
                    assert!(!now.contains(&unordered(pair)), "step {step}: {e:?}");
                    named.remove(&bodies_key);
                }
                _ => continue,
            }
            if matches!(
                e.kind,
                EventKind::ContactStarted | EventKind::ContactStopped
            ) {
                out.push((step, e.kind, e.body1, e.body2, pair));
            }
        }
        before = now;
    }
    assert!(
        out.iter()
            .filter(|x| x.1 == EventKind::ContactStopped)
            .count()
            >= bodies.len(),
        "the bodies jumped: {out:?}"
    );
    (out, names_per_step)
}

/// Several collider pairs per pair of bodies: each event names a pair Rapier
/// reports, by the documented rule, and the rule gives the same names under
/// touching and proximity tracking and under both pair walks.
#[test]
fn compound_bodies_name_one_pair_by_the_rule_under_every_tracking() {
    let (touching, names) = run_compound(Tracking::Touching, ScanPolicy::Auto);
    // Several pairs per pair of bodies did touch.
    let pairs_per_bodies: BTreeMap<_, BTreeSet<_>> =
        touching.iter().fold(BTreeMap::new(), |mut m, x| {
            let key = (
                x.2.map(|b| b.into_raw_parts()),
                x.3.map(|b| b.into_raw_parts()),
            );
            m.entry(key).or_default().insert(raw(x.4));
            m
        });
    assert!(
        pairs_per_bodies.values().any(|s| s.len() > 1),
        "a pair of bodies named two collider pairs over the run: {pairs_per_bodies:?}"
    );
    // An edge changed the pair it names while it kept touching (the named pair
    // stopped, another went on).
    let renamed = names.windows(2).any(|w| {
        w[1].iter()
            .any(|(k, p)| w[0].iter().any(|(k0, p0)| k0 == k && p0 != p))
    });
    assert!(renamed, "a touching edge was renamed");
    // Within a step the trackings refresh edges in different orders (the events'
    // order is each tracking's refresh order): compared step by step as sets.
    let sorted = |mut v: Vec<Change>| {
        v.sort_by_key(|x| {
            (
                x.0,
                x.1,
                x.2.map(|b| b.into_raw_parts()),
                x.3.map(|b| b.into_raw_parts()),
            )
        });
        v
    };
    let touching = sorted(touching);
    for policy in [ScanPolicy::Walk, ScanPolicy::Scan] {
        let (changes, names_p) = run_compound(Tracking::Proximity, policy);
        assert_eq!(sorted(changes), touching, "{policy:?}");
        assert_eq!(names_p, names, "{policy:?}");
    }
}

/// A collider subscription receives exactly the events naming the collider.
#[test]
fn with_colliders_receives_exactly_the_events_naming_the_collider() {
    let (mut world, bodies) = compound_scene();
    let watched = world.bodies[bodies[2]].colliders()[1];
    let mut layer = ContactLayer::new();
    let all = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS));
    let mine = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_colliders(&[watched]));
    let mut expected = Vec::new();
    let mut got = Vec::new();
    for step in 0..400 {
        if step == 200 {
            world.bodies[bodies[2]].set_linvel(Vector::new(0.0, 4.0, 0.0), true);
        }
        layer.step(&mut world);
        expected.extend(
            all.try_iter()
                .filter(|e| e.collider1 == Some(watched) || e.collider2 == Some(watched)),
        );
        got.extend(mine.try_iter());
    }
    assert!(!got.is_empty(), "the watched ball touched the floor");
    assert_eq!(got, expected);
}
