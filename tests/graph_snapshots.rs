//! Insta snapshots of the graph state of small deterministic scenes at several frames.
//! `validate()` runs after every step.

mod common;

use rcg_scenes as scenes;

fn check(name: &str, scene: scenes::Scene, frames: &[u64]) {
    for (frame, text) in common::snapshot_frames(scene, frames) {
        insta::assert_snapshot!(format!("{name}_{frame:04}"), text);
    }
}

#[test]
fn ball_dropped_on_a_box() {
    check("ball_on_box", scenes::ball_on_box(), &[1, 40, 60, 200]);
}

#[test]
fn three_sphere_stack() {
    check("sphere_stack_3", scenes::sphere_stack(3), &[1, 5, 50, 300]);
}

#[test]
fn two_piles_separated_by_a_fixed_wall() {
    check("two_piles", scenes::two_piles_with_wall(), &[1, 100]);
}

#[test]
fn body_on_a_kinematic_platform() {
    check(
        "kinematic_platform",
        scenes::kinematic_platform(),
        &[1, 50, 150],
    );
}
