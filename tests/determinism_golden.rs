//! Golden determinism hashes (in the style of Box2D's and Avian's
//! determinism tests).
//!
//! One fixed scene is run for 1,000 steps in four modes:
//! - `all`: the layer with every speed-up on (`rcg_lab::table5::combination(127)`, "CTRZDSF");
//! - `none`: the layer with the speed-ups attached but all off (`SpeedUps::none()`);
//! - `observe`: the plain observe-only layer (no speed-ups, no rules);
//! - `plain`: stock Rapier, no layer at all.
//!
//! The scene is `scenes::sphere_pile(200, 7)` plus, built here:
//! - a fixed sensor slab across the container at mid height, which the upper layers of
//!   spheres fall through (trigger enter and exit);
//! - a timer of 0.25 s (timer ticks);
//! - a heavy ball dropped onto the settled pile at step 600, through the slab, waking
//!   what it hits (wake-up after the pile fell asleep).
//!
//! So every event kind can occur: proximity and touch begin / persist / end, trigger
//! enter / exit, timer ticks, and (where something sleeps) fell-asleep and woke-up.
//!
//! Each run is hashed with an explicit 64-bit FNV-1a (std's `DefaultHasher` is not
//! specified and may change between releases):
//! - *pose checkpoints*: at every 100th step (100, 200, …, 1000), the step number and
//!   every body's handle (index, generation) and pose bits (translation x y z, rotation
//!   x y z w, `f32::to_bits`), bodies in handle order;
//! - *final pose*: the same for the state after the last step alone;
//! - *events*: the full event stream of an all-kinds subscription, per event its step,
//!   kind as `u8`, `node1` (index, generation), `node2` (presence byte, index,
//!   generation) and tick.
//!
//! Checked:
//! 1. two runs of each mode in one process give the same hashes (unconditional);
//! 2. the observe-only layer's pose hashes equal plain Rapier's (unconditional);
//! 3. the hashes equal the pinned constants below (x86_64 only); with
//!    `RCG_GOLDEN_SET=enhanced-determinism`, for a build with Rapier's
//!    `enhanced-determinism`, the second set below (every architecture).
//!
//! Built with the crate's `parallel` feature (Rapier on rayon's threads) the hashes
//! are the default build's: the same trajectories and the same event stream.
//!
//! # The pinned values
//! They were measured on x86_64 Linux with rustc 1.95.0, rapier3d 0.36.1 (default
//! features: no `enhanced-determinism`) and the test profile of this crate's
//! Cargo.toml (the release profile gives the same values). Rapier uses SIMD and the
//! compiler may contract or reorder float operations differently on another
//! architecture or toolchain, so the pins are only asserted on
//! `target_arch = "x86_64"`. A mismatch means the simulation or the
//! event stream changed: if that was intended (a Rapier upgrade, a change to the
//! analysis or the speed-ups, a new toolchain), update the constants deliberately and
//! note the change in CHANGELOG.md; the failing test prints the new values.

use std::sync::OnceLock;

use rapier3d::math::Vector;
use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Event, NodeId};
use rcg_scenes as scenes;

// ── Pinned hashes (x86_64, rustc 1.95.0, rapier3d 0.36.1) ──────────────
// Re-pinned deliberately whenever what the speed-ups do to motion or events changes,
// each time said in CHANGELOG.md; last when a release's spread through a held pile
// came to be given back over steps, at most a quarter of the dynamic bodies a step
// (the release budget): the poses and events of "all speed-ups" changed; the other
// two did not.

/// Every speed-up on: pose checkpoints, final pose, event stream.
const GOLDEN_ALL_POSES: u64 = 0x789d_a629_c652_61f6;
const GOLDEN_ALL_FINAL: u64 = 0xcf3c_1d27_da8a_4b17;
const GOLDEN_ALL_EVENTS: u64 = 0xddad_df94_7af4_c902;
/// `SpeedUps::none()`.
const GOLDEN_NONE_POSES: u64 = 0x91b4_8c73_eeb0_02d0;
const GOLDEN_NONE_FINAL: u64 = 0xea52_db4c_bfc2_35f8;
const GOLDEN_NONE_EVENTS: u64 = 0x8a04_d8ba_9e6f_7794;
/// The observe-only layer (its poses are plain Rapier's, checked separately).
const GOLDEN_OBSERVE_POSES: u64 = 0x7ade_e943_58ff_12cc;
const GOLDEN_OBSERVE_FINAL: u64 = 0x0105_6043_cac1_72fd;
const GOLDEN_OBSERVE_EVENTS: u64 = 0x03d0_0f6e_58d4_d9f8;

// ── Pinned hashes with Rapier's `enhanced-determinism` ─────────────────
// Rapier and parry then compute with libm's functions (parry without SIMD math):
// other trajectories than the default build's, the same on every platform. Checked
// when `RCG_GOLDEN_SET=enhanced-determinism` (CI's feature build, together with
// `parallel`: `--features parallel,rapier3d/enhanced-determinism`), on every
// architecture.

/// Every speed-up on, `enhanced-determinism`.
const ED_ALL: [u64; 3] = [
    0x696f_6f35_9a8b_6cec,
    0x6bb8_e2d7_c517_ccc7,
    0x529a_a38c_4d3a_c154,
];
/// `SpeedUps::none()`, `enhanced-determinism`.
const ED_NONE: [u64; 3] = [
    0xe7e1_1266_b3ac_3214,
    0xe3fb_53c9_8e1c_b3b2,
    0xd8cd_36a3_6234_25d2,
];
/// The observe-only layer, `enhanced-determinism`.
const ED_OBSERVE: [u64; 3] = [
    0xa5eb_3264_924e_14fa,
    0xc1e9_ef4a_0a3a_7dbc,
    0x85e1_49d4_7286_fcc2,
];

// ── The scene ──────────────────────────────────────────────────────────

const STEPS: u64 = 1000;
const CHECKPOINT_EVERY: u64 = 100;
const PILE: usize = 200;
const SEED: u64 = 7;
const TIMER_PERIOD: f64 = 0.25;
/// The 0-based step before which the heavy ball is dropped.
const DROP_AT: u64 = 600;

/// The pile with the sensor slab. The layer's modes and plain Rapier all start from
/// this world.
fn build_world() -> PhysicsWorld {
    let mut world = scenes::sphere_pile(PILE, SEED).world;
    // The container's inside spans -h..h; the drop layers are at y = 1.5, 2.7, 3.9,
    // 5.1, 6.3 and 7.5, and the settled pile is lower than 4 m. The slab (y 4.7..5.3)
    // holds the fourth layer at the start and the two above fall through it.
    let h = scenes::pile::inner_half_width(PILE);
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, 5.0, 0.0)),
        ColliderBuilder::cuboid(h - 0.1, 0.3, h - 0.1).sensor(true),
    );
    world
}

/// The per-step script: the heavy ball dropped onto the settled pile.
fn before_step(world: &mut PhysicsWorld, step: u64) {
    if step == DROP_AT {
        world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.3, 7.0, -0.2))
                .linvel(Vector::new(0.0, -4.0, 0.0)),
            ColliderBuilder::ball(0.8).density(5.0),
        );
    }
}

#[derive(Clone, Debug)]
enum Mode {
    Plain,
    Observe,
    SpeedUps(SpeedUps),
}

impl Mode {
    fn all() -> Self {
        Mode::SpeedUps(rcg_lab::table5::combination(127))
    }
    fn none() -> Self {
        Mode::SpeedUps(SpeedUps::none())
    }
}

// ── Hashing ────────────────────────────────────────────────────────────

/// 64-bit FNV-1a over bytes, written out so that its algorithm is fixed.
#[derive(Clone, Copy)]
struct Fnv1a(u64);

impl Fnv1a {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    fn new() -> Self {
        Self(Self::OFFSET)
    }
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }
    fn u8(&mut self, x: u8) {
        self.bytes(&[x]);
    }
    fn u32(&mut self, x: u32) {
        self.bytes(&x.to_le_bytes());
    }
    fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
    fn f32(&mut self, x: f32) {
        self.u32(x.to_bits());
    }
    fn node(&mut self, n: NodeId) {
        self.u32(n.index());
        self.u32(n.generation());
    }
}

/// Every body's handle and pose bits, in handle order.
fn hash_poses(h: &mut Fnv1a, world: &PhysicsWorld) {
    h.u64(world.bodies.len() as u64);
    for (handle, rb) in world.bodies.iter() {
        let (i, g) = handle.into_raw_parts();
        h.u32(i);
        h.u32(g);
        let p = rb.position();
        for x in [
            p.translation.x,
            p.translation.y,
            p.translation.z,
            p.rotation.x,
            p.rotation.y,
            p.rotation.z,
            p.rotation.w,
        ] {
            h.f32(x);
        }
    }
}

fn hash_event(h: &mut Fnv1a, e: &Event) {
    h.u64(e.step);
    h.u8(e.kind as u8);
    h.node(e.node1);
    match e.node2 {
        Some(b) => {
            h.u8(1);
            h.node(b);
        }
        None => h.u8(0),
    }
    h.u64(e.tick);
}

/// What a run is checked by.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Outcome {
    /// Pose checkpoints (every 100th step, the last included).
    poses: u64,
    /// The pose after the last step.
    final_pose: u64,
    /// The event stream (`None` for plain Rapier).
    events: Option<u64>,
    /// Events per kind, in `EventKind::ALL` order.
    counts: [u64; EventKind::ALL.len()],
    bodies: usize,
}

fn run(mode: &Mode) -> Outcome {
    let mut world = build_world();
    let mut layer = match mode {
        Mode::Plain => None,
        Mode::Observe => Some(ContactLayer::new()),
        Mode::SpeedUps(cfg) => {
            let mut l = ContactLayer::new();
            l.speedups_mut().set(Some(cfg.clone())).unwrap();
            Some(l)
        }
    };
    let rx = layer.as_mut().map(|l| {
        l.logic_mut().add_timer(TIMER_PERIOD).unwrap();
        l.subscribe(Filter::all())
    });

    let mut poses = Fnv1a::new();
    let mut events = Fnv1a::new();
    let mut counts = [0u64; EventKind::ALL.len()];
    for step in 0..STEPS {
        before_step(&mut world, step);
        match &mut layer {
            Some(l) => {
                l.step(&mut world);
            }
            None => world.step(),
        }
        if let Some(rx) = &rx {
            for e in rx.try_iter() {
                hash_event(&mut events, &e);
                counts[e.kind as usize] += 1;
            }
        }
        let done = step + 1;
        if done % CHECKPOINT_EVERY == 0 {
            poses.u64(done);
            hash_poses(&mut poses, &world);
        }
    }
    if let Some(l) = &layer {
        l.validate(&world).unwrap();
    }
    let mut final_pose = Fnv1a::new();
    hash_poses(&mut final_pose, &world);
    Outcome {
        poses: poses.0,
        final_pose: final_pose.0,
        events: rx.map(|_| events.0),
        counts,
        bodies: world.bodies.len(),
    }
}

/// The first run of each mode, shared by the tests of this file (they run on
/// parallel threads; each mode's first run is computed once).
fn first_run(mode: &Mode) -> &'static Outcome {
    static ALL: OnceLock<Outcome> = OnceLock::new();
    static NONE: OnceLock<Outcome> = OnceLock::new();
    static OBSERVE: OnceLock<Outcome> = OnceLock::new();
    static PLAIN: OnceLock<Outcome> = OnceLock::new();
    let cell = match mode {
        Mode::Plain => &PLAIN,
        Mode::Observe => &OBSERVE,
        Mode::SpeedUps(c) if *c == SpeedUps::none() => &NONE,
        Mode::SpeedUps(c) if *c == rcg_lab::table5::combination(127) => &ALL,
        Mode::SpeedUps(c) => panic!("no cached run for {}", rcg_lab::table5::full_label(c)),
    };
    cell.get_or_init(|| run(mode))
}

fn count(o: &Outcome, kind: EventKind) -> u64 {
    o.counts[kind as usize]
}

fn describe(name: &str, o: &Outcome) -> String {
    let counts: Vec<String> = EventKind::ALL
        .iter()
        .map(|&k| format!("{k:?}={}", count(o, k)))
        .collect();
    format!(
        "{name}: poses {:#018x}, final {:#018x}, events {}, bodies {}\n  {}",
        o.poses,
        o.final_pose,
        o.events
            .map(|e| format!("{e:#018x}"))
            .unwrap_or_else(|| "-".into()),
        o.bodies,
        counts.join(" ")
    )
}

fn assert_same_twice(name: &str, mode: Mode) {
    let first = first_run(&mode);
    let second = run(&mode);
    assert_eq!(
        first,
        &second,
        "{name}: two runs in one process differ\n{}\n{}",
        describe("first", first),
        describe("second", &second)
    );
    println!("{}", describe(name, first));
}

// ── Tests ──────────────────────────────────────────────────────────────

#[test]
fn all_speedups_two_runs_are_bit_identical() {
    assert_same_twice("all (CTRZDSF)", Mode::all());
}

#[test]
fn no_speedups_two_runs_are_bit_identical() {
    assert_same_twice("none", Mode::none());
}

#[test]
fn observe_only_two_runs_are_bit_identical() {
    assert_same_twice("observe", Mode::Observe);
}

#[test]
fn plain_rapier_two_runs_are_bit_identical() {
    assert_same_twice("plain", Mode::Plain);
}

#[test]
fn observe_only_poses_equal_plain_rapier() {
    let observe = first_run(&Mode::Observe);
    let plain = first_run(&Mode::Plain);
    assert_eq!(
        (observe.poses, observe.final_pose),
        (plain.poses, plain.final_pose),
        "the observe-only layer changed Rapier's trajectories\n{}\n{}",
        describe("observe", observe),
        describe("plain", plain)
    );
}

/// The scene does what it is for: every event kind occurs in the runs where it can.
#[test]
fn every_event_kind_occurs() {
    let observe = first_run(&Mode::Observe);
    let all = first_run(&Mode::all());
    let none = first_run(&Mode::none());
    // The golden runs do not run the plausibility monitor: its kinds are covered by
    // tests/monitor_modes.rs.
    let kinds = EventKind::ALL
        .into_iter()
        .filter(|&k| !KindSet::MONITOR.contains(k));
    for k in kinds.clone() {
        assert!(
            count(observe, k) > 0,
            "observe: no {k:?}\n{}",
            describe("observe", observe)
        );
    }
    // With every speed-up on, fixation turns sleepy bodies fixed before their island
    // can sleep, and a fixation and its release are not reported as sleep events; so
    // the sleep kinds are not required here.
    for k in kinds.clone() {
        if !matches!(k, EventKind::FellAsleep | EventKind::WokeUp) {
            assert!(count(all, k) > 0, "all: no {k:?}\n{}", describe("all", all));
        }
    }
    // Without `sleepy` nothing sleeps; every other kind occurs.
    for k in kinds {
        let sleep = matches!(k, EventKind::FellAsleep | EventKind::WokeUp);
        assert_eq!(
            count(none, k) == 0,
            sleep,
            "none: {k:?}\n{}",
            describe("none", none)
        );
    }
    // The timer ticks 4 times a simulated second, whatever the speed-ups.
    for o in [observe, all, none] {
        assert_eq!(count(o, EventKind::TimerTick), 40);
    }
}

/// The pinned hashes of the build under test (`RCG_GOLDEN_SET`: unset or `default`,
/// or `enhanced-determinism`): all, none, observe. `None` where they are not asserted
/// (the default set off x86_64).
fn pinned_set() -> Option<(&'static str, [[u64; 3]; 3])> {
    match std::env::var("RCG_GOLDEN_SET").as_deref() {
        Err(_) | Ok("default") => cfg!(target_arch = "x86_64").then_some((
            "x86_64",
            [
                [GOLDEN_ALL_POSES, GOLDEN_ALL_FINAL, GOLDEN_ALL_EVENTS],
                [GOLDEN_NONE_POSES, GOLDEN_NONE_FINAL, GOLDEN_NONE_EVENTS],
                [
                    GOLDEN_OBSERVE_POSES,
                    GOLDEN_OBSERVE_FINAL,
                    GOLDEN_OBSERVE_EVENTS,
                ],
            ],
        )),
        Ok("enhanced-determinism") => Some(("enhanced-determinism", [ED_ALL, ED_NONE, ED_OBSERVE])),
        Ok(other) => panic!("RCG_GOLDEN_SET={other}: default or enhanced-determinism"),
    }
}

#[test]
fn hashes_match_the_pinned_values() {
    let Some((set, [all, none, observe])) = pinned_set() else {
        return;
    };
    let cases = [
        ("ALL", first_run(&Mode::all()), all),
        ("NONE", first_run(&Mode::none()), none),
        ("OBSERVE", first_run(&Mode::Observe), observe),
    ];
    let mut mismatches = Vec::new();
    for (name, o, pinned) in cases {
        let measured = [o.poses, o.final_pose, o.events.expect("a layer run")];
        for (what, (m, p)) in ["POSES", "FINAL", "EVENTS"]
            .iter()
            .zip(measured.iter().zip(pinned))
        {
            if *m != p {
                mismatches.push(format!(
                    "const GOLDEN_{name}_{what}: u64 = {m:#018x}; // pinned {p:#018x}"
                ));
            }
        }
    }
    assert!(
        mismatches.is_empty(),
        "golden determinism hashes changed ({set}). If the change is intended, update \
         the constants deliberately and note it in CHANGELOG.md. New values:\n{}",
        mismatches.join("\n")
    );
}
