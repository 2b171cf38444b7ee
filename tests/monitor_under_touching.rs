//! The monitor judges the same under touching tracking (the default) as under
//! proximity tracking: a held body's support and the awake bodies' penetrations are
//! read from Rapier's narrow phase when the graph keeps no details, with the same
//! figures. On every scene of the stability suite, built to make the speed-ups fail,
//! with the monitor reporting and repairing: the same violations, repairs, deepest
//! contact and peaks, and the same poses at every step, with `validate()` after each.

mod common;

use common::{pose_bits, run_validated};
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::MonitorMode;
use rapier_contact_graph::ContactLayer;
use rcg_scenes::stability::*;
use rcg_scenes::Scene;

const SCENES: [fn() -> Scene; 14] = [
    bounce_on_sleepers::bounce_on_sleepers,
    face_to_face::face_to_face,
    fixated_pile::fixated_pile,
    gravity_change::gravity_change,
    hanging_sleeper::hanging_sleeper,
    jointed_sleeper::jointed_sleeper,
    platform_sleepers::platform_sleepers,
    pyramid::pyramid,
    removed_support::removed_support,
    seesaw::seesaw,
    slow_incline::slow_incline,
    slow_push::slow_push,
    static_moved::static_moved,
    tower::tower,
];

/// Per step: the poses and the violations found (kind, body, value bits); at the end
/// the totals and the repairs, as text.
fn run(
    scene: fn() -> Scene,
    bits: u8,
    mode: MonitorMode,
    tracking: Tracking,
) -> (Vec<String>, usize) {
    let mut scene = scene();
    let mut layer = ContactLayer::with_tracking(tracking);
    layer
        .speedups_mut()
        .set(Some(rcg_lab::table5::combination(bits)))
        .unwrap();
    common::monitor_in(&mut layer, mode);
    let mut out = Vec::new();
    let mut found = 0;
    for step in 0..400 {
        run_validated(&mut scene, &mut layer, step, 1);
        assert_eq!(
            layer.analysis().coherence().tracking(),
            tracking,
            "{} step {step}",
            scene.name
        );
        let m = layer.monitor().unwrap();
        let violations: Vec<_> = m
            .monitor()
            .last()
            .iter()
            .map(|v| (v.kind, v.body.into_raw_parts(), v.value.to_bits()))
            .collect();
        found += violations.len();
        // The deepest contact (relative to its limit) and the peaks: the depths and
        // supports read, bit for bit.
        let deepest = m.monitor().last_deepest().map(|(r, n)| (r.to_bits(), n));
        let peaks = m.monitor().peaks();
        out.push(format!(
            "{:?} {violations:?} {deepest:?} {} {}",
            pose_bits(&scene.world),
            peaks.penetration.to_bits(),
            peaks.hang.to_bits()
        ));
    }
    let m = layer.monitor().unwrap();
    out.push(format!("{:?} {:?}", m.monitor().totals(), m.repairs()));
    (out, found)
}

fn same_under_both(mode: MonitorMode) {
    let mut found = 0;
    for scene in SCENES {
        for bits in [0b100_0000, 0b110_0001, 0b010_0001, 0b111_1111] {
            let (touching, n) = run(scene, bits, mode, Tracking::Touching);
            let (proximity, _) = run(scene, bits, mode, Tracking::Proximity);
            found += n;
            let name = scene().name;
            for (step, (t, p)) in touching.iter().zip(&proximity).enumerate() {
                assert_eq!(
                    t, p,
                    "{name}, combination {bits:07b}, {mode:?}: step {step}"
                );
            }
        }
    }
    // The comparison means something only where the monitor found something.
    assert!(found > 0, "no violation in any run");
}

#[test]
fn reporting_finds_the_same_violations_under_both_trackings() {
    same_under_both(MonitorMode::Report);
}

#[test]
fn repairing_repairs_the_same_under_both_trackings() {
    same_under_both(MonitorMode::Repair);
}
