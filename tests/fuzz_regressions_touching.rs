//! Minimised regression tests of what `tests/fuzz_operations.rs` found once half of
//! its sequences ran in touching mode (touching tracking in effect, switched to
//! proximity and back by the operations). `fixed_*` failed when found and pass since
//! the fix named in each.

mod common;

/// The fuzz harness (`tests/common/fuzz/`), for the tests that replay the arena.
#[path = "common/fuzz/mod.rs"]
#[allow(dead_code)]
mod harness;

use harness::{run, Op};

/// A dynamic ball on the arena's grid.
fn ball(x: i8, y: u8, z: i8, r: u8) -> Op {
    Op::Ball { x, y, z, r }
}

/// A subscription to a proximity kind switched tracking to proximity; dropping it
/// switched back to touching, whose rescan kept an edge whose count of touching
/// collider pairs was already right but whose contact count was proximity
/// tracking's solver contacts ("layer (true, 4, 1), fresh (true, 1, 1)"). Passes since
/// the rescan also compares the contact count and the proximity flag.
#[test]
fn fixed_switching_back_to_touching_recounts_contacts() {
    let ops = [
        Op::Touching(true),
        Op::Subscribe {
            kinds: 2,
            capacity: 0,
            node: None,
        },
        ball(0, 0, 0, 0),
        Op::RemoveBody(0),
        Op::SetParent(50, Some(0)),
        Op::DropReceiver(0),
    ];
    run(&ops, true).unwrap();
}

/// The floor body, made dynamic and jointed into a multibody, went non-finite and
/// Rapier's quarantine disabled it: its pairs went without a `Stopped`, and under
/// touching tracking its edges stayed ("passive node n0v0 has physical or geometric
/// edges"). Passes since a body whose passive state changed has its touching pairs
/// counted again.
#[test]
fn fixed_a_body_disabled_by_rapier_loses_its_touches() {
    let ops = [
        Op::Touching(true),
        ball(0, 0, 1, 0),
        Op::RemoveCollider(46),
        Op::RemoveCollider(4),
        Op::SetType(84, harness::Ty::Dynamic),
        Op::Teleport {
            body: 0,
            x: 0,
            y: 2,
            z: 3,
        },
        ball(-3, 5, 0, 0),
        Op::Multibody { a: 151, b: 189 },
        Op::Step(1),
        Op::Step(1),
        Op::Multibody { a: 63, b: 2 },
        Op::RemoveCollider(201),
        Op::SetParent(29, None),
        Op::Joint {
            a: 67,
            b: 144,
            revolute: false,
        },
        Op::Teleport {
            body: 78,
            x: -4,
            y: 4,
            z: -3,
        },
    ];
    run(&ops, true).unwrap();
}

/// The floor body's collider removed under a resting ball: Rapier's `Stopped`
/// (flag `REMOVED`) names a collider no longer in Rapier, whose owner the lookup
/// cache had dropped when the collider count changed, so the touch stayed ("edge
/// e0v0 is proximate without a Rapier pair"). Passes since a body whose collider
/// count changed has its touching pairs counted again.
#[test]
fn fixed_a_collider_removed_from_a_fixed_body_ends_its_touches() {
    let ops = [
        Op::Touching(true),
        ball(0, 0, 0, 0),
        Op::Step(20),
        Op::RemoveCollider(0),
    ];
    run(&ops, true).unwrap();
}

/// Proximity tracking asked for, then touching again: the step's `Started` events
/// were applied on top of proximity tracking's counts, and the rescan at the switch
/// skipped the edges those events had updated ("layer (true, 2, 1), fresh (true, 1,
/// 1)"). Passes since the rescan settles such edges again with the count it read.
#[test]
fn fixed_switching_to_touching_recounts_edges_the_events_changed() {
    let ops = [
        Op::Touching(true),
        ball(0, 0, 0, 0),
        ball(-2, 0, 0, 2),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::Touching(false),
        ball(0, 0, -2, 2),
        ball(0, 5, 3, 0),
        ball(-2, 1, 0, 0),
        Op::Joint {
            a: 94,
            b: 47,
            revolute: false,
        },
        Op::Joint {
            a: 125,
            b: 94,
            revolute: false,
        },
        Op::Step(26),
        Op::Touching(true),
    ];
    run(&ops, true).unwrap();
}

/// The speed-ups switched off: touching tracking took over from proximity while an
/// edge whose proximity had just ended lingered for the obsolete pass (not
/// proximate, no collider pair), which the rescan at the switch kept; the body made
/// passive next kept it ("passive node n7v0 has physical or geometric edges").
/// Passes since the rescan removes every physical edge without a touching pair.
#[test]
fn fixed_switching_to_touching_drops_edges_whose_proximity_ended() {
    let ops = [
        Op::Touching(true),
        Op::ToggleSensor(18),
        Op::Cube {
            x: -1,
            y: 1,
            z: 0,
            r: 2,
        },
        ball(0, 0, 0, 0),
        ball(0, 0, -1, 0),
        Op::SpeedUps(Some(0)),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::Step(1),
        Op::Step(2),
        ball(0, 0, 0, 0),
        Op::Step(2),
        Op::SpeedUps(None),
        ball(0, 0, 0, 0),
        Op::Step(1),
        Op::Passive(83, true),
    ];
    run(&ops, true).unwrap();
}

/// A ball's collider disabled in place while it rested on the floor: Rapier drops a
/// disabled collider's pairs, but sends `Stopped` only for pairs that sent
/// `Started`, and this pair began touching before the layer flagged it (proximity
/// tracking was in effect while the speed-ups were on), so the touch stayed ("edge
/// e0v0 is proximate without a Rapier pair"). Passes since, under touching tracking,
/// a refreshed body whose set of disabled colliders changed has its touching pairs
/// counted again.
#[test]
fn fixed_a_collider_disabled_in_place_ends_touches_begun_before_the_flag() {
    let ops = [
        Op::Touching(true),
        ball(0, 0, 0, 0),
        Op::SpeedUps(Some(0)),
        ball(0, 0, 0, 0),
        Op::SpeedUps(None),
        Op::Step(2),
        Op::ColliderEnabled(6, false),
    ];
    run(&ops, true).unwrap();
}
