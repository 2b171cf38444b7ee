//! Touching tracking is the default, and it goes on only where the layer's event
//! handler reaches Rapier's step: always with `ContactLayer::step`; in a hand-stepped
//! loop only when the loop passes `event_handler` (or `event_handler_with`). A loop
//! that never does keeps proximity tracking and its colliders' flags untouched; one
//! that stops is read in full and goes back to proximity tracking.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::monitor::MonitorMode;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Error, WorldMut, WorldView};
use rcg_scenes as scenes;

use common::build::*;

/// How a hand-stepped loop hands Rapier the layer's pieces.
#[derive(Clone, Copy, PartialEq)]
enum Feed {
    /// `layer.event_handler()` passed to Rapier.
    Layer,
    /// Rapier's default handler: the layer's never reaches the step.
    None,
}

fn hand_step(world: &mut PhysicsWorld, layer: &mut ContactLayer, feed: Feed) {
    layer.pre_step(WorldMut::from(&mut *world));
    match feed {
        Feed::Layer => world.step_with_events(&layer.hooks(), layer.event_handler()),
        Feed::None => world.step_with_events(&layer.hooks(), &()),
    }
    layer.analyze(WorldView::from(&*world));
    layer.validate(&*world).unwrap();
}

fn flags_set(world: &PhysicsWorld) -> usize {
    world
        .colliders
        .iter()
        .filter(|(_, c)| c.active_events().contains(ActiveEvents::COLLISION_EVENTS))
        .count()
}

#[test]
fn step_tracks_touching_from_the_first_step() {
    let mut scene = scenes::sphere_pile(60, 3);
    let mut layer = ContactLayer::new();
    assert_eq!(
        layer.analysis().coherence().requested_tracking(),
        Tracking::Touching
    );
    assert!(
        !layer.analysis().touching_in_effect(),
        "no step has reached Rapier yet"
    );
    for step in 0..120 {
        common::step_validated(&mut scene, &mut layer, step);
        assert_eq!(
            layer.analysis().coherence().tracking(),
            Tracking::Touching,
            "step {step}"
        );
        assert!(layer.analysis().touching_in_effect());
    }
    assert_eq!(flags_set(&scene.world), scene.world.colliders.len());
    assert!(layer.graph().edges().all(|(_, e)| e.is_touching()));
}

#[test]
fn a_hand_stepped_loop_without_the_layers_handler_keeps_proximity_and_its_flags() {
    let mut scene = scenes::sphere_pile(60, 3);
    let mut layer = ContactLayer::new();
    for _ in 0..150 {
        hand_step(&mut scene.world, &mut layer, Feed::None);
        assert_eq!(layer.analysis().coherence().tracking(), Tracking::Proximity);
        assert!(!layer.analysis().touching_in_effect());
        assert_eq!(
            flags_set(&scene.world),
            0,
            "no flag set for a handler nobody gets"
        );
    }
    assert!(layer.graph().edge_count() > 0);
}

#[test]
fn passing_the_handler_switches_on_and_stopping_switches_back_without_losing_a_touch() {
    let (mut world, _) = world_with_ground();
    let mut balls = Vec::new();
    for i in 0..6 {
        balls.push(
            ball_at(
                &mut world,
                [1.2 * i as Real - 3.0, 0.6 + 0.3 * i as Real, 0.0],
                0.5,
            )
            .0,
        );
    }
    let mut layer = ContactLayer::new();
    let touches = layer.subscribe(Filter::kinds(KindSet::of(&[
        EventKind::ContactStarted,
        EventKind::ContactStopped,
    ])));
    let plan = [
        (Feed::None, 20),
        (Feed::Layer, 40),
        (Feed::None, 30),
        (Feed::Layer, 40),
    ];
    // Per body: touches begun minus touches ended, from the events.
    let mut open = std::collections::HashMap::<RigidBodyHandle, i64>::new();
    for (feed, steps) in plan {
        for k in 0..steps {
            hand_step(&mut world, &mut layer, feed);
            let want = match feed {
                // The first step passing the handler is tracked by touching (its
                // switch reads the touching pairs); flags follow from the next
                // pre-step.
                Feed::Layer => Tracking::Touching,
                // The first step without it is read in full by proximity tracking.
                Feed::None => Tracking::Proximity,
            };
            assert_eq!(
                layer.analysis().coherence().tracking(),
                want,
                "step {k} of {steps}"
            );
            for e in touches.try_iter() {
                let d = if e.kind == EventKind::ContactStarted {
                    1
                } else {
                    -1
                };
                for b in [e.body1, e.body2].into_iter().flatten() {
                    *open.entry(b).or_default() += d;
                }
            }
            // The event stream never loses or repeats a touch across the switches:
            // what it left open is what the graph holds.
            for &b in &balls {
                let n = layer.graph().try_node_of_body(b).unwrap();
                let edges = layer.graph().touching(n).count() as i64;
                assert_eq!(open.get(&b).copied().unwrap_or(0), edges, "{b:?} step {k}");
            }
        }
        if feed == Feed::None {
            assert_eq!(
                flags_set(&world),
                0,
                "the layer's flags are taken off again"
            );
        } else {
            assert_eq!(flags_set(&world), world.colliders.len());
        }
    }
}

#[test]
fn a_persist_subscription_switches_to_proximity_until_it_goes_and_speedups_or_the_monitor_do_not() {
    let mut scene = scenes::sphere_pile(60, 3);
    let mut layer = ContactLayer::new();
    let mut step = 0;
    // `after` steps to take effect (the speed-ups let go of what they hold first),
    // then `n` steps in `want`.
    let mut run = |layer: &mut ContactLayer, after: u64, n: u64, want: Tracking| {
        for _ in 0..after {
            common::step_validated(&mut scene, layer, step);
            step += 1;
        }
        for _ in 0..n {
            common::step_validated(&mut scene, layer, step);
            step += 1;
            assert_eq!(layer.analysis().coherence().tracking(), want, "step {step}");
        }
    };
    run(&mut layer, 0, 10, Tracking::Touching);
    let (id, _rx) =
        layer.subscribe_with_id(Filter::kinds(KindSet::of(&[EventKind::ContactPersisted])));
    run(&mut layer, 0, 10, Tracking::Proximity);
    layer.unsubscribe(id);
    run(&mut layer, 0, 10, Tracking::Touching);
    // The speed-ups and the monitor read what they need from Rapier for the bodies
    // concerned: touching tracking stays.
    layer
        .speedups_mut()
        .set(Some(SpeedUps::contact_graph()))
        .unwrap();
    run(&mut layer, 0, 10, Tracking::Touching);
    common::monitor_in(&mut layer, MonitorMode::Repair);
    run(&mut layer, 0, 10, Tracking::Touching);
    common::monitor_in(&mut layer, MonitorMode::Off);
    layer.speedups_mut().set(None).unwrap();
    run(&mut layer, 3, 10, Tracking::Touching);
}

#[test]
fn the_graphs_normals_are_kept_by_proximity_tracking_only_and_say_so() {
    let build = || {
        let (mut world, _) = world_with_ground();
        let (ball, _) = ball_at(&mut world, [0.0, 0.6, 0.0], 0.5);
        (world, ball)
    };
    let (mut world, ball) = build();
    let (mut w2, _) = build();
    let mut touching = ContactLayer::new();
    let mut proximity = ContactLayer::with_tracking(Tracking::Proximity);
    for _ in 0..30 {
        touching.step(&mut world);
        proximity.step(&mut w2);
    }
    let n = touching.graph().try_node_of_body(ball).unwrap();
    assert!(!touching.analysis().coherence().details_kept());
    assert_eq!(
        touching.analysis().is_supported(n),
        Err(Error::DetailsNotKept)
    );
    // The by-handle query reads Rapier and answers under either tracking.
    assert_eq!(
        touching.supports_of_body(&world, ball, 0.0).unwrap().len(),
        1
    );
    let m = proximity.graph().try_node_of_body(ball).unwrap();
    assert!(proximity.analysis().coherence().details_kept());
    assert_eq!(proximity.analysis().is_supported(m), Ok(true));
    assert_eq!(proximity.supports_of_body(&w2, ball, 0.0).unwrap().len(), 1);
}
