//! A held body the user writes to is the user's from the next step on (paper §7,
//! fixation): the layer sees Rapier's modified flag on it and gives it back. Rapier
//! drops the write itself (an impulse, force or velocity on a fixed body), so a push
//! repeated every step lifts a held box one step later than a sleeping one, a held
//! box the user moves up falls back as a sleeping one does, and a held pile nobody
//! writes to stays held.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::MonitorMode;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;
use rcg_scenes as scenes;

const SETTLE: u64 = 400;
const AFTER: u64 = 60;

/// A settled pile of 50 boxes (10 columns of 5), stepped `SETTLE` steps by the layer
/// with the held preset and the monitor in `monitor` mode (or by Rapier alone, its
/// own sleep, when `monitor` is `None`), and the top box of the first column: held
/// (or asleep).
fn settled(monitor: Option<MonitorMode>) -> (scenes::Scene, ContactLayer, RigidBodyHandle) {
    settled_with(monitor, SpeedUps::reliable_sleep())
}

fn settled_with(
    monitor: Option<MonitorMode>,
    config: SpeedUps,
) -> (scenes::Scene, ContactLayer, RigidBodyHandle) {
    let layered = monitor.is_some();
    let mut scene = scenes::box_pile(50, 7);
    let top = scene.dynamic_bodies()[4];
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(config)).unwrap();
    common::monitor_in(&mut layer, monitor.unwrap_or(MonitorMode::Off));
    for step in 0..SETTLE {
        stepped(&mut scene, &mut layer, layered, step);
    }
    if layered {
        assert!(layer.speedups().unwrap().is_fixated(top), "held");
    } else {
        assert!(scene.world.bodies[top].is_sleeping(), "asleep");
    }
    (scene, layer, top)
}

fn stepped(scene: &mut scenes::Scene, layer: &mut ContactLayer, layered: bool, step: u64) {
    if layered {
        common::step_validated(scene, layer, step);
    } else {
        scene.world.step();
    }
}

/// How high the top box rises over `AFTER` steps when the user pushes it up before
/// every step with an impulse worth twice its weight.
fn rise_under_a_push_every_step(monitor: Option<MonitorMode>) -> Real {
    rise_under_a_push_every_step_with(monitor, SpeedUps::reliable_sleep())
}

fn rise_under_a_push_every_step_with(monitor: Option<MonitorMode>, config: SpeedUps) -> Real {
    let layered = monitor.is_some();
    let (mut scene, mut layer, top) = settled_with(monitor, config);
    let y0 = scene.world.bodies[top].translation().y;
    let dt = scene.world.integration_parameters.dt;
    let g = -scene.world.gravity.y;
    let mut peak = y0;
    for step in SETTLE..SETTLE + AFTER {
        let rb = &mut scene.world.bodies[top];
        let m = rb.mass();
        rb.apply_impulse(Vector::new(0.0, 2.0 * m * g * dt, 0.0), true);
        stepped(&mut scene, &mut layer, layered, step);
        peak = peak.max(scene.world.bodies[top].translation().y);
    }
    peak - y0
}

#[test]
fn a_push_every_step_lifts_a_held_box_as_it_lifts_a_sleeping_one() {
    let stock = rise_under_a_push_every_step(None);
    // Net g upwards for 0.6 s (60 steps of 0.01 s): about 1.8 m. The held box loses
    // the first push only, with or without the monitor.
    assert!(stock > 1.5, "the sleeping box rose {stock} m");
    for mode in [MonitorMode::Off, MonitorMode::Report, MonitorMode::Repair] {
        let held = rise_under_a_push_every_step(Some(mode));
        assert!(
            (held - stock).abs() < 0.1 * stock,
            "monitor {mode:?}: the held box rose {held} m, the sleeping one {stock} m"
        );
    }
}

#[test]
fn without_release_written_a_push_every_step_never_lifts_a_held_box() {
    let config = SpeedUps {
        release_written: false,
        ..SpeedUps::reliable_sleep()
    };
    let held = rise_under_a_push_every_step_with(Some(MonitorMode::Off), config);
    assert_eq!(held, 0.0, "Rapier drops every push on the fixed body");
}

#[test]
fn a_held_box_the_user_wakes_is_dynamic_and_awake_after_the_next_step() {
    let (mut scene, mut layer, top) = settled(Some(MonitorMode::Repair));
    scene.world.bodies[top].wake_up(true);
    common::step_validated(&mut scene, &mut layer, SETTLE);
    let rb = &scene.world.bodies[top];
    assert!(!layer.speedups().unwrap().is_fixated(top), "released");
    assert!(rb.is_dynamic() && !rb.is_sleeping(), "dynamic and awake");
}

#[test]
fn a_held_pile_nobody_writes_to_stays_held() {
    let (mut scene, mut layer, _) = settled(Some(MonitorMode::Repair));
    let held = layer.speedups().unwrap().stats().fixated;
    assert!(held >= 45, "{held} of 50 boxes held");
    for step in SETTLE..SETTLE + 200 {
        common::step_validated(&mut scene, &mut layer, step);
        let stats = layer.speedups().unwrap().stats();
        // The layer's own writes (parking, eligibility, the monitor's) leave no flag
        // on a held body that would pass for the user's.
        assert_eq!(stats.releases, 0, "a release at step {step}");
        assert_eq!(stats.fixated, held, "held bodies at step {step}");
    }
}

/// Where the top box is 100 steps after the user moved it 1 m up (waking it).
fn after_a_move_up(monitor: Option<MonitorMode>) -> (Real, Real) {
    let layered = monitor.is_some();
    let (mut scene, mut layer, top) = settled(monitor);
    let y0 = scene.world.bodies[top].translation().y;
    let rb = &mut scene.world.bodies[top];
    let up = rb.translation() + Vector::new(0.0, 1.0, 0.0);
    rb.set_translation(up, true);
    for step in SETTLE..SETTLE + 100 {
        stepped(&mut scene, &mut layer, layered, step);
    }
    (y0, scene.world.bodies[top].translation().y)
}

#[test]
fn a_held_box_the_user_moves_up_falls_back_as_a_sleeping_one() {
    let (y0, stock) = after_a_move_up(None);
    assert!(
        (stock - y0).abs() < 0.1,
        "the sleeping box came down to {stock} from {y0}"
    );
    for mode in [MonitorMode::Off, MonitorMode::Repair] {
        let (_, held) = after_a_move_up(Some(mode));
        assert!(
            (held - stock).abs() < 0.1,
            "monitor {mode:?}: the held box ended at {held}, the sleeping one at {stock}"
        );
    }
}
