//! Programs written as a Rapier user writes them, asserting what
//! such a user expects, by Rapier handle:
//! - a mixed scene (ground, ramp, 48 boxes and balls) with a sensor carried by a
//!   kinematic platform: events per body and per sensor with their handles, the
//!   sensor's contents equal to Rapier's own intersections, touches equal to Rapier's
//!   contact pairs, the user's collision types as built;
//! - a pile with the presets: warm start and contact recycling stay the user's, the
//!   pile is held or asleep and says so in events, and `detach` gives every body back
//!   dynamic.
//!
//! The third such program, a hand-stepped pipeline with the user's own hooks
//! and event collector, is `tests/user_hooks_composed.rs` and
//! `tests/user_sensor_events.rs`.

mod common;

use std::collections::BTreeSet;

use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Touching};
use rcg_scenes as scenes;

use common::build::*;

struct Mixed {
    world: PhysicsWorld,
    platform: RigidBodyHandle,
    sensor: ColliderHandle,
    sensor_types: ActiveCollisionTypes,
    dynamic: Vec<RigidBodyHandle>,
}

fn mixed_scene() -> Mixed {
    let (mut world, _) = world_with_ground();
    world.integration_parameters.dt = 0.01;
    // A ramp down towards the platform's path.
    world.insert(
        RigidBodyBuilder::fixed()
            .translation(Vector::new(-6.0, 1.0, 0.0))
            .rotation(Vector::new(0.0, 0.0, -0.3)),
        ColliderBuilder::cuboid(3.0, 0.2, 3.0),
    );
    let mut dynamic = Vec::new();
    for i in 0..48 {
        let (x, z, y) = ((i % 4) as Real, ((i / 4) % 4) as Real, (i / 16) as Real);
        let at = Vector::new(-7.5 + 0.9 * x, 3.0 + 0.9 * y, -1.5 + 0.9 * z);
        let body = RigidBodyBuilder::dynamic().translation(at);
        let shape = if i % 2 == 0 {
            ColliderBuilder::ball(0.35)
        } else {
            ColliderBuilder::cuboid(0.3, 0.3, 0.3)
        };
        dynamic.push(world.insert(body, shape).0);
    }
    // A kinematic platform carrying a sensor volume above it.
    let (platform, _) = world.insert(
        RigidBodyBuilder::kinematic_position_based().translation(Vector::new(-2.0, 0.3, 0.0)),
        ColliderBuilder::cuboid(1.5, 0.1, 1.5),
    );
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(1.4, 0.6, 1.4)
            .sensor(true)
            .translation(Vector::new(0.0, 0.7, 0.0)),
        Some(platform),
    );
    let sensor_types = world.colliders[sensor].active_collision_types();
    Mixed {
        world,
        platform,
        sensor,
        sensor_types,
        dynamic,
    }
}

/// The bodies Rapier says intersect the sensor now.
fn rapier_inside(world: &PhysicsWorld, sensor: ColliderHandle) -> BTreeSet<(u32, u32)> {
    world
        .narrow_phase
        .intersection_pairs_with(sensor)
        .filter(|(_, _, on)| *on)
        .filter_map(|(a, b, _)| {
            let other = if a == sensor { b } else { a };
            world.colliders.get(other)?.parent()
        })
        .map(|h| h.into_raw_parts())
        .collect()
}

#[test]
fn a_mixed_scene_with_a_sensor_on_a_moving_platform() {
    let Mixed {
        mut world,
        platform,
        sensor,
        sensor_types,
        dynamic,
    } = mixed_scene();
    let mut layer = ContactLayer::new();
    let watched = dynamic[0];
    let sensor_events = layer.subscribe(Filter::kinds(KindSet::SENSOR).with_colliders(&[sensor]));
    let ball_events = layer.subscribe(
        Filter::kinds(KindSet::of(&[
            EventKind::ContactStarted,
            EventKind::ContactStopped,
        ]))
        .with_bodies(&[watched]),
    );
    let mut entered = 0;
    let mut ball_touches = 0;
    for step in 0..400u32 {
        // The platform sweeps under the ramp's foot and back.
        let x = -2.0 - 3.0 * (step as Real * 0.01).sin();
        world.bodies[platform].set_next_kinematic_translation(Vector::new(x, 0.3, 0.0));
        layer.step(&mut world);
        layer.validate(&world).unwrap();

        for e in sensor_events.try_iter() {
            assert_eq!(e.collider1, Some(sensor), "{e:?}: the sensor is named");
            assert_eq!(e.body1, Some(platform), "{e:?}: its carrier is named");
            let body = e.body2.expect("the body entering or leaving");
            assert!(dynamic.contains(&body), "{e:?}");
            entered += usize::from(e.kind == EventKind::SensorStarted);
        }
        for e in ball_events.try_iter() {
            assert!(
                e.body1 == Some(watched) || e.body2 == Some(watched),
                "{e:?}"
            );
            ball_touches += 1;
        }
        // What is inside the sensor is what Rapier says, by handle.
        let inside: BTreeSet<(u32, u32)> = layer
            .sensor_contents(&world.colliders, sensor)
            .unwrap()
            .into_iter()
            .filter_map(|t| match t {
                Touching::Body(h) => Some(h.into_raw_parts()),
                Touching::Collider(_) => None,
            })
            .collect();
        assert_eq!(inside, rapier_inside(&world, sensor), "step {step}");
        for &b in inside.iter().take(3) {
            let h = RigidBodyHandle::from_raw_parts(b.0, b.1);
            assert!(layer
                .sensors_containing(&world.bodies, h)
                .unwrap()
                .contains(&sensor));
        }
        if step % 25 == 0 {
            for &b in &dynamic {
                let ours: BTreeSet<String> = layer
                    .touching_body(&world.bodies, b)
                    .unwrap()
                    .into_iter()
                    .map(|t| format!("{t:?}"))
                    .collect();
                assert_eq!(ours, rapier_touching(&world, b), "{b:?} at step {step}");
            }
        }
    }
    assert!(entered > 0, "bodies entered the carried sensor");
    assert!(ball_touches > 0, "the watched ball touched something");
    // Sensors keep the collision types the user built them with.
    assert_eq!(
        world.colliders[sensor].active_collision_types(),
        sensor_types
    );
}

#[test]
fn a_pile_with_the_presets_keeps_warm_start_and_is_held_or_asleep() {
    for (name, preset) in [
        ("reliable_sleep", SpeedUps::reliable_sleep()),
        ("papers_fastest", SpeedUps::papers_fastest()),
        (
            "fixate on the defaults",
            SpeedUps {
                hold: true,
                ..Default::default()
            },
        ),
    ] {
        let mut scene = scenes::box_pile(60, 3);
        let params = scene.world.integration_parameters;
        let boxes = scene.dynamic_bodies();
        let mut layer = ContactLayer::new();
        layer.speedups_mut().set(Some(preset)).unwrap();
        let sleep = layer.subscribe(Filter::kinds(KindSet::SLEEP));
        let mut fell_asleep = BTreeSet::new();
        let mut stats = Default::default();
        for step in 0..400 {
            stats = common::step_validated(&mut scene, &mut layer, step);
            let p = scene.world.integration_parameters;
            assert_eq!(
                p.warmstart_coefficient, params.warmstart_coefficient,
                "{name}"
            );
            assert_eq!(p.contact_recycling, params.contact_recycling, "{name}");
            for e in sleep.try_iter() {
                let body = e.body1.expect("a sleep event names its body");
                if e.kind == EventKind::FellAsleep {
                    fell_asleep.insert(body.into_raw_parts());
                } else {
                    fell_asleep.remove(&body.into_raw_parts());
                }
            }
        }
        let still = |h: RigidBodyHandle| {
            scene.world.bodies[h].is_sleeping() || layer.analysis().holds(&scene.world.bodies, h)
        };
        assert!(
            boxes.iter().all(|&h| still(h)),
            "{name}: the pile is held or asleep"
        );
        assert_eq!(stats.awake_bodies, 0, "{name}: Rapier integrates nothing");
        assert_eq!(
            fell_asleep.len(),
            boxes.len(),
            "{name}: each box said it sleeps"
        );
        layer.detach((&mut scene.world).into());
        assert!(
            boxes.iter().all(|&h| scene.world.bodies[h].is_dynamic()),
            "{name}: detach gives every body back dynamic"
        );
        assert_eq!(
            scene.world.integration_parameters.warmstart_coefficient,
            params.warmstart_coefficient
        );
    }
}
