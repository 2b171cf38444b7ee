//! The plausibility monitor (paper §8, Figs. 15 and 17): its configuration, the hanging
//! sleeper detector (Fig. 17), and the ordinary scenes in which no detector fires (a
//! settling pile, bounces, collisions, a toppling stack, a multibody pendulum, DIKU).
//!
//! Every test steps Rapier with the layer (`layer.step`) and then calls
//! `monitor.check`, the way a user would. The quiet scenes print the monitor's peaks
//! (how close each detector came to firing) with `--nocapture`.

#[path = "common/detectors.rs"]
mod detectors;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::{Monitor, MonitorConfig, ViolationKind};
use rapier_contact_graph::{ContactLayer, Error, WorldView};
use rcg_scenes::{self as scenes};

use detectors::*;

// ── Configuration ──────────────────────────────────────────────────────

#[test]
fn config_validation_names_the_bad_field() {
    MonitorConfig::default().validate().unwrap();
    let bad = [
        (
            "hang_time",
            MonitorConfig {
                hang_time: Real::NAN,
                ..Default::default()
            },
        ),
        (
            "hang_time",
            MonitorConfig {
                hang_time: -1.0,
                ..Default::default()
            },
        ),
        (
            "penetration_fraction",
            MonitorConfig {
                penetration_fraction: -0.1,
                ..Default::default()
            },
        ),
        (
            "launch_relative",
            MonitorConfig {
                launch_relative: Real::INFINITY,
                ..Default::default()
            },
        ),
        (
            "launch_per_kg",
            MonitorConfig {
                launch_per_kg: -0.5,
                ..Default::default()
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: Real::NAN,
                ..Default::default()
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: 1.0,
                ..Default::default()
            },
        ),
    ];
    for (field, config) in bad {
        match Monitor::new(config) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, field),
            Err(e) => panic!("{field}: wrong error {e:?}"),
            Ok(_) => panic!("{field}: {config:?} was accepted"),
        }
    }
}

// ── Hanging sleeper ────────────────────────────────────────────────────

/// The first check (1-based, counted from the first unsupported step) at which time
/// accumulated step by step in `f32` exceeds `hang_time`.
fn expected_hang_check(hang_time: Real, dt: Real) -> u64 {
    let (mut t, mut n): (Real, u64) = (0.0, 0);
    while t <= hang_time {
        t += dt;
        n += 1;
    }
    n
}

#[test]
fn hanging_sleeper_detects_a_held_body_left_in_the_air() {
    let mut world = world_with_ground();
    let r = 0.5;
    let lower = ball(
        &mut world,
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, r, 0.0)),
        r,
        0.0,
    );
    let upper = ball(
        &mut world,
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0 * r, 0.0)),
        r,
        0.0,
    );
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let held = move |h: RigidBodyHandle| h == upper;

    // Resting on the lower sphere, the held upper sphere is supported.
    for _ in 0..50 {
        let found = step(&mut world, &mut layer, &mut monitor, &held, &no_one);
        assert!(found.is_empty(), "{found:?}");
    }
    assert!(layer
        .analysis()
        .is_supported(layer.graph().try_node_of_body(upper).unwrap())
        .unwrap());

    // Fixate the upper sphere and take the lower one away.
    let rb = &mut world.bodies[upper];
    rb.set_locked_axes(LockedAxes::all(), true);
    rb.set_linvel(Vector::ZERO, true);
    rb.set_angvel(Vector::ZERO, true);
    world.remove_body(lower);
    let start_y = world.bodies[upper].translation().y;

    let due = expected_hang_check(0.1, DT);
    assert!(
        (10..=11).contains(&due),
        "0.1 s is 10 or 11 steps of 0.01 s, got {due}"
    );
    let node = layer.graph().try_node_of_body(upper).unwrap();
    let mut reports = Vec::new();
    for check in 1..=60u64 {
        let found = step(&mut world, &mut layer, &mut monitor, &held, &no_one);
        if check < due {
            assert!(
                found.is_empty(),
                "check {check}: reported before 0.1 s: {found:?}"
            );
            let timed: Vec<_> = monitor.unsupported_held().collect();
            assert_eq!(timed.len(), 1);
            assert_eq!(timed[0].0, upper);
            assert!((timed[0].1 - check as Real * DT).abs() < 1e-5);
        }
        for v in found {
            reports.push((check, v));
        }
    }
    assert_eq!(reports.len(), 1, "one episode, one report: {reports:?}");
    let (check, v) = reports[0];
    assert_eq!(check, due, "reported at the first check past 0.1 s");
    assert_eq!(v.kind, ViolationKind::HangingSleeper);
    assert_eq!(v.body, upper);
    assert_eq!(v.node, Some(node));
    assert!(
        v.value > 0.1 && v.value < 0.1 + DT + 1e-5,
        "value {}",
        v.value
    );
    assert_eq!(v.step, layer.analysis().current_step() - (60 - check));
    assert_eq!(monitor.totals().hanging_sleeper, 1);
    assert!(
        (world.bodies[upper].translation().y - start_y).abs() < 1e-6,
        "the fixated sphere stayed in the air"
    );

    // Released, it falls and lands: the episode is over, nothing more is reported, and
    // held again on the ground it is supported.
    world.bodies[upper].set_locked_axes(LockedAxes::empty(), true);
    let mut released = true;
    for _ in 0..150 {
        let found = step(
            &mut world,
            &mut layer,
            &mut monitor,
            &|h| !released && h == upper,
            &no_one,
        );
        assert!(found.is_empty(), "{found:?}");
        if world.bodies[upper].translation().y < r + 0.01 {
            released = false;
        }
    }
    assert!(!released, "the sphere landed");
    assert_eq!(monitor.unsupported_held().count(), 0);
    assert_eq!(monitor.totals().total(), 1);
}

#[test]
fn hanging_sleeper_detects_a_body_asleep_in_the_air() {
    // No caller hold at all: Rapier's own sleep holds it.
    let mut world = world_with_ground();
    let sleeper = ball(
        &mut world,
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 2.0, 0.0))
            .sleeping(true),
        0.5,
        0.0,
    );
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let due = expected_hang_check(0.1, DT);
    let mut first = None;
    for check in 1..=40u64 {
        let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
        assert!(
            world.bodies[sleeper].is_sleeping(),
            "Rapier keeps it asleep"
        );
        if let Some(v) = found.first() {
            assert_eq!((v.kind, v.body), (ViolationKind::HangingSleeper, sleeper));
            assert!(first.is_none(), "reported twice");
            first = Some(check);
        }
    }
    assert_eq!(first, Some(due));
}

#[test]
fn hanging_sleeper_quiet_when_supported_on_a_slope_or_asleep_in_a_pile() {
    // A box held on a fixed 20° slope: its contact normal has an upward component.
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    world.integration_parameters.dt = DT;
    let tilt = 20f32.to_radians();
    let slope = Pose::from_parts(Vector::ZERO, Rotation::from_rotation_z(tilt));
    world.insert(
        RigidBodyBuilder::fixed().pose(slope),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let on_slope = slope * Vector::new(0.0, 0.75, 0.0);
    let (b, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(on_slope, Rotation::from_rotation_z(tilt))),
        ColliderBuilder::cuboid(0.25, 0.25, 0.25),
    );
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for s in 0..200 {
        let held = |h: RigidBodyHandle| s >= 20 && h == b;
        if s == 20 {
            let rb = &mut world.bodies[b];
            rb.set_locked_axes(LockedAxes::all(), true);
            rb.set_linvel(Vector::ZERO, true);
            rb.set_angvel(Vector::ZERO, true);
        }
        let found = step(&mut world, &mut layer, &mut monitor, &held, &no_one);
        assert!(found.is_empty(), "step {s}: {found:?}");
    }
    assert_eq!(monitor.peaks().hang, 0.0, "never unsupported");

    // Rapier puts the settled pile (after ~7 s) and the stack to sleep; every sleeper
    // rests on something.
    for (mut scene, steps) in [
        (scenes::sphere_pile(300, 1), 800),
        (scenes::sphere_stack(5), 300),
    ] {
        let (found, totals, peaks) = run_scene(&mut scene, steps);
        let asleep = scene
            .world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_sleeping())
            .count();
        assert!(
            asleep + 1 >= scene.world.bodies.len(),
            "{}: {asleep} asleep",
            scene.name
        );
        assert_eq!(totals.hanging_sleeper, 0, "{found:?}");
        assert_eq!(peaks.hang, 0.0);
    }
}

// ── The quiet scenes ───────────────────────────────────────────────────

#[test]
fn quiet_scenes_report_nothing() {
    for (mut scene, steps) in quiet_scenes() {
        let (found, totals, peaks) = run_scene(&mut scene, steps);
        assert_eq!(totals.launch, 0, "{}: {found:?}", scene.name);
        assert!(
            peaks.launch < 0.5,
            "{}: launch peak {} leaves no margin",
            scene.name,
            peaks.launch
        );
        assert_eq!(totals.hanging_sleeper, 0, "{}: {found:?}", scene.name);
        assert_eq!(totals.escape, 0, "{}: {found:?}", scene.name);
        if scene.name == "pendulum_wall" {
            // The free link (10 cm thick) strikes the wall at ~3 m/s and sinks 3.2 cm
            // into it, a third of its thickness: a real deep penetration by the definition in `docs/ARCHITECTURE.md` §6,
            // reported once.
            let l2 = scene.body("l2").unwrap();
            assert_eq!(totals.deep_penetration, 1, "{found:?}");
            assert_eq!(found[0].body, l2);
            assert!(found[0].value > 0.01 && found[0].value < 0.05, "{found:?}");
        } else {
            assert_eq!(totals.deep_penetration, 0, "{}: {found:?}", scene.name);
            assert!(
                peaks.penetration < 0.6,
                "{}: penetration peak {}",
                scene.name,
                peaks.penetration
            );
        }
    }
}

#[test]
fn violations_are_sorted_and_repeat_checks_add_no_time() {
    // Two sleepers created in the air: reported in the same step, in handle order.
    let mut world = world_with_ground();
    let mut sleepers = Vec::new();
    for x in [2.0, -2.0] {
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(x, 3.0, 0.0))
            .sleeping(true);
        sleepers.push(ball(&mut world, body, 0.5, 0.0));
    }
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let due = expected_hang_check(0.1, DT);
    for check in 1..=due {
        layer.step(&mut world);
        let view = WorldView::from(&world);
        // Checking a step several times adds no time (and reports an episode once).
        for repeat in 0..3 {
            let found = monitor.check(&layer, &view, &no_one, &no_one).to_vec();
            if check < due || repeat > 0 {
                assert!(found.is_empty(), "check {check}.{repeat}: {found:?}");
            } else {
                assert_eq!(found.len(), 2, "{found:?}");
                assert!(found[0].body.into_raw_parts() < found[1].body.into_raw_parts());
                assert!(found
                    .iter()
                    .all(|v| v.kind == ViolationKind::HangingSleeper));
            }
        }
    }
    assert_eq!(monitor.totals().hanging_sleeper, 2);
}

#[test]
fn hanging_sleeper_without_contact_details_counts_any_touch_as_support() {
    let mut world = world_with_ground();
    let r = 0.5;
    let grounded = ball(
        &mut world,
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, r, 0.0)),
        r,
        0.0,
    );
    let floating = ball(
        &mut world,
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(3.0, 3.0, 0.0))
            .sleeping(true),
        r,
        0.0,
    );
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    layer.analysis_mut().set_contact_details(false);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let held = move |h: RigidBodyHandle| h == grounded;
    let mut found = Vec::new();
    for _ in 0..30 {
        found.extend(step(&mut world, &mut layer, &mut monitor, &held, &no_one));
    }
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].body, floating);
}
