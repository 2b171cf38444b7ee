//! Fuzzed operation sequences : random sequences of world and layer
//! operations interleaved with steps, checked after every analysed step.
//!
//! # The operation language ([`harness::Op`])
//! The world is a closed box arena (a fixed floor body, four walls and a ceiling as
//! parentless colliders) so that what is added stays close and interacts. Positions are
//! on a 0.5 m grid, so new bodies often overlap others. An operation names bodies,
//! colliders and joints by an index taken modulo the live ones (in Rapier's slot
//! order), and nodes by an index into the live nodes of the kinds concerned, so every
//! sequence is meaningful and shrinks well. The operations:
//! - **world:** add a dynamic ball or box, a fixed body, a parentless solid collider,
//!   a kinematic body (velocity- or position-based, with a velocity), a sensor (on a
//!   body or parentless), an extra solid collider on a body; remove a body or a
//!   collider; toggle a collider's sensor flag; change a body's type; teleport a body
//!   (`set_translation(.., true)`) or move a parentless collider; set a velocity; put a
//!   body to sleep (`RigidBody::sleep`) or wake it; add or remove an impulse joint
//!   (fixed or revolute) and a multibody joint (revolute);
//! - **layer:** make a body passive or active (`set_body_disabled`); add or remove a rule
//!   (`Rule::ignore_pair`, `Rule::ignore_between` on live body, static-collider and
//!   trigger nodes), a timer, a declared composite; subscribe (bounded or not, filtered by kind and node),
//!   unsubscribe, drop a receiver; switch the speed-ups on, off or to another
//!   combination (`set_speedups(Some(SpeedUps::combination(bits)))` / `None`); ask
//!   for touching or proximity tracking (`set_tracking`); `request_full_sync`;
//! - **`Step(n)`:** n steps of `ContactLayer::step` (1–5 mostly, sometimes 20–40 so
//!   that bodies settle, sleep and get sleepy).
//!
//! A sequence has 20–60 operations; the harness steps once before and three times
//! after them.
//!
//! Touching tracking yields to any subscription to proximity or persist events, and
//! the harness's own contract subscribers ask for every kind: so here it never takes
//! effect (the totals count the steps where it did: 0), and the operation checks that
//! asking for it changes nothing else. Touching tracking itself is tested in
//! `tests/touch_tracking.rs` (equal touch events and touching edges to proximity
//! tracking step by step, validated, on several scenes).
//!
//! Following the docs, the harness calls `request_full_sync()` after changing a
//! *sleeping, fixed or passive* body in place (type change, moving a fixed body or a
//! parentless collider), and after an insertion and a removal between the same two
//! steps (`audit`, B1: otherwise found within `slots / verify_budget()` steps only).
//! It keeps no invariant of its own: it reads the world and the layer after each step.
//!
//! # Known bugs the generator steers clear of
//! Each bug found is a minimised regression test in `tests/fuzz_regressions_*.rs`
//! (`_triggers`: sensors and triggers; `_sync`: world changes the layer must see, and
//! sleep events; `_joints`: joints, containers, multibodies and passive bodies):
//! `bug_*`, marked `#[ignore = "bug: ..."]`, for the open ones; `fixed_*` for those
//! fixed since (they failed when found). So that the fuzzing goes on finding new bugs, the harness
//! avoids what triggers the open ones (each place names the test). None is open now;
//! what it still avoids is
//! - Rapier's own panics and preconditions, which the layer cannot prevent: multibody
//!   links stay dynamic and get one parent (a rejected insertion corrupts Rapier's
//!   bookkeeping); no multibody member is made active with `set_body_disabled(false)`
//!   (Rapier may have quarantined it); no joint or multibody joint to a body Rapier
//!   disabled itself (quarantined: plain Rapier panics on a joint between two
//!   disabled bodies, and the layer guards only the bodies it made passive).
//!
//! `set_body_disabled(true)` is called on any body: the layer refuses dynamic multibody
//! members (`Error::Unsupported`), and the harness follows `refusals()`.
//!
//! # What is checked after every step
//! Nothing panics (a panic anywhere is a failure), and:
//! 1. `layer.validate(&world)` is Ok (only after analysed steps: user changes between
//!    steps are seen at the next step);
//! 2. the **event contract** of `events`, by a checker of our own subscribed to every
//!    event: pair events name *A* (smaller slot) first; every `Begin` is followed by
//!    `Persist`s and one `End`; touch spans nest in proximity spans; `Enter`/`Exit`
//!    alternate; `FellAsleep`/`WokeUp` alternate and agree with the node's awake flag;
//!    ticks count up by one; `Persist` names a pair with an awake body; no `Begin`,
//!    `Persist`, `Enter` or sleep event names a pair a rule in force during the step
//!    ignores, or a body passive during the step (ends are allowed: they close
//!    spans); every event carries the step's index; the open spans equal the graph's proximate, touching
//!    and geometric edges. The shared `ContractLog` of `tests/common` runs too (its
//!    `passive` set kept to the bodies passive during the step, with its
//!    `agrees_with(layer)`);
//! 3. **subscriptions:** the contract subscriber receives exactly `last_events()`;
//!    every other subscription receives exactly the events of the step that match its
//!    filter (kinds, nodes with container membership), a bounded one the first
//!    `capacity` of them (receivers are drained every step), and `unsubscribe` of a
//!    live subscription succeeds;
//! 4. **the graph equals a graph rebuilt from scratch from Rapier's state:** a fresh
//!    `ContactLayer` analyses the world once (`fresh.analyze(WorldView::from(&world))`,
//!    its own `validate()` must hold too) and the two graphs are compared on what is
//!    derived from Rapier's state alone:
//!    - nodes of bodies, static colliders, sensors and joint-derived containers, by
//!      source, with their kind (and a trigger's carrier body);
//!    - proximate physical edges, by their ends' sources, with the touching flag, the
//!      contact count and the number of collider pairs;
//!    - geometric (trigger) edges, and structural edges of joint-derived containers.
//!
//!    Out of scope (a fresh layer cannot know them): rules and their logical edges,
//!    timers, declared composites, passive flags, lingering (vanished, not yet
//!    obsolete) edges, marks, groups, sleepy/fixated state of the speed-ups. Pairs a
//!    rule of the layer ignores, and pairs with a disabled (passive) body, are left out
//!    of both sides (the same screen as `validate()`);
//! 5. the layer's awake flags equal Rapier's active set (fixed bodies never awake), and
//!    every body node's passive flag equals `!is_enabled()`, which equals what the user
//!    last asked with `set_body_disabled` (unless Rapier quarantined the body).
//!
//! # Running
//! - default: 256 sequences, fixed seed (deterministic): `cargo test --test
//!   fuzz_operations` (well under a second);
//! - long run: `PROPTEST_CASES=10000 cargo test --release --test fuzz_operations`
//!   (add `PROPTEST_RNG_SEED=<n>` for another deterministic seed; `FUZZ_TRACE=1`
//!   prints each operation; `--nocapture` shows the totals). A failure is shrunk by
//!   proptest, then by removing operations one by one, and printed as a list of
//!   `Op`s to paste into `harness::run`;
//! - coverage-guided: `fuzz/` holds a cargo-fuzz target on the same harness
//!   (operations decoded from the fuzzer's bytes); see `fuzz/README.md`.
//!
//! # Where the parts are
//! This file holds the property; the harness is `tests/common/fuzz/` (included below
//! as the module `harness`, which the cargo-fuzz target reaches through this file):
//! the operations (`ops.rs`), what they do (`apply.rs`), the checks (`check.rs`,
//! `contract.rs`, `derived.rs`), the proptest generator (`strategies.rs`) and the
//! runner that minimises a failure (`runner.rs`).

#![allow(clippy::too_many_lines)]

#[cfg(test)]
mod common;

/// The operation language and the checks (`tests/common/fuzz/`); no proptest outside
/// its `cfg(test)` parts, so that the cargo-fuzz target can include this file.
#[path = "common/fuzz/mod.rs"]
pub mod harness;

/// The property: every sequence the generator makes keeps every check.
#[cfg(test)]
mod fuzz {
    use std::sync::Mutex;

    use proptest::test_runner::{TestCaseError, TestError, TestRunner};

    use super::harness::runner::{config, minimise, silence_panics};
    use super::harness::{self, strategies, Counters};

    #[test]
    fn fuzzed_operation_sequences_keep_every_invariant() {
        let cfg = config();
        let cases = cfg.cases;
        let trace = std::env::var_os("FUZZ_TRACE").is_some();
        let total = Mutex::new(Counters::default());
        let start = std::time::Instant::now();
        let mut runner = TestRunner::new(cfg);
        let hook = silence_panics();
        let result = runner.run(&strategies::ops(), |ops| {
            if trace {
                eprintln!("sequence of {} ops", ops.len());
            }
            let c = harness::run(&ops, trace).map_err(TestCaseError::fail)?;
            let mut t = total.lock().unwrap();
            t.ops += c.ops;
            t.steps += c.steps;
            t.events += c.events;
            t.max_nodes = t.max_nodes.max(c.max_nodes);
            t.kinds_seen |= c.kinds_seen;
            t.sleeping_seen += c.sleeping_seen;
            t.refused += c.refused;
            t.touching_steps += c.touching_steps;
            Ok(())
        });
        let result = result.map_err(|e| match e {
            TestError::Fail(reason, ops) => {
                let (ops, reason) = minimise(ops, reason.to_string());
                let list: Vec<String> = ops.iter().map(|op| format!("        {op:?},")).collect();
                format!(
                    "{reason}\nminimised sequence ({} ops):\n{}",
                    ops.len(),
                    list.join("\n")
                )
            }
            e => e.to_string(),
        });
        std::panic::set_hook(hook);
        let t = *total.lock().unwrap();
        eprintln!(
            "fuzz_operations: {cases} cases in {:.1?}: {} ops, {} steps, {} events, \
             max {} nodes, event kinds seen {:#013b}, body-steps asleep {}, \
             passive changes refused {}, steps with touching tracking {}",
            start.elapsed(),
            t.ops,
            t.steps,
            t.events,
            t.max_nodes,
            t.kinds_seen,
            t.sleeping_seen,
            t.refused,
            t.touching_steps
        );
        if let Err(e) = result {
            panic!("{e}");
        }
    }
}
