//! Minimised regression tests of what `tests/fuzz_operations.rs` found about steps
//! the layer did not see (Rapier's own `PhysicsWorld::step` between the layer's
//! steps) and two layers taking turns on one world, under its configurations (the
//! rest is in `tests/fuzz_regressions_tracking.rs` and
//! `tests/fuzz_regressions_held.rs`). `bug_*` are ignored until fixed (each fails when
//! run with `--ignored`), `fixed_*` were fixed meanwhile (each failed when found);
//! `limit_*` are ignored too, and fail with `--ignored`: what they show is a
//! documented limit (`docs/ARCHITECTURE.md`, "Steps the layer did not see"). The
//! sequences replay with `harness::run_unsteered`.

mod common;

/// The fuzz harness (`tests/common/fuzz/`), for the tests that replay the arena.
#[path = "common/fuzz/mod.rs"]
#[allow(dead_code)]
mod harness;

use harness::{run_unsteered, Config, Op};

/// A dynamic ball on the arena's grid.
fn ball(x: i8, y: u8, z: i8, r: u8) -> Op {
    Op::Ball { x, y, z, r }
}

/// Steps the layer did not see, in a world with a kinematic body at rest (here the
/// floor, turned kinematic by the user), under touching tracking: after two steps of
/// Rapier alone (`PhysicsWorld::step`) the layer's next step does not notice it missed
/// any, and a touching pair the balls made meanwhile has no edge ("Rapier pair of
/// nodes 7–8 has no edge"). With the floor turned dynamic or fixed instead, or under
/// proximity tracking, it passes. The guess: the witness of "a few awake bodies" the
/// layer compares at its pre-step picked the kinematic body, which a step does not
/// change (velocity-based at zero velocity, or position-based and not driven: the
/// long run met one of those, with a residual velocity of 4e-6 m/s, in a sequence
/// of 14 operations ending `Step(2)`, `Unseen(1)`). Found by `speedups_contact_graph`;
/// fails under `touching` alike.
/// Fixed (the unseen-step witness samples dynamic bodies only).
#[test]
fn fixed_an_unseen_step_is_noticed_with_a_kinematic_body_at_rest() {
    use harness::{Call, Ty, Who};
    let ops = [
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 3),
        ball(0, 2, 0, 0),
        ball(0, 0, 0, 0),
        // The floor (no body is held: `Held` falls back to any body).
        Op::User(Who::Held(25), Call::Type(Ty::KinematicVelocity)),
        Op::Step(1),
        Op::Multibody { a: 153, b: 2 },
        Op::Unseen(2),
    ];
    run_unsteered(Config::Proximity, &ops, false).unwrap();
    // Failed when found: "after step 3: validate() failed: graph invariant violated:
    // Rapier pair of nodes 7–8 has no edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// As `fixed_an_unseen_step_is_noticed_with_a_kinematic_body_at_rest`, with a fixed
/// body in Rapier's active set instead of the kinematic one: a
/// ball the user turned fixed and put to sleep (`RigidBody::sleep()`), which Rapier
/// leaves in its active set, asleep, with a sleep timer that no step changes; the
/// other sampled bodies had just been woken (a teleport) and move fast (their timers
/// stay at 0). Found by the `touching` configuration's long run, shrunk.
/// Fixed (the unseen-step witness samples dynamic bodies only).
#[test]
fn fixed_an_unseen_step_is_noticed_with_a_fixed_body_in_the_active_set() {
    use harness::Ty;
    let ops = [
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 3),
        Op::Step(1),
        Op::RemoveBody(238),
        // A ball turned fixed, then put to sleep.
        Op::SetType(246, Ty::Fixed),
        ball(0, 0, 0, 0),
        Op::Sleep(227),
        ball(0, 2, 0, 0),
        Op::Step(1),
        Op::Teleport {
            body: 33,
            x: 0,
            y: 1,
            z: 0,
        },
        Op::Unseen(1),
    ];
    // Failed when found: "after step 4: validate() failed: graph invariant violated:
    // Rapier pair of nodes 10–11 has no edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// The witness of `fixed_an_unseen_step_is_noticed_with_a_kinematic_body_at_rest`
/// under the speed-ups, which own sleeping: Rapier's sleep timers do not run
/// (the layer makes bodies sleep-eligible only when their group is sleepy), so the
/// witness's "a sampled body's sleep timer grew" never holds, and an awake body at
/// rest in the sample (here a ball, and a kinematic body the user turned dynamic,
/// both at zero velocity) hides the step. Under `touching` (no speed-ups) the same
/// sequence passes. Found by `speedups_papers_fastest`'s long run, shrunk; also seen
/// with two layers taking turns under `speedups_contact_graph`.
/// Here one sampled ball falls and the other two rest exactly; the witness asked
/// every sampled body to have moved. It now asks it of the bodies that were moving.
#[test]
fn fixed_an_unseen_step_is_noticed_under_the_speedups() {
    use harness::{Preset, Ty};
    let ops = [
        Op::RemoveBody(0),
        ball(0, 0, 0, 0),
        Op::Kinematic {
            x: 0,
            y: 1,
            z: 0,
            vx: 0,
            vz: 0,
            velocity_based: false,
        },
        // The kinematic body.
        Op::SetType(223, Ty::Dynamic),
        ball(0, 0, 2, 0),
        Op::RemoveCollider(0),
        Op::Kinematic {
            x: 0,
            y: 0,
            z: 0,
            vx: 0,
            vz: 1,
            velocity_based: true,
        },
        Op::Joint {
            a: 9,
            b: 36,
            revolute: false,
        },
        Op::Step(1),
        Op::Unseen(1),
    ];
    run_unsteered(Config::Touching, &ops, false).unwrap();
    // Failed when found: "after step 3: validate() failed: graph invariant violated:
    // Rapier pair of nodes 7–9 has no edge".
    run_unsteered(Config::SpeedUps(Preset::PapersFastest), &ops, true).unwrap();
}

/// A joint added to a body the layer made passive (disabled in Rapier), then a step
/// of Rapier the layer does not see: Rapier panics in its solver ("internal error:
/// entered unreachable code", `interaction_groups.rs:153`), as plain Rapier does on a
/// joint between a disabled and a fixed body. `set_body_disabled` guards such joints
/// (disables them while the body is passive) in the layer's pre-step, which this step
/// does not have; the same step through the layer passes. Now that a user's own
/// `world.step()` between the layer's steps is a supported loop, the guard, or the
/// docs of `set_body_disabled`, should say so. Found by the `proximity` configuration's
/// long run, shrunk.
/// Documented limit: the passive bodies' joint guard runs in the layer's pre-step
/// (`set_body_disabled`'s docs); kept to show it (fails with `--ignored`).
#[test]
#[ignore = "documented: a new joint to a passive body panics Rapier in a step the layer did not see"]
fn limit_an_unseen_step_with_a_new_joint_to_a_passive_body_does_not_panic() {
    let ops = [
        ball(0, 0, 0, 0),
        Op::Kinematic {
            x: 0,
            y: 0,
            z: 0,
            vx: 0,
            vz: 0,
            velocity_based: false,
        },
        Op::Step(1),
        // The ball.
        Op::Passive(199, true),
        ball(0, 0, 0, 0),
        Op::RemoveBody(38),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::Step(1),
        // The floor and the passive ball.
        Op::Joint {
            a: 75,
            b: 131,
            revolute: false,
        },
        Op::Unseen(1),
    ];
    // Failed when found: a panic in Rapier's step.
    run_unsteered(Config::Proximity, &ops, true).unwrap();
}

/// Under proximity tracking a step the layer did not see is not looked for (the full
/// read after one is touching tracking's): a box asleep at the layer's last
/// analysis is teleported by the user (which wakes it), moved off its contacts by a
/// step of Rapier alone, and put back to sleep by the user before the layer's next
/// step. Asleep at both analyses, it is not read again, and its touching edge stays
/// ("edge e1v0 touching = true, Rapier says false"). With the step seen, or without the
/// teleport or the sleep, or under touching tracking, it passes. Found by the
/// `proximity` configuration's long run, shrunk.
/// Fixed by reading a missed step in full under proximity tracking too.
#[test]
fn fixed_a_body_asleep_on_both_sides_of_an_unseen_step_is_read_again() {
    let ops = [
        ball(0, 0, 0, 0),
        Op::Cube {
            x: 0,
            y: 0,
            z: 2,
            r: 2,
        },
        ball(0, 6, 0, 0),
        ball(0, 0, 0, 0),
        Op::Step(5),
        Op::Step(23),
        ball(0, 0, 0, 0),
        Op::Step(1),
        Op::Step(3),
        Op::Step(5),
        // The box, asleep.
        Op::Teleport {
            body: 92,
            x: -2,
            y: 0,
            z: 0,
        },
        Op::Unseen(1),
        Op::Sleep(20),
    ];
    // Failed when found: "after step 39: validate() failed: graph invariant violated:
    // edge e1v0 touching = true, Rapier says false".
    run_unsteered(Config::Proximity, &ops, true).unwrap();
}

/// The same as `limit_an_unseen_step_with_a_new_joint_to_a_passive_body_does_not_panic`
/// for a multibody: a passive body (the floor, turned dynamic) joined to a multibody,
/// then a step of Rapier the layer does not see: Rapier panics in the multibody's
/// solve ("LU solve matrix dimension mismatch", nalgebra's `lu.rs:247`). The layer's
/// pre-step makes such a body active again
/// (`fixed_a_passive_body_joined_to_a_multibody_is_made_active_again`), and this step
/// has none. Found by the `touching` configuration's long run, shrunk.
/// Documented limit: the passive bodies' guard runs in the layer's pre-step
/// (`set_body_disabled`'s docs name the joints; the multibodies are alike); kept to
/// show it (fails with `--ignored`).
#[test]
#[ignore = "documented: a passive body joined to a multibody panics Rapier in a step the layer did not see"]
fn limit_an_unseen_step_with_a_passive_body_in_a_multibody_does_not_panic() {
    use harness::{Call, Ty, Who};
    let ops = [
        ball(0, 0, 0, 0),
        Op::SetType(48, Ty::Dynamic),
        Op::Passive(8, true),
        Op::Step(1),
        ball(0, 0, 0, 0),
        Op::Sleep(8),
        ball(0, 0, 0, 0),
        Op::User(
            Who::Held(0),
            Call::Remove {
                keep_colliders: false,
            },
        ),
        Op::Multibody { a: 81, b: 28 },
        Op::Unseen(1),
    ];
    // Failed when found: a panic in Rapier's step.
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// The witness the layer keeps of a few awake dynamic bodies, to notice a step it did
/// not see, is fooled when the user turns a sampled body kinematic between the
/// layer's steps: a kinematic body at rest neither moves nor ages, and the other
/// sampled bodies were pushed (a ball inserted into them: their sleep timers start
/// again), so the second layer's step goes unnoticed by the first ("Rapier pair of
/// nodes 9–10 has no edge" at the first layer's next step). Turned fixed or dynamic
/// instead, or with a full sync, it passes; with a step of Rapier alone instead of the
/// second layer's, it fails alike ("edge e0v0 is proximate without a Rapier pair").
/// Found by `speedups_default` (with the speed-ups switched off) in the long run;
/// fails under `touching`.
/// Fixed by letting sampled bodies the user turned kinematic or fixed tell nothing.
#[test]
fn fixed_a_step_is_noticed_when_a_sampled_body_turns_kinematic() {
    use harness::{Second, Ty};
    let kinematic = Op::Kinematic {
        x: 0,
        y: 0,
        z: 0,
        vx: 0,
        vz: 0,
        velocity_based: false,
    };
    let ops = [
        kinematic.clone(),
        ball(0, 1, 0, 0),
        ball(0, 5, 0, 0),
        ball(0, 0, 0, 0),
        Op::RemoveBody(181),
        Op::Step(24),
        kinematic,
        Op::Step(1),
        Op::Second(Second::Attach),
        // A ball at rest, sampled.
        Op::SetType(42, Ty::KinematicPosition),
        ball(0, 0, 0, 0),
        Op::Second(Second::Step(1)),
    ];
    // Failed when found: "after step 27: validate() failed: graph invariant violated:
    // Rapier pair of nodes 9–10 has no edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// As `fixed_an_unseen_step_is_noticed_with_a_kinematic_body_at_rest`, with two layers
/// taking turns on one world: the second layer's second
/// step misses the first layer's step, and a fixed body turned kinematic rests in
/// the world: "Rapier pair of nodes 2–11 has no edge" in the second layer. Found by
/// `speedups_reliable_sleep`; fails under `touching` alike.
/// Fixed (the unseen-step witness samples dynamic bodies only).
#[test]
fn fixed_two_layers_taking_turns_with_a_kinematic_body_at_rest() {
    use harness::{Second, Ty};
    let ops = [
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::Cube {
            x: 3,
            y: 4,
            z: 2,
            r: 0,
        },
        Op::Second(Second::Attach),
        Op::FixedBody { x: 2, y: 3, z: 1 },
        // The fixed body just added.
        Op::SetType(131, Ty::KinematicVelocity),
        Op::Second(Second::Step(1)),
        ball(0, 0, 0, 0),
        Op::Teleport {
            body: 179,
            x: 0,
            y: 0,
            z: 0,
        },
        Op::Step(1),
        Op::Second(Second::Step(1)),
    ];
    run_unsteered(Config::Proximity, &ops, false).unwrap();
    // Failed when found: "op #11 Second(Step(1)): second layer, after its step 2:
    // validate() failed: graph invariant violated: Rapier pair of nodes 2–11 has no
    // edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// Two layers taking turns: a ball inserted after the second layer's first step falls
/// onto a fixed body and goes to sleep in the 42 steps of the first layer that follow.
/// At the second layer's next pre-step nothing tells it missed them: no body was
/// awake at its last step (its witness has nothing to compare) and none is now, so
/// Rapier's active set kept its size. The ball's node is new to it, but its collider
/// was flagged for collision events by the first layer, so the second layer relied on
/// the events of its own step, which has none for a contact that began long before
/// ("Rapier pair of nodes 0–7 has no edge"). Found by `touching` at 10,000 sequences
/// (`PROPTEST_RNG_SEED=0`). Fixed: the touching pairs of a new node's colliders
/// flagged by someone else are read once.
#[test]
fn fixed_a_ball_another_layer_stepped_to_sleep_has_its_contact_in_the_second() {
    use harness::Second;
    let ops = [
        Op::FixedBody { x: 0, y: 0, z: 0 },
        ball(0, 0, 0, 0),
        Op::Second(Second::Attach),
        Op::RemoveBody(188),
        Op::Step(1),
        Op::Second(Second::Step(1)),
        ball(0, 0, 2, 1),
        Op::Step(5),
        Op::Step(27),
        Op::Step(3),
        Op::Step(3),
        Op::Step(4),
        Op::Second(Second::Step(1)),
    ];
    run_unsteered(Config::Proximity, &ops, false).unwrap();
    // Failed when found: "op #12 Second(Step(1)): second layer, after its step 2:
    // validate() failed: graph invariant violated: Rapier pair of nodes 0–7 has no
    // edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// Two layers taking turns, the first widening sensors (`set_trigger_widening`), the
/// second not, both reading every pair: a wall turned sensor in place is widened by
/// the first layer's pre-step, Rapier then reports its intersection with the floor,
/// and the second layer, which saw the sensor before, never reads it again ("nodes
/// 2–3 intersect in Rapier but have no geometric edge"). To the second layer the
/// first one's widening is a change of static geometry in place, which the docs ask a
/// full sync for, but nothing tells it. Found by the `proximity` configuration's long
/// run, shrunk. (Alike for any write of one layer the other relies on: the
/// `COLLISION_EVENTS` flags one layer takes off when its touching tracking ends.)
/// Fixed by reading a missed step in full under proximity tracking too.
#[test]
fn fixed_a_second_layer_sees_the_sensors_the_first_widened() {
    use harness::Second;
    let ops = [
        Op::Second(Second::Attach),
        // A wall.
        Op::ToggleSensor(92),
        Op::Second(Second::Step(1)),
        ball(0, 0, 0, 0),
        Op::Step(1),
        Op::Second(Second::Step(1)),
    ];
    // Failed when found: "op #5 Second(Step(1)): second layer, after its step 2:
    // validate() failed: graph invariant violated: nodes 2–3 intersect in Rapier but
    // have no geometric edge".
    run_unsteered(Config::Proximity, &ops, true).unwrap();
}

/// Observe-only is not bit-identical across a step the layer did not see: colliders
/// inserted since the layer's last step are stepped by Rapier alone without
/// `COLLISION_EVENTS`, and the layer's next pre-step adds the flag to them
/// (`set_active_events` through `ColliderSet::get_mut`, which marks them modified for
/// Rapier's next step). Rapier then treats them as changed, and the trajectories
/// part from those of the plain world given the same operations (body 1 after step
/// 3 here). The twin passes when it gets the same flag writes at the same time (so the
/// write itself, not the flag, makes the difference); the flag written before a
/// collider's first step, as without unseen steps, changes nothing. Found by the
/// `touching` configuration, shrunk by hand: every operation is needed (the
/// difference comes from the order Rapier handles pairs in).
/// Documented limit: loops with steps the layer did not see give up bit-identity
/// (`docs/ARCHITECTURE.md`, "Steps the layer did not see"); kept to show it (fails with
/// `--ignored`).
#[test]
#[ignore = "documented: after a step the layer did not see, flagging colliders changes trajectories"]
fn limit_flags_added_after_an_unseen_step_change_no_trajectory() {
    use harness::Ty;
    let ops = [
        Op::Cube {
            x: 2,
            y: 0,
            z: 0,
            r: 2,
        },
        Op::Cube {
            x: 0,
            y: 0,
            z: 1,
            r: 0,
        },
        Op::Kinematic {
            x: -2,
            y: 5,
            z: 1,
            vx: 0,
            vz: -1,
            velocity_based: false,
        },
        ball(0, 6, 2, 1),
        Op::Unseen(1),
        Op::SetType(214, Ty::Fixed),
        Op::Kinematic {
            x: 0,
            y: 2,
            z: -1,
            vx: 0,
            vz: 2,
            velocity_based: true,
        },
        Op::Cube {
            x: -3,
            y: 3,
            z: -2,
            r: 0,
        },
        Op::SetType(38, Ty::Dynamic),
        ball(0, 2, 0, 0),
        ball(2, 0, 0, 1),
        Op::FixedBody { x: 0, y: 2, z: -2 },
        ball(-3, 1, -1, 0),
        ball(3, 4, 0, 1),
        ball(-3, 0, 2, 1),
        ball(-4, 2, -3, 3),
        Op::Kinematic {
            x: 0,
            y: 0,
            z: 0,
            vx: 0,
            vz: 0,
            velocity_based: false,
        },
        ball(-3, 1, 0, 0),
        Op::Multibody { a: 53, b: 225 },
    ];
    // The layer sees every step: bit-identical.
    let mut seen = ops.clone();
    seen[4] = Op::Step(1);
    run_unsteered(Config::Touching, &seen, false).unwrap();
    // Failed when found: "after step 3: trajectories differ from the plain Rapier
    // twin: body (1, 0)".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// Two layers taking turns on a world with no dynamic body awake (here none at all: a
/// sensor the first layer widens, the arena): the layer's witness samples awake
/// dynamic bodies, finds none, and falls back on the size of Rapier's active set,
/// which a step does not change; so the second layer does not notice the first
/// layer's step, in which the widened sensor met the floor ("nodes 5–6 intersect in
/// Rapier but have no geometric edge"), and no full read comes (as it does in
/// `fixed_a_second_layer_sees_the_sensors_the_first_widened`). Found by the
/// `proximity` configuration's long run with another seed (`PROPTEST_RNG_SEED=7`),
/// shrunk. Documented: a second layer sees one layer's widening as a sensor changed
/// in place, to be told with its `request_full_sync` (`set_trigger_widening`'s docs),
/// as the harness does; kept to show it (fails with `--ignored`).
#[test]
#[ignore = "documented: a second layer sees a sensor the first widened only after its request_full_sync"]
fn limit_a_second_layer_sees_a_new_sensor_the_first_widened() {
    use harness::Second;
    let ops = [
        Op::Second(Second::Attach),
        Op::Sensor {
            on: None,
            x: 0,
            y: 6,
            z: 0,
        },
        Op::Second(Second::Step(1)),
        Op::Step(1),
        Op::Second(Second::Step(1)),
    ];
    // Failed when found: "op #4 Second(Step(1)): second layer, after its step 2:
    // validate() failed: graph invariant violated: nodes 5–6 intersect in Rapier but
    // have no geometric edge".
    run_unsteered(Config::Proximity, &ops, true).unwrap();
}

/// A rule (`Rule::ignore_between`, a sensor against static geometry) screens a pair
/// through the layer's hooks, which a step of Rapier alone does not have: in that step
/// Rapier pairs them (the floor removed, a static collider moved into the sensor),
/// and since neither side moves Rapier would keep the intersection afterwards. With a
/// ball falling far away the witness sees the missed step, and the layer's next step
/// (a full read) puts the rule back in force.
#[test]
fn a_rule_holds_again_after_a_step_the_layer_noticed_it_missed() {
    let mut ops = vec![ball(4, 9, 4, 0)];
    ops.extend(rule_across_an_unseen_step());
    run_unsteered(Config::Proximity, &ops, true).unwrap();
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// The same without the falling ball: nothing in the world moves, so no witness sees
/// the missed step (`docs/ARCHITECTURE.md`, "What the witness cannot see"), and the
/// pair the rule screens stays collided until a rule or a member changes. Found by the
/// `proximity` configuration's long run with `PROPTEST_RNG_SEED=7`, shrunk.
#[test]
#[ignore = "limit: a step the layer did not see, in a world where nothing moves, goes unnoticed"]
fn limit_a_rule_holds_across_an_unseen_step_where_nothing_moves() {
    run_unsteered(Config::Proximity, &rule_across_an_unseen_step(), true).unwrap();
}

/// A sensor and static geometry that a rule keeps apart, and a step of Rapier alone
/// after the static collider moved into the sensor.
fn rule_across_an_unseen_step() -> Vec<Op> {
    vec![
        Op::Sensor {
            on: None,
            x: -3,
            y: 0,
            z: 0,
        },
        Op::Step(1),
        Op::IgnoreBetween(2, 64),
        Op::Sensor {
            on: None,
            x: 0,
            y: 0,
            z: 0,
        },
        Op::RemoveBody(0),
        Op::Step(1),
        Op::MoveStatic {
            collider: 21,
            x: -2,
            y: 0,
            z: 0,
        },
        Op::Unseen(1),
    ]
}

/// Two layers taking turns, a rule on the first: the second layer, which has no rule,
/// did not notice the first layer's step in which the pair was screened ("Rapier pair
/// of nodes 4–9 has no edge" in the second layer): some of its sampled bodies rested
/// exactly, and the witness asked every sampled body to have moved (see
/// `fixed_an_unseen_step_is_noticed_under_the_speedups`). Found by the `touching`
/// configuration's long run with `PROPTEST_RNG_SEED=7`, shrunk.
#[test]
fn fixed_two_layers_taking_turns_with_a_rule_on_one() {
    use harness::Second;
    let ops = [
        ball(0, 0, 0, 0),
        ball(0, 0, -2, 0),
        ball(0, 6, -1, 0),
        Op::RemoveCollider(21),
        Op::Kinematic {
            x: 0,
            y: 1,
            z: 0,
            vx: 0,
            vz: 0,
            velocity_based: false,
        },
        Op::Step(33),
        Op::Second(Second::Attach),
        Op::IgnoreBetween(64, 32),
        Op::Second(Second::Step(5)),
        ball(0, 1, 0, 0),
        Op::Step(1),
        Op::Second(Second::Step(1)),
    ];
    // Failed when found: "op #11 Second(Step(1)): second layer, after its step 6:
    // validate() failed: graph invariant violated: Rapier pair of nodes 4–9 has no
    // edge".
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// The floor turned kinematic, then dynamic again by the user, and a step of Rapier
/// alone: the active set held no dynamic body to sample (the floor was kinematic at
/// the analysis), and its size did not change, so the missed step went unnoticed
/// ("Rapier pair of nodes 0–1 has no edge": the falling floor meets the walls). The
/// witness now records a few other bodies of the active set when it has no dynamic
/// one, and one made dynamic that moved tells. Found by `speedups_reliable_sleep`'s
/// long run once it no longer steered clear of unseen steps, shrunk.
#[test]
fn fixed_an_unseen_step_is_noticed_when_a_kinematic_body_turned_dynamic_falls() {
    use harness::{Call, Preset, Ty, Who};
    let ops = [
        Op::SetType(0, Ty::KinematicVelocity),
        Op::Step(1),
        Op::User(Who::Any(0), Call::Type(Ty::Dynamic)),
        Op::Unseen(1),
    ];
    run_unsteered(Config::SpeedUps(Preset::ReliableSleep), &ops, true).unwrap();
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// Overlapping balls flying apart, one of which the user disables with Rapier's own
/// `set_enabled(false)`, then steps of Rapier alone: the disabled ball was sampled
/// moving and did not move in the missed steps, so the witness (every sampled moving
/// body changed) said no step ("edge e0v0 is proximate without a Rapier pair"). A
/// sampled body the user disabled now tells nothing. Found by
/// `speedups_papers_fastest`'s long run once it no longer steered clear of unseen
/// steps, shrunk.
#[test]
fn fixed_an_unseen_step_is_noticed_when_a_sampled_body_is_disabled() {
    use harness::{Call, Preset, Who};
    let ops = [
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::RemoveCollider(0),
        ball(0, 0, 0, 0),
        ball(0, 0, 0, 0),
        Op::Step(1),
        Op::Joint {
            a: 101,
            b: 95,
            revolute: false,
        },
        Op::User(Who::Held(37), Call::Enabled(false)),
        Op::Unseen(2),
    ];
    run_unsteered(Config::SpeedUps(Preset::PapersFastest), &ops, true).unwrap();
}

/// A pile with kinematic bodies and a sensor, pushed, then steps of Rapier alone
/// under `SpeedUps::contact_graph()`: one sampled body drifted at 6e-10 m/s, which
/// moves no pose bit, and the witness, which asked every sampled moving body to have
/// changed, saw no missed step ("Rapier pair of nodes 1–9 has no edge"). A body counts
/// as moving now only when its velocity changes its pose within a step. Found by a
/// long run with another seed (`PROPTEST_RNG_SEED=11`), shrunk.
#[test]
fn fixed_an_unseen_step_is_noticed_beside_a_body_drifting_too_slowly_to_move() {
    use harness::{Call, Preset, Who};
    let cube = |x: i8, y: u8, z: i8, r: u8| Op::Cube { x, y, z, r };
    let kin = |x: i8, y: u8, z: i8| Op::Kinematic {
        x,
        y,
        z,
        vx: 0,
        vz: 0,
        velocity_based: false,
    };
    let ops = [
        ball(-1, 0, 0, 0),
        ball(0, 0, 0, 0),
        kin(0, 0, 0),
        ball(0, 0, 0, 1),
        Op::Static { x: 0, y: 5, z: 2 },
        Op::Sensor {
            on: None,
            x: 0,
            y: 0,
            z: 0,
        },
        cube(0, 0, 0, 0),
        ball(-1, 0, 0, 0),
        kin(0, 3, -1),
        ball(0, 4, 3, 3),
        Op::Step(20),
        ball(1, 2, 0, 1),
        Op::User(Who::Any(24), Call::Impulse { x: 0, y: 0, z: 1 }),
        Op::Step(34),
        Op::Sensor {
            on: Some(133),
            x: 0,
            y: 0,
            z: 0,
        },
        Op::Unseen(3),
    ];
    run_unsteered(Config::SpeedUps(Preset::ContactGraph), &ops, true).unwrap();
}

/// One ball asleep under `SpeedUps::default()`, teleported by the user (which wakes
/// it), then two steps of Rapier alone: Rapier wakes it, moves it, and puts it back to
/// sleep two steps later (the speed-ups make it sleep-eligible at once), so nothing
/// the witness can look at changed (no dynamic body awake before or after) and the
/// ball's old contact stays in the graph ("edge e0v0 is proximate without a Rapier
/// pair"). A documented limit (`docs/ARCHITECTURE.md`, "What the witness cannot
/// see"); the fuzzer steers clear of it. Found by a long run with another seed
/// (`PROPTEST_RNG_SEED=11`), shrunk.
#[test]
#[ignore = "limit: under the speed-ups' sleep, a body woken and asleep again within steps the layer did not see leaves no trace"]
fn limit_an_unseen_step_where_a_woken_body_sleeps_again_under_the_speed_ups() {
    use harness::Preset;
    let ops = [
        ball(0, 0, 0, 0),
        Op::Step(20),
        Op::Step(20),
        Op::Teleport {
            body: 137,
            x: 0,
            y: 0,
            z: 0,
        },
        Op::Unseen(2),
    ];
    run_unsteered(Config::SpeedUps(Preset::Default), &ops, true).unwrap();
}

/// A ball joined by a multibody joint to a fixed body, a step, then a step of Rapier
/// alone, under the speed-ups: the link rests exactly (its root is fixed) and no
/// sleep timer grows under their sleep, so the witness sees nothing, and the ball's
/// contact with the floor made in the missed step has no edge ("Rapier pair of nodes
/// 0–7 has no edge"). The documented limit of a step in which every sampled body
/// rests exactly (`docs/ARCHITECTURE.md`, "What the witness cannot see"); the fuzzer
/// steers clear of it. Found by a long run with `PROPTEST_RNG_SEED=16`, shrunk.
#[test]
#[ignore = "limit: under the speed-ups, a step in which every sampled body rests exactly goes unnoticed"]
fn limit_an_unseen_step_where_every_sampled_body_rests_exactly_under_the_speed_ups() {
    use harness::Preset;
    let ops = [
        Op::FixedBody { x: 0, y: 0, z: 0 },
        ball(0, 0, -1, 0),
        Op::Multibody { a: 76, b: 203 },
        Op::Step(1),
        Op::Unseen(1),
    ];
    run_unsteered(Config::SpeedUps(Preset::ContactGraph), &ops, true).unwrap();
}

/// A box joined by a multibody joint to the fixed floor, its collider turned into a
/// sensor, then a step of Rapier alone, under touching tracking: the link rests
/// exactly and its sleep timer does not grow, so the witness sees nothing, and the
/// contact Rapier dropped in the missed step keeps its edge ("edge e1v0 is proximate
/// without a Rapier pair"). The same documented limit as above; the fuzzer steers
/// clear of it. Found by a long run with `PROPTEST_RNG_SEED=19`, shrunk.
#[test]
#[ignore = "limit: a step in which every sampled body rests exactly goes unnoticed (a multibody link)"]
fn limit_an_unseen_step_where_a_multibody_link_rests_exactly() {
    let ops = [
        Op::Cube {
            x: 0,
            y: 0,
            z: 0,
            r: 1,
        },
        Op::Multibody { a: 104, b: 49 },
        Op::Step(4),
        Op::ToggleSensor(48),
        Op::Unseen(1),
    ];
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// A second layer attached, stepping in turn with the first, then detached (taking
/// off the `COLLISION_EVENTS` flags it added), a body made fixed, solver groups set
/// and a multibody joined, under touching tracking: the world's trajectories are the
/// plain twin's, bit for bit, once the twin is given `detach`'s collider accesses in
/// the same order (they are Rapier's modified list; see the limit below). Found by
/// the `touching` configuration's long run with `PROPTEST_RNG_SEED=11`, shrunk.
#[test]
fn a_second_layer_detached_before_a_multibody_joins_keeps_trajectories() {
    run_unsteered(Config::Touching, &detached_then_changed(), true).unwrap();
}

/// The same without the twin given `detach`'s accesses: `detach` takes its flags off
/// with `ColliderSet::get_mut`, which puts each collider in Rapier's modified list
/// at that moment, and a collider the user changes before the next step keeps that
/// place (the solver groups here), so Rapier handles the changes in another order
/// than in a world never layered, and the next steps differ in their last bits.
/// Rapier's API has no write that leaves the list alone; `ContactLayer::detach`'s
/// docs say to detach after the changes, right before the next step.
#[test]
#[ignore = "limit: a collider changed after detach keeps the place of the layer's write in Rapier's modified list"]
fn limit_a_collider_changed_after_detach_keeps_the_place_of_the_layers_write() {
    let mut h = harness::Harness::with_config(Config::Touching);
    h.steer = false;
    h.mirror_detach = false;
    harness::run_harness(h, &detached_then_changed(), true).unwrap();
}

/// Detach, then the user's changes after it: the operations of the two tests above.
fn detached_then_changed() -> Vec<Op> {
    use harness::{Call, Second, Ty, Who};
    vec![
        Op::User(
            Who::Any(0),
            Call::Remove {
                keep_colliders: true,
            },
        ),
        ball(0, 0, 0, 2),
        Op::Second(Second::Attach),
        Op::Second(Second::Step(4)),
        Op::Step(4),
        Op::Cube {
            x: 0,
            y: 0,
            z: 0,
            r: 0,
        },
        Op::Second(Second::Step(3)),
        Op::Cube {
            x: 2,
            y: 1,
            z: 1,
            r: 3,
        },
        ball(2, 0, 0, 0),
        ball(1, 0, -3, 0),
        Op::Step(1),
        Op::SetType(110, Ty::Fixed),
        Op::Second(Second::Detach),
        Op::SolverGroups(121, 0),
        Op::Multibody { a: 14, b: 67 },
    ]
}

/// Bodies settled for 39 steps under `SpeedUps::default()`, one removed, an impulse
/// joint inserted between two of the others, then two steps of Rapier alone: the
/// layer's next step did not notice them, and a touching pair made in them had no
/// edge ("Rapier pair of nodes 9–11 has no edge"). The witness's two sampled bodies:
/// one resting exactly (the speed-ups zero a resting body's velocity), one drifting
/// too slowly to count as moving, whose pose did change; it asked every one to have
/// changed. Now, with none moving, the ones with any velocity tell. Found by the
/// default seed's long run, shrunk.
#[test]
fn fixed_an_unseen_step_after_a_joint_between_resting_bodies_is_noticed() {
    use harness::Preset;
    let ops = [
        Op::RemoveCollider(248),
        ball(0, 0, 0, 0),
        Op::Kinematic {
            x: 0,
            y: 0,
            z: 0,
            vx: 0,
            vz: 0,
            velocity_based: false,
        },
        Op::Static { x: 0, y: 0, z: 0 },
        ball(0, 0, 0, 0),
        ball(0, 0, 1, 0),
        Op::RemoveCollider(232),
        Op::Cube {
            x: 1,
            y: 1,
            z: -2,
            r: 1,
        },
        Op::Step(39),
        Op::RemoveBody(8),
        Op::Joint {
            a: 6,
            b: 193,
            revolute: false,
        },
        Op::Unseen(2),
    ];
    // Failed when found: "Rapier pair of nodes 9–11 has no edge".
    run_unsteered(Config::SpeedUps(Preset::Default), &ops, true).unwrap();
}
