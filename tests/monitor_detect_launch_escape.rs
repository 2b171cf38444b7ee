//! The plausibility monitor (paper §8, Fig. 15): the launch, deep penetration and
//! escape detectors, each firing in a scene built to trigger it. Every test steps
//! Rapier with the layer (`layer.step`) and then calls `monitor.check`, the way a user
//! would.

#[path = "common/detectors.rs"]
mod detectors;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::{Monitor, MonitorConfig, ViolationKind};
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes::{self as scenes};

use detectors::*;

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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    for _ in 0..20 {
        step(&mut world, &mut layer, &mut monitor, &no_one, &no_one);
    }
    assert_eq!(monitor.totals().launch, 0);

    // With Rapier's defaults the same overlap is resolved gently: no launch (but a
    // deep penetration).
    let mut world = world_with_ground();
    overlapping_boxes(&mut world);
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
        let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
        let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
