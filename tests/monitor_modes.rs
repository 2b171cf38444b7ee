//! The layer's monitor in its three modes: off, report, repair.
//!
//! - report mode counts and sends violations and does not change motion (bit for bit);
//! - repair mode wakes and releases what lost its support before it is a violation;
//! - non-finite state injected into a body is an escape, the body is isolated, and
//!   nothing else is lost.

mod common;

use common::build::box_at;
use common::{pose_bits, run_validated};
use crossbeam_channel::Receiver;
use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig, ViolationKind};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Error, Event};
use rcg_scenes::{sphere_pile, sphere_stack, Scene};

fn fixate_all() -> SpeedUps {
    SpeedUps {
        hold: true,
        ..SpeedUps::contact_graph()
    }
}

fn layer_with(mode: MonitorMode) -> (ContactLayer, Receiver<Event>) {
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(fixate_all())).unwrap();
    layer
        .monitor_mut()
        .set(mode, MonitorConfig::default(), RepairConfig::default())
        .unwrap();
    let rx = layer.subscribe(Filter::kinds(KindSet::MONITOR));
    (layer, rx)
}

/// A stack of three spheres run until all are fixated, then the bottom one removed.
/// Returns the scene, the layer, and the two upper spheres.
fn fixated_stack_losing_its_base(
    mode: MonitorMode,
) -> (Scene, ContactLayer, Receiver<Event>, [RigidBodyHandle; 2]) {
    let mut scene = sphere_stack(3);
    let (mut layer, rx) = layer_with(mode);
    let mut step = 0;
    while layer.speedups().unwrap().stats().fixated < 3 {
        run_validated(&mut scene, &mut layer, step, 1);
        step += 1;
        assert!(step < 2000, "the stack never came to rest");
    }
    // Settled and fixated: nothing was wrong so far.
    assert_eq!(common::violation_totals(&layer).total(), 0);
    assert_eq!(
        rx.try_iter().count(),
        0,
        "no monitor event while all is well"
    );
    let bottom = scene.body("s0").unwrap();
    let upper = [scene.body("s1").unwrap(), scene.body("s2").unwrap()];
    scene.world.remove_body(bottom);
    (scene, layer, rx, upper)
}

#[test]
fn report_mode_finds_no_hanging_sleeper_where_fixation_lets_a_stack_fall() {
    // The speed-ups release a held body whose remembered support is gone, so a stack
    // that loses its base falls as a sleeping one does, and the monitor has nothing
    // to report (it reports Rapier's sleeping bodies left in the air; see
    // tests/monitor_detect_hanging.rs).
    let (mut scene, mut layer, rx, upper) = fixated_stack_losing_its_base(MonitorMode::Report);
    let heights: Vec<Real> = upper
        .iter()
        .map(|&h| scene.world.bodies[h].translation().y)
        .collect();
    let mut per_step = 0;
    for _ in 0..150 {
        per_step += run_validated(&mut scene, &mut layer, 0, 1).violations;
    }
    let totals = common::violation_totals(&layer);
    assert_eq!(
        totals,
        layer.monitor().unwrap().monitor().totals(),
        "the long path"
    );
    assert_eq!(totals.total(), 0, "{totals:?}");
    assert_eq!(per_step, 0);
    assert_eq!(rx.try_iter().count(), 0, "no monitor event");
    for (&h, y) in upper.iter().zip(heights) {
        let now = scene.world.bodies[h].translation().y;
        assert!(now < y - 0.5, "the sphere fell: {y} -> {now}");
    }
}

#[test]
fn repair_mode_releases_a_fixated_stack_whose_base_is_gone() {
    let (mut scene, mut layer, rx, upper) = fixated_stack_losing_its_base(MonitorMode::Repair);
    let heights: Vec<Real> = upper
        .iter()
        .map(|&h| scene.world.bodies[h].translation().y)
        .collect();
    for _ in 0..150 {
        let stats = run_validated(&mut scene, &mut layer, 0, 1);
        assert_eq!(stats.violations, 0, "repair left a violation");
    }
    let m = layer.monitor().unwrap();
    assert_eq!(
        m.monitor().totals().total(),
        0,
        "{:?}",
        m.monitor().totals()
    );
    assert!(m.repairs().woken >= 1, "{:?}", m.repairs());
    for (&h, y) in upper.iter().zip(heights) {
        let now = scene.world.bodies[h].translation().y;
        assert!(now < y - 0.5, "the sphere fell: {y} -> {now}");
    }
    let events: Vec<Event> = rx.try_iter().collect();
    assert!(events.iter().any(
        |e| e.kind == EventKind::Repaired && e.violation == Some(ViolationKind::HangingSleeper)
    ));
    assert!(events.iter().all(|e| e.kind == EventKind::Repaired));
}

#[test]
fn report_mode_does_not_change_motion() {
    let run = |mode: Option<MonitorMode>| {
        let mut scene = sphere_pile(60, 7);
        let mut layer = ContactLayer::new();
        layer
            .speedups_mut()
            .set(Some(rcg_lab::table5::combination(127)))
            .unwrap();
        if let Some(mode) = mode {
            layer
                .monitor_mut()
                .set(mode, MonitorConfig::default(), RepairConfig::default())
                .unwrap();
        }
        let mut poses = Vec::new();
        for step in 0..400 {
            run_validated(&mut scene, &mut layer, step, 1);
            poses.push(pose_bits(&scene.world));
        }
        poses
    };
    let plain = run(None);
    let reported = run(Some(MonitorMode::Report));
    assert_eq!(plain.len(), reported.len());
    for (i, (a, b)) in plain.iter().zip(&reported).enumerate() {
        assert_eq!(a, b, "report mode changed the poses at step {i}");
    }
}

#[test]
fn non_finite_state_is_an_escape_and_the_body_is_isolated() {
    let build = || {
        let mut scene = sphere_pile(30, 3);
        let mut layer = ContactLayer::new();
        common::monitor_in(&mut layer, MonitorMode::Repair);
        let rx = layer.subscribe(Filter::kinds(KindSet::MONITOR));
        run_validated(&mut scene, &mut layer, 0, 120);
        (scene, layer, rx)
    };
    let (mut scene, mut layer, rx) = build();
    let victim = scene
        .world
        .bodies
        .iter()
        .filter(|(_, rb)| rb.is_dynamic())
        .map(|(h, _)| h)
        .last()
        .unwrap();
    let node = layer.graph().try_node_of_body(victim).unwrap();
    let nodes_before = layer.graph().node_count();
    scene.world.bodies[victim].set_linvel(Vector::new(Real::NAN, 0.0, 0.0), true);
    let stats = run_validated(&mut scene, &mut layer, 120, 1);
    assert_eq!(stats.violations, 1);
    let escapes: Vec<Event> = rx
        .try_iter()
        .filter(|e| e.kind == EventKind::Violation)
        .collect();
    assert_eq!(escapes.len(), 1, "{escapes:?}");
    assert_eq!(escapes[0].violation, Some(ViolationKind::Escape));
    assert_eq!(escapes[0].node1, node);
    assert_eq!(escapes[0].body1, Some(victim));
    // Isolated: disabled in Rapier, a passive node without edges or group; the node
    // and its handle are kept, and every other node is still there.
    assert!(!scene.world.bodies[victim].is_enabled());
    let n = layer.graph().node(node).expect("the node is kept");
    assert!(n.is_body_disabled());
    assert_eq!(layer.graph().neighbors(node).count(), 0);
    assert!(n.group().is_none());
    assert_eq!(layer.graph().node_count(), nodes_before);
    // The rest of the world goes on as if the body had been disabled by the user.
    let (mut twin, mut twin_layer, _) = build();
    twin.world.bodies[victim].set_enabled(false);
    run_validated(&mut twin, &mut twin_layer, 120, 1);
    for step in 121..200 {
        run_validated(&mut scene, &mut layer, step, 1);
        run_validated(&mut twin, &mut twin_layer, step, 1);
        assert_eq!(
            pose_bits(&scene.world),
            pose_bits(&twin.world),
            "step {step}"
        );
    }
    assert_eq!(common::violation_totals(&layer).escape, 1);
}

#[test]
fn bad_monitor_parameters_are_refused_and_change_nothing() {
    let mut layer = ContactLayer::new();
    common::monitor_in(&mut layer, MonitorMode::Report);
    let bad = MonitorConfig {
        hang_time: Real::NAN,
        ..MonitorConfig::default()
    };
    assert!(matches!(
        layer
            .monitor_mut()
            .set(MonitorMode::Repair, bad, RepairConfig::default()),
        Err(Error::InvalidParameter {
            name: "hang_time",
            ..
        })
    ));
    let bad_cap = RepairConfig {
        corrective_cap: 0.0,
        ..RepairConfig::default()
    };
    assert!(matches!(
        layer
            .monitor_mut()
            .set(MonitorMode::Repair, MonitorConfig::default(), bad_cap),
        Err(Error::InvalidParameter {
            name: "corrective_cap",
            ..
        })
    ));
    assert_eq!(layer.monitor().unwrap().mode(), MonitorMode::Report);
}

#[test]
fn leaving_repair_mode_restores_rapiers_corrective_velocity() {
    let (mut scene, mut layer, _rx, _) = fixated_stack_losing_its_base(MonitorMode::Repair);
    let original = scene
        .world
        .integration_parameters
        .normalized_max_corrective_velocity;
    // The release caps the correction for a few steps.
    let mut capped = false;
    for _ in 0..5 {
        run_validated(&mut scene, &mut layer, 0, 1);
        capped |= scene
            .world
            .integration_parameters
            .normalized_max_corrective_velocity
            < original;
    }
    assert!(capped, "released bodies get a capped correction");
    common::monitor_in(&mut layer, MonitorMode::Off);
    assert!(layer.monitor().is_none());
    run_validated(&mut scene, &mut layer, 0, 1);
    assert_eq!(
        scene
            .world
            .integration_parameters
            .normalized_max_corrective_velocity,
        original
    );
}

/// The paper's ♠ failure made on purpose: two boxes created 0.3 m into each other with
/// stiff contacts and Rapier's stabilisation pass off, so position correction throws
/// them apart. Returns how far the boxes get from where they started, the launches
/// counted and the repairs made.
fn overlapping_boxes_thrown(mode: MonitorMode) -> (Real, u64, u64) {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    let p = &mut world.integration_parameters;
    p.num_internal_stabilization_iterations = 0;
    p.contact_softness.natural_frequency = 300.0;
    p.normalized_max_corrective_velocity = 100.0;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0),
    );
    let boxes = [0.0, 0.2].map(|x| box_at(&mut world, [x, 0.25, 0.0], 0.25).0);
    let mut layer = ContactLayer::new();
    layer
        .monitor_mut()
        .set(mode, MonitorConfig::default(), RepairConfig::default())
        .unwrap();
    layer
        .monitor_mut()
        .prime(&rapier_contact_graph::WorldView::from(&world));
    let start = boxes.map(|h| world.bodies[h].translation());
    let mut top: Real = 0.0;
    for _ in 0..200 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        for (h, s) in boxes.iter().zip(start) {
            top = top.max((world.bodies[*h].translation() - s).length());
        }
    }
    let m = layer.monitor().unwrap();
    (top, m.monitor().totals().launch, m.repairs().damped)
}

#[test]
fn repair_mode_stops_a_launch_by_taking_its_excess_energy_out() {
    let (top_report, launches_report, damped_report) =
        overlapping_boxes_thrown(MonitorMode::Report);
    let (top_repair, launches_repair, damped_repair) =
        overlapping_boxes_thrown(MonitorMode::Repair);
    println!(
        "overlap thrown {top_report:.3} m ({launches_report} launches) without repair, \
         {top_repair:.3} m ({launches_repair} launches, {damped_repair} damped) with"
    );
    assert!(launches_report >= 1, "the overlap throws the boxes");
    assert_eq!(damped_report, 0, "report mode repairs nothing");
    // The launch itself happens inside Rapier's step and is counted; repair stops it
    // there, so the boxes do not fly.
    assert!(launches_repair >= 1);
    assert!(damped_repair >= 1);
    assert!(
        top_repair < 0.5 * top_report,
        "thrown {top_report} m without repair, {top_repair} m with"
    );
}
