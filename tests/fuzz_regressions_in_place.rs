//! Minimised regression tests of what `tests/fuzz_operations.rs` found once it changed
//! colliders in place (`set_parent`, groups, enabled flags, the user's own
//! flags, shapes) and `validate()` checked rule screening against Rapier. `fixed_*`
//! failed when found and pass since the fix named in each.

mod common;

/// The fuzz harness (`tests/common/fuzz/`), for the tests that replay the arena.
#[path = "common/fuzz/mod.rs"]
#[allow(dead_code)]
mod harness;

use harness::{run, Op};

const BALL: Op = Op::Ball {
    x: 0,
    y: 0,
    z: 0,
    r: 0,
};

/// A rule between a trigger (a ball collider turned into a sensor) and the fixed
/// floor it rests in: neither side moves, so Rapier never evaluated the pair again and
/// the rule's hook was never asked; `validate()` (now checking rule screening against
/// Rapier) failed with "a rule screens the pair … but Rapier collides it". Passes since
/// the layer sets Rapier's `GROUPS` change flag on the colliders whose hook flags it
/// changes.
#[test]
fn fixed_a_rule_on_a_resting_pair_is_applied_by_rapier() {
    let ops = [
        BALL,
        Op::ToggleSensor(106),
        BALL,
        Op::Step(1),
        BALL,
        Op::Teleport {
            body: 4,
            x: 0,
            y: 0,
            z: 0,
        },
        Op::RemoveCollider(65),
        BALL,
        Op::Step(1),
        Op::IgnorePair(117, 51),
    ];
    run(&ops, true).unwrap();
}

/// A wall (static geometry) moved onto a ball with `set_parent`, then a rule between
/// that ball and another: Rapier's hooks, run before the analysis saw the move, named
/// the wall by its stale static node and let the pair collide. Passes since the hooks
/// name a collider by Rapier's parent.
#[test]
fn fixed_a_rule_after_set_parent_is_applied_by_rapier() {
    let ops = [
        BALL,
        Op::Sensor {
            on: None,
            x: 0,
            y: 0,
            z: 0,
        },
        BALL,
        Op::RemoveBody(42),
        BALL,
        BALL,
        BALL,
        Op::Step(1),
        Op::SetParent(167, Some(41)),
        Op::IgnorePair(72, 150),
    ];
    run(&ops, true).unwrap();
}

/// The arena's floor (a fixed body) turned sensor while a ball the speed-ups hold sat
/// on it: the layer widened the new sensor's collision types, and Rapier found the
/// held ball inside it only when the ball came back from its one disabled step out
/// of Rapier's active set. Neither side is refreshed then (a fixed carrier, a held
/// body), so `validate()` failed with "nodes 6–15 intersect in Rapier but have no
/// geometric edge" (found by `PROPTEST_CASES=30000`). Passes since the sensor pairs
/// of a body enabled again after parking are read in that step.
#[test]
fn fixed_a_held_ball_parked_in_a_floor_turned_sensor_gets_its_trigger_edge() {
    let ops = [
        Op::Ball {
            x: -4,
            y: 4,
            z: 0,
            r: 1,
        },
        Op::SpeedUps(Some(80)),
        BALL,
        BALL,
        Op::Cube {
            x: 0,
            y: 0,
            z: 0,
            r: 0,
        },
        Op::Step(24),
        BALL,
        BALL,
        Op::Step(38),
        BALL,
        BALL,
        Op::Step(1),
        BALL,
        Op::ToggleSensor(165),
    ];
    run(&ops, true).unwrap();
}
