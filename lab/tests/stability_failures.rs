//! The stability suite: each scene of `scenes::stability` fails where the
//! measured table says it fails, and nowhere else it was built to fail.
//!
//! For every scene:
//! - under the suite's reference (`stability::reference()`) the monitor reports no
//!   violation at all;
//! - for every expected failure, the target's run shows it against its control (the
//!   same configuration without the target): more violations of the expected kind, or a
//!   deviation from the reference larger by `stability::DEVIATION_MARGIN`;
//! - for every target the scene was built against but is not expected to fail under,
//!   the run shows no failure of any kind against its control (the honest negatives of
//!   the table: what Rapier 0.36 and this crate's realisation of a switch get right).
//!
//! The monitor runs in plain detection, as `measure::run` drives it (fixated or
//! Rapier-sleeping bodies are "held"), and `validate()` runs after every step. A hanging
//! sleeper must show as a violation *and* as a deviation (a body left in the air is
//! away from the reference), except the ones the monitor does not report yet
//! ([`MISSED`], empty today): those by the deviation alone.

#[path = "../../tests/common/mod.rs"]
mod common;

use rapier3d::prelude::RigidBodyHandle;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, MonitorMode, RepairConfig, RepairCounts, ViolationKind,
};
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_lab::measure::{deviation, Mode, RunSpec, Trajectory, Violations};
use rcg_lab::stability::{self, Expectation, Failure, Outcome, StabilityCase, Target};

/// Runs a case under a configuration (stock Rapier or the layer with speed-ups), with
/// `validate()` after every step and the monitor in plain detection; samples the
/// measured bodies every `SAMPLE_EVERY` steps, as `rcg-lab stability` does.
fn run(
    case: &StabilityCase,
    spec: &RunSpec,
    reference: Option<&Trajectory>,
) -> (Outcome, Trajectory) {
    let mut scene = (case.build)();
    let bodies = case.measured_bodies(&scene);
    // A standalone monitor reads the layer's per-edge details: proximity tracking.
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    match &spec.mode {
        Mode::Stock => {}
        Mode::Layer(s) => layer.speedups_mut().set(Some(s.clone())).unwrap(),
        Mode::Plain { .. } => panic!("the suite's runs are stock or layered: {}", spec.name),
    }
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&scene.world));
    let mut traj = Trajectory::default();
    for step in 0..case.steps {
        common::step_validated(&mut scene, &mut layer, step);
        let held = |h: RigidBodyHandle| layer.analysis().holds(&scene.world.bodies, h);
        monitor.check_with_quarantine(
            &layer,
            &WorldView::from(&scene.world),
            &held,
            &|_| false,
            scene.world.quarantine().bodies(),
        );
        if (step + 1) % stability::SAMPLE_EVERY == 0 || step + 1 == case.steps {
            traj.frames.push(rcg_lab::measure::sample(&scene, &bodies));
        }
    }
    let t = monitor.totals();
    let violations = Violations {
        hanging: t.hanging_sleeper,
        launch: t.launch,
        penetration: t.deep_penetration,
        escape: t.escape,
        unresponsive: t.unresponsive,
    };
    let deviation = reference.map_or(0.0, |r| deviation(&traj, r, case.radius));
    (
        Outcome {
            violations,
            deviation,
        },
        traj,
    )
}

/// The hanging sleepers the monitor does not report yet, with why: none today. (Gravity
/// switched on from zero, and static geometry moved from under fixated bodies, were
/// missed until the monitor remembered gravity before its zero-gravity early return and
/// the fixation memory checked its static supporters' poses.)
const MISSED: [(&str, Target, &str); 0] = [];

fn missed(case: &StabilityCase, e: &Expectation) -> bool {
    MISSED
        .iter()
        .any(|&(name, t, _)| name == case.name && t == e.target)
}

const HANGING: Failure = Failure::Violation(ViolationKind::HangingSleeper);

fn describe(o: &Outcome) -> String {
    let v = o.violations;
    format!(
        "{}H {}L {}P {}E {}U, deviation {:.3}",
        v.hanging, v.launch, v.penetration, v.escape, v.unresponsive, o.deviation
    )
}

/// Checks one scene against its row of the measured table (see the module docs).
fn check(name: &str) {
    let case = stability::case(name).unwrap_or_else(|| panic!("no scene {name}"));
    let (reference, traj) = run(case, &stability::reference(), None);
    assert_eq!(
        reference.violations.total(),
        0,
        "{name}: the reference has violations: {}",
        describe(&reference)
    );
    let mut targets: Vec<Target> = case.expected.iter().map(|e| e.target).collect();
    for &t in case.built_against {
        if !targets.contains(&t) {
            targets.push(t);
        }
    }
    for t in targets {
        let (spec, control_spec) = (case.target_spec(t), case.control_spec(t));
        let (on, _) = run(case, &spec, Some(&traj));
        let (off, _) = run(case, &control_spec, Some(&traj));
        let what = format!(
            "{name} under {} (`{}`: {}) against `{}` ({})",
            t.name(),
            spec.name,
            describe(&on),
            control_spec.name,
            describe(&off)
        );
        match case.expected.iter().find(|e| e.target == t) {
            Some(e) if e.failure == HANGING => {
                assert!(
                    stability::shows(Failure::Deviation, &on, &off),
                    "{what}: the sleeper left in the air should move it away from the reference"
                );
                assert!(
                    missed(case, e) || stability::shows(HANGING, &on, &off),
                    "{what}: the hanging sleeper is not reported"
                );
            }
            Some(e) => assert!(
                stability::shows(e.failure, &on, &off),
                "{what}: expected {:?}",
                e.failure
            ),
            None => {
                let any = ViolationKind::ALL
                    .iter()
                    .map(|&k| Failure::Violation(k))
                    .chain([Failure::Deviation])
                    .find(|&f| stability::shows(f, &on, &off));
                assert_eq!(any, None, "{what}: measured not to fail");
            }
        }
    }
}

#[test]
fn fixation_lets_a_sphere_fall_when_the_one_below_rolls_away_but_elsewhere() {
    check("hanging_sleeper");
}

#[test]
fn a_released_fixated_pile_is_not_thrown_but_tweak_reduce_and_fixate_press_it_deep() {
    check("fixated_pile");
}

#[test]
fn reduce_and_tweak_topple_boxes_resting_face_to_face() {
    check("face_to_face");
}

#[test]
fn reduce_drops_the_tower_that_tweak_with_warm_start_keeps_standing() {
    check("tower");
}

#[test]
fn tweak_and_reduce_sink_the_pyramid() {
    check("pyramid");
}

#[test]
fn zero_takes_the_bounce_off_a_ball_landing_on_sleepers() {
    check("bounce_on_sleepers");
}

#[test]
fn the_seesaw_throws_its_box_under_subgrouping_and_under_fixation() {
    check("seesaw");
}

#[test]
fn sleepiness_freezes_a_sphere_rolling_slowly_down_an_incline() {
    check("slow_incline");
}

#[test]
fn fixation_lets_a_stack_fall_when_its_bottom_is_removed() {
    check("removed_support");
}

#[test]
fn fixation_lets_boxes_fall_with_a_sinking_platform() {
    check("platform_sleepers");
}

#[test]
fn fixation_lets_a_kinematic_hook_drag_its_crate() {
    check("jointed_sleeper");
}

#[test]
fn sleepers_ignore_gravity_switched_on() {
    check("gravity_change");
}

#[test]
fn fixation_lets_boxes_fall_when_their_shelf_moves_away() {
    check("static_moved");
}

#[test]
fn fixation_stops_a_slow_push_into_a_pile() {
    check("slow_push");
}

/// The slow push under fixation: reported (unresponsive) in report mode, and in repair
/// mode the pile is released at the first push, moves as the reference moves it, and
/// is reported no more often than without repair.
#[test]
fn repair_releases_the_pile_a_slow_push_presses() {
    let case = stability::case("slow_push").unwrap();
    let spec = case.target_spec(Target::Fixate);
    assert_eq!(spec.name, "------F");
    let (_, traj) = run(case, &stability::reference(), None);
    let (report, _) = run(case, &spec, Some(&traj));
    assert!(
        report.violations.unresponsive >= 1,
        "report: {}",
        describe(&report)
    );
    assert!(
        report.deviation >= stability::DEVIATION_MARGIN,
        "report: the stopped push should leave the pile behind the reference: {}",
        describe(&report)
    );
    let (repaired, repairs) = run_repaired_outcome(case, &spec, Some(&traj));
    assert!(repairs.woken >= 1, "{repairs:?}");
    assert!(
        repaired.violations.unresponsive <= report.violations.unresponsive,
        "repair: {} against report: {}",
        describe(&repaired),
        describe(&report)
    );
    assert_eq!(
        repaired.violations.total(),
        repaired.violations.unresponsive,
        "repair: {}",
        describe(&repaired)
    );
    assert!(
        repaired.deviation + stability::DEVIATION_MARGIN <= report.deviation,
        "repair should push the pile as the reference does: {} against report: {}",
        describe(&repaired),
        describe(&report)
    );
}

/// Every hanging sleeper of the suite is reported by the monitor.
#[test]
fn the_monitor_reports_every_hanging_sleeper_of_the_suite() {
    let mut unreported = Vec::new();
    for case in stability::suite() {
        let expected: Vec<&Expectation> = case
            .expected
            .iter()
            .filter(|e| e.failure == HANGING)
            .collect();
        if expected.is_empty() {
            continue;
        }
        let (_, traj) = run(case, &stability::reference(), None);
        for e in expected {
            let (on, _) = run(case, &case.target_spec(e.target), Some(&traj));
            let (off, _) = run(case, &case.control_spec(e.target), Some(&traj));
            if !stability::shows(e.failure, &on, &off) {
                unreported.push(format!(
                    "{} under {}: {}",
                    case.name,
                    e.target.name(),
                    describe(&on)
                ));
            }
        }
    }
    assert!(
        unreported.is_empty(),
        "hanging sleepers not reported:\n{}",
        unreported.join("\n")
    );
}

/// Fixation leaves no hanging sleeper in any scene of the suite: a held body whose
/// support goes is released and falls, without the monitor.
#[test]
fn fixation_leaves_no_hanging_sleeper_in_the_suite() {
    let mut hanging = Vec::new();
    for case in stability::suite() {
        let (_, traj) = run(case, &stability::reference(), None);
        let (on, _) = run(case, &case.target_spec(Target::Fixate), Some(&traj));
        if on.violations.hanging > 0 {
            hanging.push(format!("{}: {}", case.name, describe(&on)));
        }
    }
    assert!(
        hanging.is_empty(),
        "hanging sleepers:\n{}",
        hanging.join("\n")
    );
}

#[test]
fn the_suite_is_complete_cheap_and_deterministic() {
    let suite = stability::suite();
    assert_eq!(suite.len(), 14, "the 14 scenes of the suite");
    for case in suite {
        let a = (case.build)();
        assert_eq!(a.name, case.name);
        assert!(case.steps <= 600, "{}: {} steps", case.name, case.steps);
        assert!(a.world.bodies.len() <= 300, "{}", case.name);
        let measured = case.measured_bodies(&a);
        assert!(!measured.is_empty(), "{}", case.name);
        if !case.measured.is_empty() {
            assert_eq!(
                measured.len(),
                case.measured.len(),
                "{}: a named body is missing",
                case.name
            );
        }
        // Built twice and run for a while with the script, bit-identical.
        let mut b = (case.build)();
        let mut a = a;
        let (mut la, mut lb) = (ContactLayer::new(), ContactLayer::new());
        let n = case.steps.min(200);
        common::run_validated(&mut a, &mut la, 0, n);
        common::run_validated(&mut b, &mut lb, 0, n);
        assert_eq!(
            common::pose_bits(&a.world),
            common::pose_bits(&b.world),
            "{}",
            case.name
        );
    }
}

/// Boxes fixated while resting on boxes are not reported as hanging (a false alarm
/// once: in bounce_on_sleepers under `CTR---F` the support memory of fixated bodies
/// resting on each other was memoised inside a cycle and came out false).
#[test]
fn boxes_resting_on_fixated_boxes_are_not_hanging() {
    let case = stability::case("bounce_on_sleepers").unwrap();
    let (_, traj) = run(case, &stability::reference(), None);
    let spec = RunSpec::combination(0b100_0111);
    assert_eq!(spec.name, "CTR---F");
    let (on, _) = run(case, &spec, Some(&traj));
    assert_eq!(on.violations.hanging, 0, "{}", describe(&on));
}

/// Runs a case with the layer's monitor repairing (no outside monitor): the violations
/// left after repair.
fn run_repaired(case: &StabilityCase, spec: &RunSpec) -> Violations {
    run_repaired_outcome(case, spec, None).0.violations
}

/// [`run_repaired`] with the deviation from `reference` (0 without one), sampled as
/// [`run`] samples, and the repairs done.
fn run_repaired_outcome(
    case: &StabilityCase,
    spec: &RunSpec,
    reference: Option<&Trajectory>,
) -> (Outcome, RepairCounts) {
    let mut scene = (case.build)();
    let bodies = case.measured_bodies(&scene);
    let mut traj = Trajectory::default();
    let mut layer = ContactLayer::new();
    match &spec.mode {
        Mode::Layer(s) => layer.speedups_mut().set(Some(s.clone())).unwrap(),
        _ => panic!("only layer runs repair: {}", spec.name),
    }
    layer
        .monitor_mut()
        .set(
            MonitorMode::Repair,
            MonitorConfig::default(),
            RepairConfig::default(),
        )
        .unwrap();
    layer.monitor_mut().prime(&WorldView::from(&scene.world));
    for step in 0..case.steps {
        common::step_validated(&mut scene, &mut layer, step);
        if (step + 1) % stability::SAMPLE_EVERY == 0 || step + 1 == case.steps {
            traj.frames.push(rcg_lab::measure::sample(&scene, &bodies));
        }
    }
    let t = layer.monitor().map(|m| m.monitor().totals()).unwrap();
    let violations = Violations {
        hanging: t.hanging_sleeper,
        launch: t.launch,
        penetration: t.deep_penetration,
        escape: t.escape,
        unresponsive: t.unresponsive,
    };
    let repairs = layer.monitor().unwrap().repairs();
    let deviation = reference.map_or(0.0, |r| deviation(&traj, r, case.radius));
    (
        Outcome {
            violations,
            deviation,
        },
        repairs,
    )
}

/// The scenes where an impact makes a contact deep within one step, which repair
/// (acting between steps) does not always prevent: measured, see `docs/results.md`.
const DEEP_IN_ONE_STEP: [&str; 3] = ["fixated_pile", "seesaw", "removed_support"];

/// With the monitor repairing, every failure each scene was built for is gone under its
/// target switch and under every switch at once: no hanging sleeper, launch or escape
/// anywhere, and no deep penetration except in the scenes where an impact goes deep
/// within one step (and there never more than without repair).
#[test]
fn repair_leaves_no_hanging_sleeper_or_launch_in_any_scene() {
    for case in stability::suite() {
        let mut specs: Vec<RunSpec> = case
            .built_against
            .iter()
            .filter(|&&t| t != Target::StockSleep)
            .map(|&t| case.target_spec(t))
            .collect();
        specs.push(RunSpec::combination(127));
        for spec in specs {
            let repaired = run_repaired(case, &spec);
            assert_eq!(
                (repaired.hanging, repaired.launch, repaired.escape),
                (0, 0, 0),
                "{} under {} with repair: {repaired:?}",
                case.name,
                spec.name
            );
            if DEEP_IN_ONE_STEP.contains(&case.name) {
                let (plain, _) = run(case, &spec, None);
                assert!(
                    repaired.penetration <= plain.violations.penetration,
                    "{} under {}: repair made it worse: {repaired:?} vs {:?}",
                    case.name,
                    spec.name,
                    plain.violations
                );
            } else {
                assert_eq!(
                    repaired.penetration, 0,
                    "{} under {} with repair",
                    case.name, spec.name
                );
            }
        }
    }
}
