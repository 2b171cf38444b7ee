//! Fuzzed operation sequences: random sequences of world and layer operations, the
//! user's own Rapier calls and steps, run under several configurations of the layer
//! and checked after every step.
//!
//! # The configurations (`harness::Config`), one test each
//! Each runs 256 sequences by default (`PROPTEST_CASES` overrides), from a seed of its
//! own, and prints a totals line (`--nocapture`).
//! - **`touching`**: what a user gets. The layer's defaults: touching tracking driven
//!   by Rapier's collision events, sensors as the user built them; the base subscriber
//!   (the contract checker's) asks for `KindSet::COLLISION_EVENTS` (contact and
//!   sensor start / stop), and nine in ten generated subscriptions leave out the kinds
//!   that need every pair read. The run asserts that touching tracking was in effect
//!   on most analysed steps. Observe-only: compared bit for bit with a plain twin.
//! - **`proximity`**: the base subscriber asks for every kind, so the layer reads
//!   every pair each step (asserted: touching tracking in effect on no step); sensors
//!   widened (`set_trigger_widening`). Observe-only: compared with a twin.
//! - **`speedups_default`, `speedups_contact_graph`, `speedups_reliable_sleep`,
//!   `speedups_papers_fastest`**: `SpeedUps::default()`, `contact_graph()`,
//!   `reliable_sleep()`, `papers_fastest()` set at the start, with the monitor in
//!   repair mode (`MonitorConfig::default()`), under the default tracking (asserted
//!   in effect on most steps); the base subscriber asks for every kind touching
//!   tracking delivers, monitor events included. Operations may switch to another of
//!   the 2^7 combinations or off and back to the preset, and the monitor off and on.
//!   With fixation on, the run asserts that some body was held. Bodies settle more
//!   often here (more long runs of steps), so that the speed-ups hold and park them.
//!
//! # The operation language (`harness::Op`)
//! The world is a closed box arena (a fixed floor body, four walls and a ceiling as
//! parentless colliders) so that what is added stays close and interacts. Positions are
//! on a 0.5 m grid, so new bodies often overlap others. An operation names bodies,
//! colliders and joints by an index taken modulo the live ones (in Rapier's slot
//! order), and nodes by an index into the live nodes of the kinds concerned, so every
//! sequence is meaningful and shrinks well. The operations:
//! - **world:** add a dynamic ball or box, a fixed body, a parentless solid collider,
//!   a kinematic body (velocity- or position-based, with a velocity), a sensor (on a
//!   body or parentless), an extra solid collider on a body; remove a body or a
//!   collider; toggle a collider's sensor flag; move a collider to another body or
//!   none; change a collider's groups, enabled flag, hook and event flags, shape;
//!   change a body's type; teleport a body (`set_translation(.., true)`) or move a
//!   parentless collider; set a velocity; put a body to sleep (`RigidBody::sleep`) or
//!   wake it; add or remove an impulse joint (fixed or revolute) and a multibody joint
//!   (revolute);
//! - **the user's own Rapier calls** (`Op::User`) on any body, a held one (one
//!   `LayerAnalysis::holds`: fixated by the speed-ups or asleep) or a parked one (held
//!   and taken out of Rapier's active set by the speed-ups), each falling back to the
//!   next kind when there is none: `apply_impulse(.., true)`, `set_linvel(.., true)`,
//!   `set_body_type(.., true)`, `set_enabled`, `sleep()`, `wake_up(true)`, and removal
//!   with `RigidBodySet::remove` (islands, colliders, joints; colliders kept or not);
//! - **steps the layer does not see** (`Op::Unseen`): Rapier's `PhysicsWorld::step`
//!   between the layer's steps; **a second `ContactLayer`** on the same world
//!   (`Op::Second`: attached, detached, or stepping instead of the first, as two
//!   subsystems of a game taking turns; it reads every pair under the proximity
//!   configuration, follows the default tracking elsewhere). Generated since the
//!   layer notices steps it did not see (`harness::config::UNSEEN_STEPS_RECOVERED`;
//!   `FUZZ_UNSEEN=0` / `1` overrides);
//! - **layer:** make a body passive or active (`set_body_disabled`); add or remove a
//!   rule (`Rule::ignore_pair`, `Rule::ignore_between` on live body, static-collider
//!   and trigger nodes), a timer, a declared composite; subscribe (bounded or not,
//!   filtered by kind and node, or by Rapier handle), unsubscribe, drop a receiver;
//!   ask for touching or proximity tracking (`set_tracking`); `request_full_sync`;
//!   where a preset runs, switch the speed-ups to another combination, off, or back to
//!   the preset, and the monitor off or on;
//! - **`Step(n)`:** n steps of `ContactLayer::step` (1–5 mostly, sometimes 20–40 so
//!   that bodies settle, sleep and get sleepy).
//!
//! A sequence has 20–60 operations; the harness steps once before and three times
//! after them. Under the observe-only configurations half of the sequences have no
//! operation that lets the layer change motion (rules, passive bodies), so that the
//! twin is compared all along.
//!
//! Following the docs, the harness calls `request_full_sync()` after changing a
//! *sleeping, fixed or disabled* body in place (type change, enabled flag, moving a
//! fixed body or a parentless collider), and after an insertion and a removal between
//! the same two steps (`audit`, B1: otherwise found within `slots / verify_budget()`
//! steps only), on both layers when there are two; after detaching the second layer
//! (it takes off the `COLLISION_EVENTS` flags it added, which the first may have
//! relied on). A type the user gives a held body, or its enabled flag, gets no full
//! sync: the layer answers them itself (rule 4 of "Releasing held bodies"). The harness keeps no invariant of its own: it reads the
//! world and the layer after each step.
//!
//! # What is checked after every step
//! Nothing panics (a panic anywhere is a failure), and after every step the layer
//! analysed:
//! 1. `layer.validate(&world)` is Ok; and the **touching oracle**: the collider pairs
//!    Rapier's narrow phase says touch (`ContactPair::has_any_active_contact()`), by
//!    body or static collider, equal the graph's touching edges, screened as
//!    `validate()` screens (rule-ignored pairs, disabled bodies, pairs no physical
//!    edge may join) but written from Rapier's API alone. Under touching tracking no
//!    event needs every pair read (`KindSet::NEEDS_EVERY_PAIR`);
//! 2. the **event contract** of `events`, by a checker of our own subscribed with
//!    the configuration's base filter, for the kinds that filter carries: pair events
//!    name *A* (smaller slot) first; every `Begin` is followed by `Persist`s and one
//!    `End`; touch spans nest in proximity spans (when proximity kinds are carried);
//!    `Enter`/`Exit` alternate; `FellAsleep`/`WokeUp` alternate and agree with the
//!    node's awake flag; ticks count up by one; `Persist` names a pair with an awake
//!    body; no `Begin`, `Persist`, `Enter`, sleep or monitor event names a pair a rule
//!    in force during the step ignores, or a body passive during the step (ends are
//!    allowed: they close spans); monitor events only with the monitor on, each naming
//!    one body and its violation; every event carries the step's index; the open spans
//!    of the carried kinds equal the graph's proximate, touching and geometric edges.
//!    The shared `ContractLog` of `tests/common` runs too;
//! 3. **subscriptions:** the contract subscriber receives exactly the events of
//!    `last_events()` of its kinds; every other subscription receives exactly the
//!    events of the step that match its filter (kinds, nodes with container
//!    membership, bodies, colliders), a bounded one the first `capacity` of them
//!    (receivers are drained every step), and `unsubscribe` of a live subscription
//!    succeeds;
//! 4. **the graph equals a graph rebuilt from scratch from Rapier's state:** a fresh
//!    `ContactLayer` analyses the world once (its own `validate()` must hold too) and
//!    the two graphs are compared on what is derived from Rapier's state alone: nodes
//!    of bodies, static colliders, sensors and joint-derived containers, by source,
//!    with their kind (and a trigger's carrier body); proximate physical edges, by
//!    their ends' sources, with the touching flag, the contact count and the number of
//!    collider pairs; geometric (trigger) edges, and structural edges of joint-derived
//!    containers. Out of scope (a fresh layer cannot know them): rules and their
//!    logical edges, timers, declared composites, passive flags, lingering (vanished,
//!    not yet obsolete) edges, marks, groups, sleepy and held state of the speed-ups.
//!    Pairs a rule of the layer ignores, and pairs with a disabled body, are left out
//!    of both sides (the same screen as `validate()`);
//! 5. **awake, passive and held flags against Rapier:** a body node is awake exactly
//!    when Rapier has the body in its active set and the node is not `Fixed` (a body
//!    the speed-ups hold is fixed to Rapier, and its node `Fixed`: never awake); every
//!    body node's passive flag equals `!is_enabled()`, except for held bodies the
//!    speed-ups disabled for this one step to park them (`SpeedUpState::parking`),
//!    which are not passive; Rapier's enabled flag is what was asked last, by
//!    `set_body_disabled` or by the user's own `set_enabled` (unless Rapier
//!    quarantined the body; a `set_body_disabled` since the last step is applied at
//!    the next pre-step, after the user's calls, and stays the last word); every
//!    parking body is held, fixed and disabled in Rapier;
//! 6. **the twin**, under the observe-only configurations: a plain Rapier world given
//!    the same world operations and user calls, stepped by `PhysicsWorld::step` alone
//!    whenever the world steps (the layer's step, an unseen step, the second layer's
//!    step), has bit for bit the same bodies: poses, velocities, types, enabled and
//!    sleep flags. Widened sensors are a documented change of the sensors' types: the
//!    twin's sensors get the types the layer gave the world's, set as the layer sets
//!    them. The twin is dropped at the first operation that lets the layer change
//!    motion (a rule, a passive body); under the speed-ups configurations there is
//!    none (the speed-ups change motion by design).
//!
//! After a step of the second layer: its `validate()`, the touching oracle for it,
//! and the twin. After a step the layer did not see: the twin only (nothing was
//! analysed); the layer's next step must catch up, and every check above holds then.
//!
//! # What is not checked, and why
//! - Between a step and the layer's analysis of it nothing is checked: user changes
//!   between steps are seen at the next step.
//! - The speed-ups' decisions (which body to hold, when to release) and the monitor's
//!   verdicts are not judged: the property checks that the layer's picture of the
//!   world stays true whatever they decide (their own tests judge the decisions). What
//!   a held body does with the user's impulse or velocity is not checked either:
//!   Rapier drops writes to a fixed body (documented in `SpeedUps::reliable_sleep`).
//! - No trajectory check under the speed-ups (they change motion), nor after a rule
//!   or a passive body under the observe-only configurations.
//! - The second layer subscribes to nothing: only its graph is checked.
//!
//! # Known bugs and limits the generator steers clear of
//! Each bug found is a minimised regression test in `tests/fuzz_regressions_*.rs`
//! (`_triggers`: sensors and triggers; `_sync`: world changes the layer must see, and
//! sleep events; `_joints`: joints, containers, multibodies and passive bodies;
//! `_touching`: touching tracking; `_tracking`: the collision-event flags, colliders
//! changed by the user, widened sensors; `_unseen`: steps the layer did not see, two
//! layers on one world; `_held`: held bodies and the monitor): `bug_*`, marked
//! `#[ignore = "bug: ..."]`, for the open ones; `fixed_*` for those fixed since (they
//! failed when found); `limit_*`, ignored, for what was found and then documented as a
//! limit (they fail with `--ignored`). So that the fuzzing goes on finding new bugs,
//! the harness avoids what triggers the open bugs and the limits (`Harness::steer`;
//! each place names the test; `harness::run_unsteered` replays without it):
//! - no held body joins a multibody
//!   (`limit_a_quarantined_body_beside_a_rule_trips_rapiers_island_assertion`);
//! - no user `set_enabled(false)` on a held body in its parking step
//!   (`limit_a_held_body_the_user_disables_while_parking_stays_disabled`);
//! - no unseen step and no second-layer step while a held body is a multibody link
//!   (`limit_an_unseen_step_with_a_held_body_joined_to_a_multibody_panics_rapier`), a
//!   joint the layer has not guarded yet has a disabled body
//!   (`limit_an_unseen_step_with_a_new_joint_to_a_passive_body_does_not_panic`:
//!   Rapier panics), or a multibody holds a disabled body
//!   (`limit_an_unseen_step_with_a_passive_body_in_a_multibody_does_not_panic`), or
//!   the layer has rules (`limit_a_rule_holds_across_an_unseen_step_where_nothing_moves`),
//!   or, under the speed-ups, no awake dynamic body moves
//!   (`limit_an_unseen_step_where_every_sampled_body_rests_exactly_under_the_speed_ups`,
//!   `limit_an_unseen_step_where_a_woken_body_sleeps_again_under_the_speed_ups`);
//! - no collider is moved onto or attached to a disabled multibody member (Rapier
//!   panics, with or without the layer:
//!   `limit_a_collider_moved_onto_a_quarantined_multibody_root_panics_rapier`);
//! - the twin is dropped when a second layer detaches
//!   (`bug_a_second_layer_detached_before_a_multibody_joins_keeps_trajectories`);
//! - the twin gets the layer's own `COLLISION_EVENTS` writes, at the same time
//!   (`limit_flags_added_after_an_unseen_step_change_no_trajectory`);
//! - the second layer gets a full sync when the first changed a sensor's collision
//!   types since its last step, as `set_trigger_widening`'s docs ask
//!   (`limit_a_second_layer_sees_a_new_sensor_the_first_widened`).
//!
//! Met by the check itself (always, steered or not): the twin gets the collision
//! types the layer gave the world's colliders (widened, or given back), set as the
//! layer sets them, so that it compares what the layer does beyond the widening
//! (`limit_widened_sensor_keeps_a_kinematic_body_awake`,
//! `limit_widening_a_sensor_rapier_stepped_changes_trajectories`: widening is not
//! observe-only, as its docs now say).
//!
//! What the harness avoids besides, because Rapier itself panics or cannot do it:
//! multibody links stay dynamic and get one parent (a rejected insertion corrupts
//! Rapier's bookkeeping); no multibody member is made active or enabled (Rapier may
//! have quarantined it), nor disabled by the user; no joint or multibody joint to a
//! body disabled by Rapier or by the user, no user disable of a body jointed to a
//! disabled one, and no body jointed to a disabled one made fixed or kinematic
//! (plain Rapier panics on a joint between two disabled bodies, and on one between a
//! disabled and a fixed body; the
//! layer guards only the bodies it made passive). `set_body_disabled(true)` is called
//! on any body: the layer refuses dynamic multibody members (`Error::Unsupported`),
//! and the harness follows `refusals()`.
//!
//! # Running
//! - default: 256 sequences per configuration, fixed seeds (deterministic): `cargo
//!   test --test fuzz_operations` (a few seconds per configuration; they run in
//!   parallel); one configuration: `cargo test --test fuzz_operations touching`;
//! - long run: `PROPTEST_CASES=10000 cargo test --release --test fuzz_operations
//!   <name> -- --nocapture` (add `PROPTEST_RNG_SEED=<n>` for another deterministic
//!   seed; `FUZZ_TRACE=1` prints each operation). A failure is shrunk by proptest,
//!   then by removing operations one by one, and printed as a list of `Op`s to paste
//!   into `harness::run_in(Config::…, &ops, true)`;
//! - coverage-guided: `fuzz/` holds a cargo-fuzz target on the same harness
//!   (configuration and operations decoded from the fuzzer's bytes); see
//!   `fuzz/README.md`.
//!
//! # Where the parts are
//! This file holds the property; the harness is `tests/common/fuzz/` (included below
//! as the module `harness`, which the cargo-fuzz target reaches through this file):
//! the configurations (`config.rs`), the operations (`ops.rs`), what they do
//! (`apply.rs` for the world, `apply_layer.rs` for the layer, `apply_user.rs` for the
//! user's own calls, unseen steps and the second layer), the checks (`check.rs`,
//! `contract.rs`, `derived.rs`, `oracle.rs`, `twin.rs`), the proptest generator
//! (`strategies.rs`) and the runner that minimises a failure and prints the totals
//! (`runner.rs`).

#![allow(clippy::too_many_lines)]

#[cfg(test)]
mod common;

/// The operation language and the checks (`tests/common/fuzz/`); no proptest outside
/// its `cfg(test)` parts, so that the cargo-fuzz target can include this file.
#[path = "common/fuzz/mod.rs"]
pub mod harness;

/// The property under each configuration (`harness::Config`): every sequence the
/// generator makes keeps every check. One test each, so that they run in parallel
/// and report separately; `cargo test --test fuzz_operations <name>` runs one.
#[cfg(test)]
mod fuzz {
    use super::harness::runner::property;
    use super::harness::{Config, Preset};

    #[test]
    fn touching() {
        property(Config::Touching);
    }

    #[test]
    fn proximity() {
        property(Config::Proximity);
    }

    #[test]
    fn speedups_default() {
        property(Config::SpeedUps(Preset::Default));
    }

    #[test]
    fn speedups_contact_graph() {
        property(Config::SpeedUps(Preset::ContactGraph));
    }

    #[test]
    fn speedups_reliable_sleep() {
        property(Config::SpeedUps(Preset::ReliableSleep));
    }

    #[test]
    fn speedups_papers_fastest() {
        property(Config::SpeedUps(Preset::PapersFastest));
    }
}
