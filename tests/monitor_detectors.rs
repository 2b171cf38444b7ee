//! The plausibility monitor's detectors (paper §8, Figs. 15 and 17): each one fires in a scene built to
//! trigger it, and none fires in the ordinary scenes (a settling pile, bounces,
//! collisions, a toppling stack, a multibody pendulum, DIKU).
//!
//! Every test steps Rapier with the layer (`layer.step`) and then calls
//! `monitor.check`, the way a user would. The quiet scenes print the monitor's peaks
//! (how close each detector came to firing) with `--nocapture`.

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, Peaks, Violation, ViolationCounts, ViolationKind,
};
use rapier_contact_graph::{ContactLayer, Error, WorldView};
use rcg_scenes::{self as scenes, Scene};

const DT: Real = 0.01;

fn no_one(_: RigidBodyHandle) -> bool {
    false
}

/// A world with the scenes' settings and a fixed ground slab whose top is `y = 0`.
fn world_with_ground() -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    world.integration_parameters.dt = DT;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0),
    );
    world
}

fn cube(world: &mut PhysicsWorld, at: Vector, half: Real) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::dynamic().translation(at),
            ColliderBuilder::cuboid(half, half, half),
        )
        .0
}

fn ball(
    world: &mut PhysicsWorld,
    body: RigidBodyBuilder,
    radius: Real,
    e: Real,
) -> RigidBodyHandle {
    world
        .insert(
            body,
            ColliderBuilder::ball(radius)
                .restitution(e)
                .restitution_combine_rule(CoefficientCombineRule::Max),
        )
        .0
}

/// One layer step and one check; returns the step's violations.
fn step(
    world: &mut PhysicsWorld,
    layer: &mut ContactLayer,
    monitor: &mut Monitor,
    held: &dyn Fn(RigidBodyHandle) -> bool,
    excepted: &dyn Fn(RigidBodyHandle) -> bool,
) -> Vec<Violation> {
    layer.step(world);
    monitor
        .check(layer, &WorldView::from(&*world), held, excepted)
        .to_vec()
}

/// Runs a scene (script included) for `steps` steps with a primed monitor, nobody held
/// or excepted; returns every violation, the totals and the peaks.
fn run_scene(scene: &mut Scene, steps: u64) -> (Vec<Violation>, ViolationCounts, Peaks) {
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&scene.world));
    let mut all = Vec::new();
    for s in 0..steps {
        scene.before_step(s);
        layer.step(&mut scene.world);
        monitor.check(&layer, &WorldView::from(&scene.world), &no_one, &no_one);
        assert_eq!(monitor.last().len(), monitor.last_count());
        all.extend_from_slice(monitor.last());
    }
    let sum: u64 = ViolationKind::ALL
        .iter()
        .map(|&k| all.iter().filter(|v| v.kind == k).count() as u64)
        .sum();
    assert_eq!(
        monitor.totals().total(),
        sum,
        "totals count every violation"
    );
    println!(
        "{:<22} peaks: hang {:.3}, launch {:.3} (excess {:.4} J), penetration {:.3}",
        scene.name,
        monitor.peaks().hang,
        monitor.peaks().launch,
        monitor.peaks().launch_excess,
        monitor.peaks().penetration
    );
    (all, monitor.totals(), monitor.peaks())
}

fn bouncing_ball() -> Scene {
    let mut scene = scenes::ball_on_box();
    for (_, c) in scene.world.colliders.iter_mut() {
        c.set_restitution(0.8);
    }
    scene.name = "bounce_e0.8";
    scene
}

/// Two balls rolling into each other on the ground, and two meeting head-on in the air,
/// all with restitution 1 (the most energy a collision can hand over).
fn colliding_balls() -> Scene {
    let mut world = world_with_ground();
    let r = 0.5;
    let mut bodies = Vec::new();
    for (name, at, v) in [
        ("rest", [0.0, r, 0.0], [0.0, 0.0, 0.0]),
        ("roller", [-3.0, r, 0.0], [5.0, 0.0, 0.0]),
        ("left", [-3.0, 3.0, 3.0], [4.0, 0.0, 0.0]),
        ("right", [3.0, 3.0, 3.0], [-4.0, 0.0, 0.0]),
    ] {
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::from(at))
            .linvel(Vector::from(v));
        bodies.push((name, ball(&mut world, body, r, 1.0)));
    }
    Scene {
        name: "colliding_balls",
        world,
        bodies,
        script: None,
    }
}

/// The scenes that must stay quiet for the launch check, with their lengths.
fn quiet_scenes() -> Vec<(Scene, u64)> {
    vec![
        (scenes::sphere_pile(300, 1), 600),
        (bouncing_ball(), 400),
        (colliding_balls(), 300),
        (scenes::toppling_stack(), 400),
        (scenes::pendulum_wall(), 400),
        (scenes::kinematic_platform(), 300),
        (scenes::diku(&Default::default()), 1000),
    ]
}

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
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let held = move |h: RigidBodyHandle| h == upper;

    // Resting on the lower sphere, the held upper sphere is supported.
    for _ in 0..50 {
        let found = step(&mut world, &mut layer, &mut monitor, &held, &no_one);
        assert!(found.is_empty(), "{found:?}");
    }
    assert!(layer
        .is_supported(layer.node_of_body(upper).unwrap())
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
    let node = layer.node_of_body(upper).unwrap();
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
    assert_eq!(v.step, layer.current_step() - (60 - check));
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
    let mut layer = ContactLayer::new();
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
    let mut layer = ContactLayer::new();
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

// ── Launch ─────────────────────────────────────────────────────────────

/// Two 0.5 m boxes created 0.3 m into each other on the ground.
fn overlapping_boxes(world: &mut PhysicsWorld) -> (RigidBodyHandle, RigidBodyHandle) {
    let a = cube(world, Vector::new(0.0, 0.25, 0.0), 0.25);
    let b = cube(world, Vector::new(0.2, 0.25, 0.0), 0.25);
    (a, b)
}

#[test]
fn launch_detects_stiff_position_correction_throwing_overlapping_boxes() {
    // The paper's ♠ failure: position correction turned into velocity. Rapier's
    // stabilisation pass removes the correction velocity; without it, and with stiffer
    // contacts, the overlap is resolved by throwing the boxes apart.
    let stiff = |world: &mut PhysicsWorld| {
        let p = &mut world.integration_parameters;
        p.num_internal_stabilization_iterations = 0;
        p.contact_softness.natural_frequency = 300.0;
        p.normalized_max_corrective_velocity = 100.0;
    };
    let mut world = world_with_ground();
    stiff(&mut world);
    let (a, b) = overlapping_boxes(&mut world);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&world));
    let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    let launches: Vec<_> = found
        .iter()
        .filter(|v| v.kind == ViolationKind::Launch)
        .collect();
    assert_eq!(launches.len(), 1, "{found:?}");
    let v = launches[0];
    assert_eq!(v.step, 1);
    assert!(v.body == a || v.body == b);
    let ke = world.bodies[a].kinetic_energy() + world.bodies[b].kinetic_energy();
    assert!(ke > 5.0, "the boxes were thrown: {ke} J");
    assert!(
        (v.value - ke).abs() < 0.01 * ke,
        "excess {} vs kinetic energy {ke}",
        v.value
    );
    println!(
        "stiff overlap: excess {} J, peak ratio {}",
        v.value,
        monitor.peaks().launch
    );

    // Without priming, the first step of a new body has nothing to compare with.
    let mut world = world_with_ground();
    stiff(&mut world);
    overlapping_boxes(&mut world);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for _ in 0..20 {
        step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    assert_eq!(monitor.totals().launch, 0);

    // With Rapier's defaults the same overlap is resolved gently: no launch (but a
    // deep penetration).
    let mut world = world_with_ground();
    overlapping_boxes(&mut world);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&world));
    for _ in 0..40 {
        step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    assert_eq!(monitor.totals().launch, 0);
    assert!(
        monitor.peaks().launch < 0.1,
        "peak {}",
        monitor.peaks().launch
    );
    assert_eq!(monitor.totals().deep_penetration, 1);
}

#[test]
fn launch_detects_release_of_a_mass_fixation_and_honours_exceptions() {
    // Fixating the box under the ball with a huge extra mass, then restoring it,
    // throws the box (rapier-0.36-facts: "launches bodies at ~65 m/s").
    let run = |except_box: bool| {
        let mut scene = scenes::ball_on_box();
        let cube = scene.body("box").unwrap();
        let mut layer = ContactLayer::new();
        let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
        let mut launches = Vec::new();
        for s in 0..260u64 {
            if s == 100 {
                scene.world.bodies[cube].set_additional_mass(1e6, true);
            }
            if s == 200 {
                scene.world.bodies[cube].set_additional_mass(0.0, true);
            }
            let excepted = |h: RigidBodyHandle| except_box && s == 200 && h == cube;
            let found = step(
                &mut scene.world,
                &mut layer,
                &mut monitor,
                &no_one,
                &excepted,
            );
            launches.extend(
                found
                    .into_iter()
                    .filter(|v| v.kind == ViolationKind::Launch)
                    .map(|v| (s, v)),
            );
        }
        println!(
            "mass fixation release (excepted: {except_box}): peak launch ratio {}",
            monitor.peaks().launch
        );
        (launches, cube)
    };
    let (launches, cube) = run(false);
    assert_eq!(launches.len(), 1, "{launches:?}");
    let (s, v) = launches[0];
    assert_eq!(s, 200, "in the release step");
    assert_eq!(v.body, cube, "on the body with the largest gain");
    assert!(v.value > 100.0, "excess {} J", v.value);

    // The same push, declared by the caller: no launch.
    let (launches, _) = run(true);
    assert!(launches.is_empty(), "{launches:?}");
}

#[test]
fn launch_sees_undeclared_pushes_but_not_released_holds_or_scripted_bodies() {
    let r = 0.5;
    // A body given 5 m/s by the caller without saying so is a launch ...
    let mut world = world_with_ground();
    let b = ball(
        &mut world,
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, r, 0.0)),
        r,
        0.0,
    );
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for _ in 0..10 {
        step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    world.bodies[b].set_linvel(Vector::new(5.0, 0.0, 0.0), true);
    let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!((found[0].kind, found[0].body), (ViolationKind::Launch, b));

    // ... but restoring the velocity of a body the caller held (a fixation released)
    // is excepted without being declared.
    let mut world = world_with_ground();
    let b = ball(
        &mut world,
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, r, 0.0)),
        r,
        0.0,
    );
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for s in 0..30 {
        let held = |h: RigidBodyHandle| (10..20).contains(&s) && h == b;
        if s == 10 {
            world.bodies[b].set_locked_axes(LockedAxes::all(), true);
        }
        if s == 20 {
            world.bodies[b].set_locked_axes(LockedAxes::empty(), true);
            world.bodies[b].set_linvel(Vector::new(5.0, 0.0, 0.0), true);
        }
        let found = step(&mut world, &mut layer, &mut monitor, &held, &no_one);
        assert!(found.is_empty(), "step {s}: {found:?}");
    }
    assert!(world.bodies[b].linvel().x > 4.0);

    // A scripted body ramming a box hands it energy: the group is skipped.
    let mut world = world_with_ground();
    let target = cube(&mut world, Vector::new(0.0, 0.25, 0.0), 0.25);
    world.insert(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(-1.0, 0.3, 0.0))
            .linvel(Vector::new(8.0, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.25, 0.25, 0.25),
    );
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&world));
    let mut top_ke: Real = 0.0;
    for _ in 0..40 {
        let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
        assert!(
            found.iter().all(|v| v.kind != ViolationKind::Launch),
            "{found:?}"
        );
        top_ke = top_ke.max(world.bodies[target].kinetic_energy());
    }
    let tolerance = MonitorConfig::default().launch_per_kg * world.bodies[target].mass();
    assert!(
        top_ke > 10.0 * tolerance,
        "the box was hit hard: {top_ke} J"
    );
}

// ── Deep penetration ───────────────────────────────────────────────────

#[test]
fn deep_penetration_detects_each_episode_once() {
    let mut world = world_with_ground();
    let (a, b) = overlapping_boxes(&mut world);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    assert_eq!(found.len(), 1, "{found:?}");
    let v = found[0];
    assert_eq!(v.kind, ViolationKind::DeepPenetration);
    assert!(v.body == a || v.body == b);
    assert!((v.value - 0.3).abs() < 0.01, "penetration {}", v.value);
    // 0.3 m of a 0.5 m box, against a limit of 10 % of it.
    assert!((monitor.peaks().penetration - 6.0).abs() < 0.1);

    // The boxes separate slowly; the episode is reported once.
    for _ in 0..300 {
        let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
        assert!(found.is_empty(), "{found:?}");
    }
    let pa = world.bodies[a].translation();
    let pb = world.bodies[b].translation();
    assert!((pb - pa).length() > 0.47, "separated: {pa:?} {pb:?}");

    // Pushed back in: a new episode.
    let pa = world.bodies[a].translation();
    let y = world.bodies[b].translation().y;
    world.bodies[b].set_translation(Vector::new(pa.x + 0.2, y, pa.z), true);
    let found = step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].kind, ViolationKind::DeepPenetration);
    assert_eq!(monitor.totals().deep_penetration, 2);
}

// ── Escape ─────────────────────────────────────────────────────────────

#[test]
fn escape_detects_non_finite_poses_and_velocities() {
    let mut scene = scenes::ball_on_box();
    let ball = scene.body("ball").unwrap();
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for _ in 0..20 {
        step(&mut scene.world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    assert_eq!(monitor.totals().total(), 0);

    // Corrupted between steps: seen by a check without a Rapier step.
    scene.world.bodies[ball].set_translation(Vector::new(Real::NAN, 1.0, 0.0), false);
    let view = WorldView::from(&scene.world);
    let found = monitor.check(&layer, &view, &no_one, &no_one).to_vec();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        (found[0].kind, found[0].body),
        (ViolationKind::Escape, ball)
    );
    assert_eq!(found[0].value, 1.0, "one non-finite scalar");
    assert_eq!(found[0].node, layer.graph().node_of_body(ball));
    // The same episode is not reported twice.
    assert!(monitor.check(&layer, &view, &no_one, &no_one).is_empty());

    // Rapier's quarantine resets the body in the next step; the episode ends once the
    // pose is finite and the quarantine no longer reports it.
    layer.step(&mut scene.world);
    let q = scene.world.quarantine().bodies().to_vec();
    assert_eq!(q, [ball], "Rapier quarantined the ball");
    let view = WorldView::from(&scene.world);
    assert!(monitor
        .check_with_quarantine(&layer, &view, &no_one, &no_one, &q)
        .is_empty());
    for _ in 0..5 {
        step(&mut scene.world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    assert_eq!(monitor.totals().escape, 1);

    // A non-finite velocity, re-enabled body: a new episode.
    let rb = &mut scene.world.bodies[ball];
    rb.set_translation(Vector::new(0.0, 2.0, 0.0), true);
    rb.set_enabled(true);
    for _ in 0..3 {
        step(&mut scene.world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    scene.world.bodies[ball].set_linvel(Vector::new(0.0, Real::INFINITY, Real::NAN), true);
    let found = monitor
        .check(&layer, &WorldView::from(&scene.world), &no_one, &no_one)
        .to_vec();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        (found[0].kind, found[0].value),
        (ViolationKind::Escape, 2.0)
    );
    assert_eq!(monitor.totals().escape, 2);
}

#[test]
fn escape_inside_a_step_needs_the_quarantine_list() {
    // Corrupted and stepped before any check: Rapier resets and disables the body in
    // the step, so only its quarantine report tells.
    let run = |with_quarantine: bool| {
        let mut scene = scenes::ball_on_box();
        let ball = scene.body("ball").unwrap();
        let mut layer = ContactLayer::new();
        let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
        let mut found = Vec::new();
        for s in 0..30 {
            if s == 10 {
                scene.world.bodies[ball].set_linvel(Vector::new(Real::NAN, 0.0, 0.0), true);
            }
            layer.step(&mut scene.world);
            let view = WorldView::from(&scene.world);
            let q: &[RigidBodyHandle] = if with_quarantine {
                scene.world.quarantine().bodies()
            } else {
                &[]
            };
            found.extend_from_slice(
                monitor.check_with_quarantine(&layer, &view, &no_one, &no_one, q),
            );
        }
        (found, ball)
    };
    let (found, ball) = run(true);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(
        (found[0].kind, found[0].body, found[0].value),
        (ViolationKind::Escape, ball, 0.0)
    );
    assert_eq!(found[0].step, 11);
    let (found, _) = run(false);
    assert!(found.is_empty(), "the reset body looks finite: {found:?}");
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
    let mut layer = ContactLayer::new();
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
    let mut layer = ContactLayer::new();
    layer.set_contact_details(false);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let held = move |h: RigidBodyHandle| h == grounded;
    let mut found = Vec::new();
    for _ in 0..30 {
        found.extend(step(&mut world, &mut layer, &mut monitor, &held, &no_one));
    }
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].body, floating);
}
