//! The two ways of finding the refreshed bodies' pairs (one pass over Rapier's pair
//! array, or a walk of each body's pairs) build the same graph, and switching the
//! contact details off changes nothing but the details.

mod common;

use std::collections::BTreeSet;

use rapier_contact_graph::coherence::ScanPolicy;
use rapier_contact_graph::{ContactLayer, EdgeKind};
use rcg_scenes as scenes;

/// The graph as a set of lines that do not depend on slot order.
fn edge_set(layer: &ContactLayer, details: bool) -> BTreeSet<String> {
    let g = layer.graph();
    let step = layer.analysis().current_step();
    g.edges()
        .filter(|(_, e)| e.kind() == EdgeKind::Physical)
        .map(|(_, e)| {
            let (a, b) = (g.body_of(e.a()), g.body_of(e.b()));
            let c = e.cache();
            let mut line = format!(
                "{a:?}-{b:?} {:?} {:?} {} {} {}",
                e.proximity_mark(step),
                e.touching_mark(step),
                c.proximity,
                c.touching,
                c.contact_count
            );
            if details {
                line += &format!(
                    " | {:?} {:.5} {:?} {:?} {}",
                    c.min_distance.to_bits(),
                    // A sum over several collider pairs depends on their order in
                    // its last bits; the order differs between scan and walk.
                    c.normal_impulse,
                    c.normal,
                    c.relative_pose,
                    c.relative_pose_changed
                );
            }
            line
        })
        .collect()
}

fn run(policy: ScanPolicy, details: bool, steps: u64) -> Vec<BTreeSet<String>> {
    let mut scene = scenes::sphere_pile(150, 11);
    let mut layer = ContactLayer::new();
    layer.analysis_mut().set_scan_policy(policy);
    layer.analysis_mut().set_contact_details(details);
    let mut out = Vec::new();
    for step in 0..steps {
        common::run_validated(&mut scene, &mut layer, step, 1);
        out.push(edge_set(&layer, details));
    }
    // Remove a few bodies mid-run: slots of Rapier's pair array change hands.
    let victims: Vec<_> = scene
        .world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .map(|(h, _)| h)
        .step_by(17)
        .collect();
    for h in victims {
        scene.world.remove_body(h);
    }
    for step in steps..steps + 100 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        out.push(edge_set(&layer, details));
    }
    out
}

#[test]
fn scan_and_walk_build_the_same_graph() {
    let scan = run(ScanPolicy::Scan, true, 250);
    let walk = run(ScanPolicy::Walk, true, 250);
    for (i, (s, w)) in scan.iter().zip(walk.iter()).enumerate() {
        assert_eq!(s, w, "step {}", i + 1);
    }
}

#[test]
fn details_off_keeps_marks_touching_and_counts() {
    let on = run(ScanPolicy::Auto, true, 150);
    let off = run(ScanPolicy::Auto, false, 150);
    let strip = |v: &Vec<BTreeSet<String>>| -> Vec<BTreeSet<String>> {
        v.iter()
            .map(|s| {
                s.iter()
                    .map(|l| l.split(" | ").next().unwrap().to_string())
                    .collect()
            })
            .collect()
    };
    assert_eq!(strip(&on), off);
}
