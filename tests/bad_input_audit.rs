//! Bad-input audit (issue 6, item 4): one test per row of the table in
//! `src/audit.rs` (`rapier_contact_graph::audit`), named as the table names it.
//!
//! Every test feeds one public entry point the five kinds of bad input the table has
//! columns for: a stale id or handle, a foreign one (from another world or layer, or
//! never issued), a non-finite value, an out-of-range parameter, and a call at the
//! wrong time. Each call runs under `no_panic`, so a panic is reported as what it is.
//!
//! Tests named `bug_*` are `#[ignore]`d: each one states what the call *should* do
//! and fails today; the table marks their cells "PANICS", "HANGS", "LOSES STATE",
//! "NO ERROR", "WRONG ERROR" or "WRONG ANSWER" (bug Bn). Run them with
//! `cargo test --test bad_input_audit -- --ignored`. The two that would hang are run in
//! a child process under a time and memory limit (`run_isolated`), so they fail
//! instead of taking the machine down.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::export::{dot, text};
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, MonitorMode, RepairConfig, ViolationKind,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{
    coherence, ContactGraph, ContactLayer, EdgeId, Error, NodeId, NodeKind, PairKey, Rule,
    WorldMut, WorldView,
};
use rcg_scenes as scenes;

// ── Helpers ────────────────────────────────────────────────────────────────

const DT: f32 = 0.01;

/// A fixed ground and a ball resting on it (dt = 0.01, gravity -9.81).
fn ball_on_ground() -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle) {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = DT;
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    (world, ground, ball)
}

/// [`ball_on_ground`] stepped `n` times with a layer.
fn stepped(n: usize) -> (PhysicsWorld, RigidBodyHandle, RigidBodyHandle, ContactLayer) {
    let (mut world, ground, ball) = ball_on_ground();
    let mut layer = ContactLayer::new();
    for _ in 0..n {
        layer.step(&mut world);
    }
    (world, ground, ball, layer)
}

/// Runs `f`; a panic fails the test with what panicked and its message.
fn no_panic<R>(what: &str, f: impl FnOnce() -> R) -> R {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(e) => {
            let msg = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("{what} panicked: {msg}");
        }
    }
}

/// Handles no world the layer saw ever issued for this slot: the next generation of
/// the same slot, a slot far past the end, and Rapier's invalid handle.
fn foreign_bodies(h: RigidBodyHandle) -> [RigidBodyHandle; 3] {
    let (i, g) = h.into_raw_parts();
    [
        RigidBodyHandle::from_raw_parts(i, g + 1),
        RigidBodyHandle::from_raw_parts(1_000_000, 0),
        RigidBodyHandle::invalid(),
    ]
}

fn foreign_colliders(c: ColliderHandle) -> [ColliderHandle; 3] {
    let (i, g) = c.into_raw_parts();
    [
        ColliderHandle::from_raw_parts(i, g + 1),
        ColliderHandle::from_raw_parts(1_000_000, 0),
        ColliderHandle::invalid(),
    ]
}

/// Node ids this layer never issued: the next generation of a live slot and a slot
/// far past the end.
fn foreign_nodes(n: NodeId) -> [NodeId; 3] {
    [
        NodeId::from_raw_parts(n.index(), n.generation() + 1),
        NodeId::from_raw_parts(1_000_000, 0),
        NodeId::from_raw_parts(u32::MAX, u32::MAX),
    ]
}

/// A node id that was live and is stale now: a box inserted, analysed, removed and
/// analysed again.
fn stale_node(layer: &mut ContactLayer, world: &mut PhysicsWorld) -> (NodeId, RigidBodyHandle) {
    let (h, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    layer.step(world);
    let n = layer.node_of_body(h).unwrap();
    world.remove_body(h);
    layer.step(world);
    assert!(layer.graph().node(n).is_none(), "{n:?} is stale");
    (n, h)
}

/// Fingerprint of what a call must not change when it refuses its input.
fn fingerprint(layer: &ContactLayer) -> (usize, usize, usize, usize) {
    (
        layer.graph().node_count(),
        layer.graph().edge_count(),
        layer.flagged_colliders(),
        layer.event_bus().len(),
    )
}

const CHILD_ENV: &str = "RCG_AUDIT_CHILD";

/// Runs the `child_*` test `child` of this binary in its own process, under a 4 GiB
/// address-space limit, and waits at most `limit`. `Ok` if it passed in time.
fn run_isolated(child: &str, limit: Duration) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut proc = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 4194304 2>/dev/null; exec \"$@\"")
        .arg("sh")
        .arg(exe)
        .args(["--exact", child, "--ignored", "--test-threads=1", "-q"])
        .env(CHILD_ENV, "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    loop {
        if let Some(status) = proc.try_wait().map_err(|e| e.to_string())? {
            return if status.success() {
                Ok(())
            } else {
                Err(format!(
                    "{child} failed ({status}): ran out of memory or panicked"
                ))
            };
        }
        if start.elapsed() > limit {
            let _ = proc.kill();
            let _ = proc.wait();
            return Err(format!("{child} did not return within {limit:?}: it hangs"));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn is_child() -> bool {
    std::env::var_os(CHILD_ENV).is_some()
}

// ── ContactLayer: stepping ─────────────────────────────────────────────────

#[test]
fn step_with_non_finite_state_and_foreign_worlds() {
    // Non-finite state injected between steps: Rapier's quarantine disables and resets
    // the body (or collider); the layer keeps the node and stays valid.
    type Corrupt = fn(&mut PhysicsWorld, RigidBodyHandle);
    let corruptions: [(&str, Corrupt); 8] = [
        ("NaN position", |w, b| {
            w.bodies[b].set_translation(Vector::new(Real::NAN, 1.0, 0.0), true)
        }),
        ("infinite position", |w, b| {
            w.bodies[b].set_translation(Vector::splat(Real::INFINITY), true)
        }),
        ("NaN rotation", |w, b| {
            w.bodies[b].set_rotation(Rotation::from_xyzw(Real::NAN, 0.0, 0.0, 1.0), true)
        }),
        ("NaN linear velocity", |w, b| {
            w.bodies[b].set_linvel(Vector::new(0.0, Real::NAN, 0.0), true)
        }),
        ("infinite angular velocity", |w, b| {
            w.bodies[b].set_angvel(Vector::splat(Real::INFINITY), true)
        }),
        ("NaN mass", |w, b| {
            w.bodies[b].set_additional_mass(Real::NAN, true)
        }),
        ("NaN gravity", |w, _| w.gravity = Vector::splat(Real::NAN)),
        ("infinite gravity", |w, _| {
            w.gravity = Vector::new(0.0, -Real::INFINITY, 0.0)
        }),
    ];
    for (what, corrupt) in corruptions {
        for speedups in [None, Some(SpeedUps::combination(127))] {
            let (mut world, _, ball, mut layer) = stepped(5);
            layer.set_speedups(speedups.clone()).unwrap();
            let node = layer.node_of_body(ball).unwrap();
            corrupt(&mut world, ball);
            no_panic(what, || {
                for _ in 0..5 {
                    layer.step(&mut world);
                    layer.validate(&world).unwrap();
                }
            });
            assert!(layer.graph().node(node).is_some(), "{what}: node kept");
        }
    }
    // A non-finite static collider.
    let mut world = PhysicsWorld::new();
    let c = world.insert_collider(ColliderBuilder::cuboid(5.0, 0.5, 5.0), None);
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    world.colliders[c].set_translation(Vector::splat(Real::NAN));
    no_panic("NaN static collider", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });

    // dt = 0 and NaN: Rapier moves nothing and does not panic; neither does the layer.
    for dt in [0.0, Real::NAN] {
        let (mut world, _, _, mut layer) = stepped(5);
        world.integration_parameters.dt = dt;
        no_panic("step with dt 0 / NaN", || {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        });
    }

    // A foreign world: the layer alternates between two worlds. Bodies are matched by
    // handle (Rapier handles carry no world identity), and each step resynchronises.
    let (mut a, _, _, mut layer) = stepped(5);
    let mut b = PhysicsWorld::new();
    for i in 0..4 {
        b.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(2.0 * i as Real, 3.0, 0.0)),
            ColliderBuilder::cuboid(0.5, 0.5, 0.5),
        );
    }
    no_panic("alternating worlds", || {
        for i in 0..6 {
            let w = if i % 2 == 0 { &mut b } else { &mut a };
            layer.step(w);
            layer.validate(w).unwrap();
        }
    });
}

#[test]
// Fixed: a replaced slot evicts its old node at once; other such changes are found by
// the round-robin verification within `nodes / VERIFY_PER_STEP` steps (here, one).
fn bug_step_remove_and_insert_leaves_ghost_node() {
    // Fixed body removed, another body inserted: the counts do not change, so no full
    // scan runs, and the fixed body was never awake, so nothing refreshes it.
    let (mut world, ground, _, mut layer) = stepped(30);
    let g = layer.node_of_body(ground).unwrap();
    world.remove_body(ground);
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(20.0, 5.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    layer.step(&mut world);
    assert!(
        layer.removed_nodes().iter().any(|r| r.id == g),
        "the removed ground is reported removed"
    );
    assert!(layer.graph().node(g).is_none(), "its node is gone");
    layer.validate(&world).unwrap();

    // Sleeping body removed, another inserted: its touch span never ends.
    let (mut world, _, ball, mut layer) = stepped(400);
    assert!(world.bodies[ball].is_sleeping());
    let events = layer.subscribe(Filter::kinds(KindSet::TOUCH));
    world.remove_body(ball);
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(20.0, 5.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    layer.step(&mut world);
    assert!(
        events.try_iter().any(|e| e.kind == EventKind::TouchEnd),
        "removing a body ends its spans (events contract)"
    );
    layer.validate(&world).unwrap();

    // Static collider removed, another inserted: the new one never gets a node.
    let mut world = PhysicsWorld::new();
    let c = world.insert_collider(ColliderBuilder::cuboid(5.0, 0.5, 5.0), None);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    world.remove_collider(c);
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.1, 1.0).translation(Vector::new(20.0, 0.0, 0.0)),
        None,
    );
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_step_huge_dt_misses_pairs() {
    for dt in [100.0, Real::INFINITY] {
        let (mut world, _, _) = ball_on_ground();
        world.integration_parameters.dt = dt;
        let mut layer = ContactLayer::new();
        no_panic("huge dt", || layer.step(&mut world));
        world.integration_parameters.dt = DT;
        for _ in 0..3 {
            layer.step(&mut world);
        }
        assert_eq!(layer.validate(&world), Ok(()), "dt = {dt}");
    }
}

#[test]
#[ignore = "helper of bug_step_infinite_dt_with_timer_hangs (runs only in a child process)"]
fn child_infinite_dt_with_timer() {
    if !is_child() {
        return;
    }
    let (mut world, _, _, mut layer) = stepped(2);
    layer.add_timer(0.5).unwrap();
    world.integration_parameters.dt = Real::INFINITY;
    layer.step(&mut world);
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_step_infinite_dt_with_timer_hangs() {
    run_isolated("child_infinite_dt_with_timer", Duration::from_secs(10)).unwrap();
}

#[test]
fn pre_step_with_a_foreign_world_and_twice() {
    let (mut world, ground, ball, mut layer) = stepped(3);
    layer.set_passive(ball, true).unwrap();
    let (g, b) = (
        layer.node_of_body(ground).unwrap(),
        layer.node_of_body(ball).unwrap(),
    );
    layer.add_rule(Rule::ignore_pair(g, b)).unwrap();
    // Queued changes applied to a world that does not have the bodies: skipped.
    let mut other = PhysicsWorld::new();
    no_panic("pre_step on an empty world", || {
        layer.pre_step(WorldMut::from(&mut other))
    });
    // Twice on the real world, then the step: idempotent.
    no_panic("pre_step twice", || {
        layer.pre_step(WorldMut::from(&mut world));
        layer.pre_step(WorldMut::from(&mut world));
        world.step_with_events(&layer.hooks(), &());
        layer.analyze(WorldView::from(&world));
    });
    layer.validate(&world).unwrap();
}

#[test]
fn analyze_with_odd_views() {
    let (mut world, _, _, mut layer) = stepped(3);
    // Non-finite and negative view values (WorldView's fields are public).
    for (gravity, dt) in [
        (Vector::splat(Real::NAN), DT),
        (Vector::new(0.0, Real::INFINITY, 0.0), DT),
        (Vector::new(0.0, -9.81, 0.0), -DT),
        (Vector::new(0.0, -9.81, 0.0), 0.0),
    ] {
        let view = WorldView {
            gravity,
            dt,
            ..WorldView::from(&world)
        };
        no_panic("analyze with odd gravity / dt", || layer.analyze(view));
        layer.validate(&world).unwrap();
    }
    // A view mixing the parts of two worlds: nothing panics, validate says it is wrong
    // or right, but answers.
    let (other, _, _) = ball_on_ground();
    let mut big = PhysicsWorld::new();
    for i in 0..5 {
        big.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(i as Real, 0.0, 0.0)),
            ColliderBuilder::ball(0.6),
        );
    }
    big.step();
    let mixed = WorldView {
        narrow_phase: &big.narrow_phase,
        islands: &big.islands,
        ..WorldView::from(&other)
    };
    no_panic("analyze a mixed view", || {
        layer.analyze(mixed);
        let _ = layer.validate_view(&mixed);
    });
    // Wrong time: analysed twice for one Rapier step. Counted as two steps (the
    // contract is one call per step; the view cannot tell).
    let timer = layer.add_timer(1.0).unwrap();
    world.step();
    let before = (layer.current_step(), layer.simulated_time());
    layer.analyze(WorldView::from(&world));
    layer.analyze(WorldView::from(&world));
    assert_eq!(layer.current_step(), before.0 + 2);
    assert!((layer.simulated_time() - before.1 - 2.0 * DT as f64).abs() < 1e-9);
    assert_eq!(layer.timer_ticks(timer), Ok(0));
    layer.validate(&world).unwrap();
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_nan_dt_stops_timers_forever() {
    let (mut world, _, _, mut layer) = stepped(0);
    let timer = layer.add_timer(0.25).unwrap();
    world.integration_parameters.dt = Real::NAN;
    layer.step(&mut world); // Rapier: nothing moves, no panic.
    world.integration_parameters.dt = DT;
    for _ in 0..100 {
        layer.step(&mut world);
    }
    assert!(
        layer.simulated_time().is_finite(),
        "clock is {}",
        layer.simulated_time()
    );
    assert_eq!(
        layer.timer_ticks(timer),
        Ok(4),
        "1 s of steps, period 0.25 s"
    );
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_negative_dt_runs_timers_backwards() {
    let (mut world, _, _, mut layer) = stepped(0);
    let timer = layer.add_timer(0.1).unwrap();
    world.integration_parameters.dt = -0.05;
    for _ in 0..4 {
        layer.step(&mut world);
    }
    world.integration_parameters.dt = DT;
    for _ in 0..50 {
        layer.step(&mut world);
    }
    assert!(
        layer.simulated_time() >= 0.5 - 1e-9,
        "clock {}",
        layer.simulated_time()
    );
    assert_eq!(layer.timer_ticks(timer), Ok(5));
}

// ── ContactLayer: wrong time ───────────────────────────────────────────────

/// A Rapier event handler holding the layer: user code that runs *during* a
/// user-driven Rapier step and queries the layer from there.
struct Spy<'a> {
    layer: &'a ContactLayer,
    ball: RigidBodyHandle,
    ground: RigidBodyHandle,
    seen: Mutex<Vec<(u64, bool, bool)>>,
}

impl EventHandler for Spy<'_> {
    fn handle_collision_event(
        &self,
        _: &RigidBodySet,
        _: &ColliderSet,
        _: CollisionEvent,
        _: Option<&ContactPair>,
    ) {
        let l = self.layer;
        let node = l.node_of_body(self.ball);
        let touching = l
            .graph()
            .edge_of_bodies(self.ball, self.ground)
            .is_some_and(|e| e.is_touching());
        let ok = node.is_ok() && l.graph().validate().is_ok();
        self.seen
            .lock()
            .unwrap()
            .push((l.current_step(), ok, touching));
    }
    fn handle_contact_force_event(
        &self,
        _: Real,
        _: &RigidBodySet,
        _: &ColliderSet,
        _: &ContactPair,
        _: Real,
    ) {
    }
    fn handle_soft_body_tear_event(&self, _: &SoftBodySet, _: &SoftBodyTearEvent) {}
}

#[test]
fn wrong_time_queries_during_a_rapier_step_see_the_last_analysis() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = DT;
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.5, 0.0)),
        ColliderBuilder::ball(0.5).active_events(ActiveEvents::COLLISION_EVENTS),
    );
    let mut layer = ContactLayer::new();
    let mut seen = Vec::new();
    for _ in 0..100 {
        layer.pre_step(WorldMut::from(&mut world));
        let spy = Spy {
            layer: &layer,
            ball,
            ground,
            seen: Mutex::new(Vec::new()),
        };
        // The layer is borrowed shared by the hooks *and* the handler for the whole
        // Rapier step: no `&mut` call can overlap it (see the compile_fail example in
        // the audit module).
        no_panic("queries from an event handler", || {
            world.step_with_events(&layer.hooks(), &spy)
        });
        seen.extend(spy.seen.into_inner().unwrap());
        layer.analyze(WorldView::from(&world));
    }
    // The ball landed once: the handler saw the state of the step before (not yet
    // touching), consistent, and no panic.
    assert!(!seen.is_empty(), "the ball landed");
    let (step, ok, touching) = seen[0];
    assert!(ok && !touching, "{seen:?}");
    assert!(step > 0);
}

#[test]
fn wrong_time_a_rule_predicate_runs_inside_the_step_and_sees_only_earlier_events() {
    let (mut world, _, ball, mut layer) = stepped(1);
    let events = layer.subscribe(Filter::all());
    let now = Arc::new(AtomicU64::new(0));
    let latest_seen = Arc::new(AtomicU64::new(0));
    let calls = Arc::new(AtomicU64::new(0));
    let (now2, latest2, calls2) = (now.clone(), latest_seen.clone(), calls.clone());
    let b = layer.node_of_body(ball).unwrap();
    let g = layer
        .graph()
        .nodes_of_kind(NodeKind::Fixed)
        .next()
        .unwrap()
        .0;
    // The predicate is `'static + Send + Sync` and gets node ids only: it cannot borrow
    // the layer. It can hold a receiver; it sees the events of finished steps only.
    layer
        .add_rule(Rule::ignore_if(&[b, g], move |_, _| {
            calls2.fetch_add(1, Ordering::Relaxed);
            for e in events.try_iter() {
                latest2.fetch_max(e.step, Ordering::Relaxed);
            }
            assert!(
                latest2.load(Ordering::Relaxed) < now2.load(Ordering::Relaxed),
                "seen {} now {}",
                latest2.load(Ordering::Relaxed),
                now2.load(Ordering::Relaxed)
            );
            false
        }))
        .unwrap();
    for _ in 0..20 {
        now.store(layer.current_step() + 1, Ordering::Relaxed);
        no_panic("predicate during the step", || layer.step(&mut world));
    }
    // Between steps (validate() asks the predicate too) every event is out.
    now.store(u64::MAX, Ordering::Relaxed);
    assert!(calls.load(Ordering::Relaxed) > 0, "the predicate ran");
    assert!(
        latest_seen.load(Ordering::Relaxed) > 0,
        "it saw earlier events"
    );
    layer.validate(&world).unwrap();
}

#[test]
fn wrong_time_changes_between_pre_step_and_rapier_step_wait_for_the_next_pre_step() {
    let (mut world, ground, ball, mut layer) = stepped(20);
    let (g, b) = (
        layer.node_of_body(ground).unwrap(),
        layer.node_of_body(ball).unwrap(),
    );
    layer.pre_step(WorldMut::from(&mut world));
    // Too late for this step: the hooks were prepared already.
    layer.add_rule(Rule::ignore_pair(g, b)).unwrap();
    world.step_with_events(&layer.hooks(), &());
    layer.analyze(WorldView::from(&world));
    layer.validate(&world).unwrap();
    for _ in 0..60 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    assert!(
        world.bodies[ball].translation().y < 0.0,
        "applied from the next step"
    );
}

#[test]
fn wrong_time_calls_before_the_first_step() {
    let (world, ground, ball) = ball_on_ground();
    let mut layer = ContactLayer::new();
    // The layer has not seen the world yet: bodies are unknown, not an absent value.
    assert_eq!(layer.node_of_body(ball), Err(Error::UnknownBody(ball)));
    assert_eq!(layer.set_passive(ball, true), Err(Error::UnknownBody(ball)));
    assert!(Error::UnknownBody(ball)
        .to_string()
        .contains("not seen by the layer yet"));
    assert!(matches!(layer.validate(&world), Err(Error::Invariant(_))));
    assert!(layer.graph().edge_of_bodies(ground, ball).is_none());
    let t = layer.add_timer(1.0).unwrap();
    assert_eq!(layer.timer_ticks(t), Ok(0));
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let found = no_panic("monitor before the first step", || {
        monitor
            .check(&layer, &WorldView::from(&world), &|_| true, &|_| false)
            .len()
    });
    assert_eq!(found, 0);
}

// ── ContactLayer: configuration ────────────────────────────────────────────

#[test]
fn set_speedups_refuses_bad_parameters() {
    let (mut world, _, _, mut layer) = stepped(3);
    let base = SpeedUps::combination(127);
    let bad = [
        SpeedUps {
            sleepy_energy: Real::NAN,
            ..base.clone()
        },
        SpeedUps {
            sleepy_energy: -1.0,
            ..base.clone()
        },
        SpeedUps {
            reduce_depth: Real::INFINITY,
            ..base.clone()
        },
        SpeedUps {
            damping: -0.5,
            ..base.clone()
        },
        SpeedUps {
            release_speed: Real::NAN,
            ..base.clone()
        },
        SpeedUps {
            sleepy_steps: 0,
            ..base.clone()
        },
        SpeedUps {
            iterations: 0,
            ..base.clone()
        },
        SpeedUps {
            tweak_iterations: 0,
            ..base.clone()
        },
    ];
    for config in bad {
        let before = fingerprint(&layer);
        assert!(matches!(
            layer.set_speedups(Some(config.clone())),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(layer.speedups().is_none(), "nothing switched on");
        assert_eq!(fingerprint(&layer), before);
    }
    // Zero thresholds and huge finite ones are in range and change nothing fatal.
    let edge = SpeedUps {
        sleepy_energy: 0.0,
        reduce_depth: Real::MAX,
        damping: Real::MAX,
        release_speed: 0.0,
        sleepy_steps: u32::MAX,
        ..base.clone()
    };
    layer.set_speedups(Some(edge)).unwrap();
    // A bad configuration while on keeps the one in force.
    assert!(layer
        .set_speedups(Some(SpeedUps {
            damping: Real::NAN,
            ..base
        }))
        .is_err());
    assert_eq!(layer.speedups().unwrap().config().damping, Real::MAX);
    no_panic("extreme speed-ups", || {
        for _ in 0..20 {
            layer.step(&mut world);
        }
    });
    layer.validate(&world).unwrap();
    // Off twice: no-op.
    layer.set_speedups(None).unwrap();
    layer.set_speedups(None).unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn settings_at_any_time() {
    let (mut world, _, ball, mut layer) = stepped(30);
    for policy in [
        coherence::ScanPolicy::Scan,
        coherence::ScanPolicy::Walk,
        coherence::ScanPolicy::Auto,
    ] {
        layer.coherence_mut().set_scan_policy(policy);
        layer.set_contact_details(false);
        layer.request_full_sync();
        layer.request_full_sync();
        layer.set_trigger_widening(false);
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        layer.set_contact_details(true);
        layer.set_trigger_widening(true);
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    // Contact details off from the start: support has no normals to go by and says
    // "not supported" (documented on set_contact_details; no error).
    let (mut world, _, _) = ball_on_ground();
    let mut layer = ContactLayer::new();
    layer.set_contact_details(false);
    for _ in 0..30 {
        layer.step(&mut world);
    }
    let n = layer.node_of_body(ball).unwrap();
    assert_eq!(layer.graph().touching(n).count(), 1);
    assert_eq!(layer.is_supported(n), Ok(false));
}

// ── ContactLayer: events ───────────────────────────────────────────────────

#[test]
fn subscribe_with_stale_or_foreign_nodes_matches_nothing() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let [next_gen, far, _] = foreign_nodes(layer.node_of_body(ball).unwrap());
    // Accepted (subscribe cannot fail); such a filter never matches, as the node can
    // never come back (ids are generational).
    let rx = layer.subscribe(Filter::all().with_nodes(&[stale, next_gen, far]));
    let (_, rx2) = layer.subscribe_with_id(Filter::kinds(KindSet::NONE));
    let rx3 = layer.subscribe(Filter::all().with_nodes(&[]));
    let all = layer.subscribe(Filter::all());
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    for _ in 0..100 {
        layer.step(&mut world);
    }
    assert!(all.try_iter().count() > 0, "events happened");
    assert_eq!(rx.try_iter().count(), 0);
    assert_eq!(rx2.try_iter().count(), 0);
    assert_eq!(rx3.try_iter().count(), 0);
    let _ = ground;
}

#[test]
fn subscribe_bounded_zero_capacity_is_an_error() {
    let mut layer = ContactLayer::new();
    assert!(matches!(
        layer.subscribe_bounded(Filter::all(), 0),
        Err(Error::InvalidParameter {
            name: "capacity",
            ..
        })
    ));
    assert_eq!(layer.event_bus().len(), 0, "nothing subscribed");
    let rx = layer.subscribe_bounded(Filter::all(), 1).unwrap();
    let (mut world, _, _) = ball_on_ground();
    for _ in 0..50 {
        layer.step(&mut world);
    }
    assert_eq!(rx.try_iter().count(), 1, "the newest are dropped");
    assert!(layer.event_bus().dropped() > 0);
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_subscribe_bounded_huge_capacity_panics() {
    let mut layer = ContactLayer::new();
    let r = no_panic("subscribe_bounded(usize::MAX)", || {
        layer
            .subscribe_bounded(Filter::all(), usize::MAX)
            .map(|_| ())
    });
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_subscribe_bounded_accepts_stale_node_filter() {
    let (mut world, _, _, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    assert_eq!(
        layer
            .subscribe_bounded(Filter::all().with_nodes(&[stale]), 8)
            .map(|_| ()),
        Err(Error::StaleNode(stale))
    );
}

#[test]
fn unsubscribe_and_dropped_receivers() {
    let (mut world, _, _) = ball_on_ground();
    let mut layer = ContactLayer::new();
    let (id, rx) = layer.subscribe_with_id(Filter::all());
    let (id2, _keep) = layer.subscribe_with_id(Filter::all());
    // Dropped receiver: pruned at the next delivery, never an error or a block.
    drop(rx);
    no_panic("dispatch to a dropped receiver", || {
        for _ in 0..5 {
            layer.step(&mut world);
        }
    });
    assert_eq!(layer.event_bus().pruned(), 1);
    assert_eq!(layer.event_bus().dropped_for(id), None, "gone");
    assert!(!layer.unsubscribe(id), "already pruned");
    assert!(layer.unsubscribe(id2));
    assert!(!layer.unsubscribe(id2), "twice");
    assert_eq!(layer.event_bus().dropped_for(id2), None);
    // A foreign id (another layer's) names this layer's subscription with the same
    // number: ids carry no layer identity (aliasing, undetectable).
    let mut other = ContactLayer::new();
    let (foreign, _) = other.subscribe_with_id(Filter::all());
    let (_, _rx3) = layer.subscribe_with_id(Filter::all());
    let _ = layer.unsubscribe(foreign);
}

// ── ContactLayer: rules, timers, passive bodies, composites ────────────────

#[test]
fn add_rule_refuses_unknown_nodes() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let (g, b) = (
        layer.node_of_body(ground).unwrap(),
        layer.node_of_body(ball).unwrap(),
    );
    let timer = layer.add_timer(1.0).unwrap();
    let before = fingerprint(&layer);
    type Want = fn(&Error) -> bool;
    let cases: Vec<(Rule, Want)> = vec![
        (Rule::ignore_pair(b, stale), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_between(&[g], &[foreign_nodes(b)[0]]), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_if(&[foreign_nodes(b)[2]], |_, _| true), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_pair(b, timer), |e| {
            matches!(e, Error::WrongKind { .. })
        }),
        (Rule::ignore_between(&[], &[]), |e| {
            matches!(e, Error::InvalidParameter { .. })
        }),
        (Rule::ignore_if(&[], |_, _| true), |e| {
            matches!(e, Error::InvalidParameter { .. })
        }),
    ];
    for (rule, want) in cases {
        let r = layer.add_rule(rule.clone());
        assert!(r.as_ref().is_err_and(want), "{rule:?}: {r:?}");
        assert_eq!(fingerprint(&layer), before, "{rule:?} changed nothing");
    }
    // A pair of one node, and repeats: accepted (members are deduplicated).
    let r = layer.add_rule(Rule::ignore_between(&[b, b], &[b])).unwrap();
    assert_eq!(layer.rule(r).unwrap().members(), vec![b]);
    // A member removed from the world later: the rule stays and can be removed.
    let r2 = layer.add_rule(Rule::ignore_pair(g, b)).unwrap();
    world.remove_body(ball);
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    layer.remove_rule(r2).unwrap();
    layer.remove_rule(r).unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn remove_rule_and_rule_with_stale_ids() {
    let (mut world, ground, ball, mut layer) = stepped(2);
    let (g, b) = (
        layer.node_of_body(ground).unwrap(),
        layer.node_of_body(ball).unwrap(),
    );
    let r = layer.add_rule(Rule::ignore_pair(g, b)).unwrap();
    layer.step(&mut world);
    layer.remove_rule(r).unwrap();
    assert_eq!(
        layer.remove_rule(r).map(|_| ()),
        Err(Error::StaleNode(r)),
        "twice"
    );
    assert!(layer.rule(r).is_none());
    for f in foreign_nodes(b) {
        assert_eq!(layer.remove_rule(f).map(|_| ()), Err(Error::StaleNode(f)));
        assert!(layer.rule(f).is_none());
    }
    assert!(matches!(layer.remove_rule(b), Err(Error::WrongKind { .. })));
    assert!(layer.rule(b).is_none(), "not a rule");
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn add_timer_refuses_bad_periods() {
    let mut layer = ContactLayer::new();
    for p in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(
            matches!(
                layer.add_timer(p),
                Err(Error::InvalidParameter { name: "period", .. })
            ),
            "{p}"
        );
    }
    assert_eq!(layer.graph().node_count(), 0, "nothing added");
    // Huge finite periods are in range: they never tick.
    let (mut world, _, _) = ball_on_ground();
    let t = layer.add_timer(f64::MAX).unwrap();
    for _ in 0..10 {
        layer.step(&mut world);
    }
    assert_eq!(layer.timer_ticks(t), Ok(0));
}

#[test]
#[ignore = "helper of bug_tiny_timer_period_hangs_next_step (runs only in a child process)"]
fn child_tiny_timer_period() {
    if !is_child() {
        return;
    }
    let (mut world, _, _, mut layer) = stepped(2);
    // Refused now; the shortest accepted period fires a bounded number of ticks.
    assert!(layer.add_timer(1e-300).is_err());
    layer
        .add_timer(rapier_contact_graph::logic::MIN_TIMER_PERIOD)
        .unwrap();
    layer.step(&mut world);
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_tiny_timer_period_hangs_next_step() {
    run_isolated("child_tiny_timer_period", Duration::from_secs(10)).unwrap();
}

#[test]
fn timer_queries_with_stale_and_wrong_ids() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let b = layer.node_of_body(ball).unwrap();
    let t = layer.add_timer(0.5).unwrap();
    assert_eq!(layer.timer_period(t), Ok(0.5));
    layer.remove_timer(t).unwrap();
    assert_eq!(layer.remove_timer(t), Err(Error::StaleNode(t)), "twice");
    assert_eq!(layer.timer_ticks(t), Err(Error::StaleNode(t)));
    assert_eq!(layer.timer_period(t), Err(Error::StaleNode(t)));
    for f in foreign_nodes(b) {
        assert_eq!(layer.remove_timer(f), Err(Error::StaleNode(f)));
        assert_eq!(layer.timer_ticks(f), Err(Error::StaleNode(f)));
        assert_eq!(layer.timer_period(f), Err(Error::StaleNode(f)));
    }
    assert!(matches!(
        layer.remove_timer(b),
        Err(Error::WrongKind { .. })
    ));
    assert!(matches!(layer.timer_ticks(b), Err(Error::WrongKind { .. })));
    assert!(matches!(
        layer.timer_period(b),
        Err(Error::WrongKind { .. })
    ));
    assert!(layer.graph().node(b).is_some(), "the body is untouched");
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn set_passive_with_stale_foreign_and_removed_bodies() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (_, removed) = stale_node(&mut layer, &mut world);
    assert_eq!(
        layer.set_passive(removed, true),
        Err(Error::UnknownBody(removed))
    );
    for f in foreign_bodies(ball) {
        assert_eq!(layer.set_passive(f, true), Err(Error::UnknownBody(f)));
    }
    // Removed from the world but not analysed yet (wrong time): the layer cannot know;
    // accepted and a no-op, the node goes at the next analysis.
    layer.set_passive(ball, true).unwrap();
    layer.set_passive(ball, false).unwrap();
    world.remove_body(ball);
    layer.set_passive(ball, true).unwrap();
    no_panic("passive on a removed body", || layer.step(&mut world));
    assert_eq!(
        layer.set_passive(ball, false),
        Err(Error::UnknownBody(ball))
    );
    layer.validate(&world).unwrap();
}

#[test]
fn composites_with_stale_wrong_and_removed_members() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (extra, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    layer.step(&mut world);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let (g, b, x) = (
        layer.node_of_body(ground).unwrap(),
        layer.node_of_body(ball).unwrap(),
        layer.node_of_body(extra).unwrap(),
    );
    let t = layer.add_timer(1.0).unwrap();
    let before = fingerprint(&layer);
    assert!(matches!(
        layer.declare_composite(&[]),
        Err(Error::InvalidParameter { .. })
    ));
    assert_eq!(
        layer.declare_composite(&[b, stale]),
        Err(Error::StaleNode(stale))
    );
    let f = foreign_nodes(b)[0];
    assert_eq!(layer.declare_composite(&[f]), Err(Error::StaleNode(f)));
    assert!(matches!(
        layer.declare_composite(&[b, g]),
        Err(Error::WrongKind { .. })
    ));
    assert!(matches!(
        layer.declare_composite(&[t]),
        Err(Error::WrongKind { .. })
    ));
    assert_eq!(fingerprint(&layer), before, "nothing added");
    // Repeats: one structural edge per member.
    let c = layer.declare_composite(&[b, b, x]).unwrap();
    assert_eq!(layer.graph().node(c).unwrap().degree(), 2);
    // remove_composite with wrong ids.
    assert_eq!(layer.remove_composite(stale), Err(Error::StaleNode(stale)));
    assert!(matches!(
        layer.remove_composite(b),
        Err(Error::WrongKind { .. })
    ));
    assert!(matches!(
        layer.remove_composite(t),
        Err(Error::WrongKind { .. })
    ));
    // A member removed from the world: the composite stays, removable, valid.
    world.remove_body(extra);
    for _ in 0..3 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    layer.remove_composite(c).unwrap();
    assert_eq!(layer.remove_composite(c), Err(Error::StaleNode(c)), "twice");
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

// ── ContactLayer: queries ──────────────────────────────────────────────────

#[test]
fn layer_node_queries_with_bad_ids() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (stale, removed) = stale_node(&mut layer, &mut world);
    assert_eq!(
        layer.node_of_body(removed),
        Err(Error::UnknownBody(removed))
    );
    for f in foreign_bodies(ball) {
        assert_eq!(layer.node_of_body(f), Err(Error::UnknownBody(f)));
    }
    let b = layer.node_of_body(ball).unwrap();
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert_eq!(layer.kind_of(n), Err(Error::StaleNode(n)));
        assert_eq!(layer.is_supported(n), Err(Error::StaleNode(n)));
        assert!(!layer.insulates(n));
    }
    assert_eq!(layer.kind_of(b), Ok(NodeKind::Rigid));
    // Non-finite gravity of the last analysed world: an error, not an answer.
    world.gravity = Vector::splat(Real::NAN);
    layer.step(&mut world);
    assert_eq!(layer.is_supported(b), Err(Error::NonFinite("gravity")));
}

#[test]
fn node_of_collider_with_bad_handles() {
    let (mut world, _, _, mut layer) = stepped(2);
    let c = world.colliders.iter().next().unwrap().0;
    for f in foreign_colliders(c) {
        assert_eq!(
            layer.node_of_collider(&world, f),
            Err(Error::UnknownCollider(f))
        );
    }
    // Removed collider.
    let (h, hc) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    layer.step(&mut world);
    assert!(layer.node_of_collider(&world, hc).is_ok());
    world.remove_body(h);
    layer.step(&mut world);
    assert_eq!(
        layer.node_of_collider(&world, hc),
        Err(Error::UnknownCollider(hc))
    );
    // A world the layer never saw: answered from that world's parent handle, which is
    // unknown here (or aliases a body of the same slot: handles carry no world).
    let mut other = PhysicsWorld::new();
    for _ in 0..5 {
        other.insert_body(RigidBodyBuilder::dynamic());
    }
    let (_, oc) = other.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(1.0));
    assert!(matches!(
        layer.node_of_collider(&other, oc),
        Err(Error::UnknownBody(_))
    ));
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_node_of_collider_parentless_sensor() {
    let (mut world, _, _) = ball_on_ground();
    let s = world.insert_collider(
        ColliderBuilder::ball(1.0)
            .sensor(true)
            .translation(Vector::new(0.0, 3.0, 0.0)),
        None,
    );
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let trigger = layer.graph().node_of_sensor(s).unwrap();
    assert_eq!(layer.node_of_collider(&world, s), Ok(trigger));
}

#[test]
fn validate_against_a_foreign_world_is_an_error() {
    let (_, _, _, layer) = stepped(5);
    let empty = PhysicsWorld::new();
    let mut other = PhysicsWorld::new();
    for i in 0..4 {
        other.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(i as Real, 0.0, 0.0)),
            ColliderBuilder::ball(0.6),
        );
    }
    other.step();
    for w in [&empty, &other] {
        let r = no_panic("validate(foreign world)", || layer.validate(w));
        assert!(matches!(r, Err(Error::Invariant(_))), "{r:?}");
        let view = WorldView {
            gravity: Vector::splat(Real::NAN),
            dt: Real::NAN,
            ..WorldView::from(w)
        };
        assert!(no_panic("validate_view", || layer.validate_view(&view)).is_err());
    }
}

#[test]
fn accessors_on_a_fresh_layer_and_error_messages() {
    let layer = ContactLayer::default();
    assert_eq!(layer.graph().node_count(), 0);
    assert!(layer.groups().is_empty());
    assert_eq!(layer.stats().step, 0);
    assert_eq!(layer.current_step(), 0);
    assert_eq!(layer.touched_edges().count(), 0);
    assert!(layer.removed_edges().is_empty() && layer.removed_nodes().is_empty());
    assert!(layer.last_events().is_empty());
    assert_eq!(layer.event_bus().len(), 0);
    assert_eq!(layer.flagged_colliders(), 0);
    assert_eq!(layer.simulated_time(), 0.0);
    assert!(layer.speedups().is_none() && layer.grouping());
    assert!(layer.hooks().table().is_empty());
    assert!(layer.coherence().contact_details());
    assert!(layer.refusals().is_empty());
    // Every error names what is wrong.
    let n = NodeId::from_raw_parts(3, 1);
    let e = EdgeId::from_raw_parts(4, 2);
    let h = RigidBodyHandle::from_raw_parts(5, 0);
    let c = ColliderHandle::from_raw_parts(6, 0);
    for (err, needle) in [
        (Error::StaleNode(n), "n3v1"),
        (Error::StaleEdge(e), "e4v2"),
        (Error::UnknownBody(h), "removed"),
        (Error::UnknownCollider(c), "collider"),
        (
            Error::WrongKind {
                node: n,
                expected: "a timer",
            },
            "a timer",
        ),
        (Error::NonFinite("gravity"), "gravity is not finite"),
        (
            Error::InvalidParameter {
                name: "period",
                reason: "must be positive".into(),
            },
            "period",
        ),
        (Error::Invariant("x".into()), "invariant"),
        (
            Error::Unsupported {
                what: "set_passive(true) on a multibody link",
                reason: "Rapier panics",
            },
            "multibody link is not supported: Rapier panics",
        ),
    ] {
        assert!(err.to_string().contains(needle), "{err}");
    }
}

// ── ContactGraph ───────────────────────────────────────────────────────────

#[test]
fn graph_node_lookups_with_bad_ids() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert!(g.node(n).is_none());
        assert_eq!(g.try_node(n).map(|_| ()), Err(Error::StaleNode(n)));
        assert!(!g.contains_node(n));
    }
    assert!(g.node_id_at(u32::MAX).is_none());
    assert!(g.node_id_at(stale.index()).is_none_or(|n| n != stale));
    assert!(ContactGraph::new().node_id_at(0).is_none());
}

#[test]
fn graph_body_lookups_with_bad_handles() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (_, removed) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    for h in [removed].into_iter().chain(foreign_bodies(ball)) {
        assert!(g.node_of_body(h).is_none());
        assert_eq!(g.try_node_of_body(h), Err(Error::UnknownBody(h)));
    }
    // The same slot and generation in another world names this world's body: Rapier
    // handles carry no world identity (aliasing, undetectable).
    let mut other = PhysicsWorld::new();
    other.insert_body(RigidBodyBuilder::fixed());
    let alias = other.insert_body(RigidBodyBuilder::dynamic());
    assert_eq!(alias, ball);
    assert!(g.node_of_body(alias).is_some());
}

#[test]
fn graph_collider_lookups_with_bad_handles() {
    let mut world = PhysicsWorld::new();
    let floor = world.insert_collider(ColliderBuilder::cuboid(5.0, 0.5, 5.0), None);
    let sensor = world.insert_collider(ColliderBuilder::ball(1.0).sensor(true), None);
    let (_, attached) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let g = layer.graph();
    assert!(g.node_of_static_collider(floor).is_some());
    assert!(g.node_of_sensor(sensor).is_some());
    // Wrong kind of collider: none, not someone else's node.
    assert!(g.node_of_static_collider(sensor).is_none());
    assert!(g.node_of_sensor(floor).is_none());
    assert!(g.node_of_static_collider(attached).is_none());
    assert!(g.node_of_sensor(attached).is_none());
    for f in foreign_colliders(floor)
        .into_iter()
        .chain(foreign_colliders(sensor))
    {
        assert!(g.node_of_static_collider(f).is_none());
        assert!(g.node_of_sensor(f).is_none());
    }
    // Removed.
    world.remove_collider(floor);
    world.remove_collider(sensor);
    layer.step(&mut world);
    assert!(layer.graph().node_of_static_collider(floor).is_none());
    assert!(layer.graph().node_of_sensor(sensor).is_none());
}

#[test]
fn graph_body_of_with_bad_ids() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let t = layer.add_timer(1.0).unwrap();
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert!(g.body_of(n).is_none());
        assert_eq!(g.try_body_of(n), Err(Error::StaleNode(n)));
    }
    assert!(g.body_of(t).is_none());
    assert!(matches!(g.try_body_of(t), Err(Error::WrongKind { .. })));
    assert_eq!(g.try_body_of(b), Ok(ball));
}

#[test]
fn graph_edge_lookups_with_bad_ids() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (h, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    for _ in 0..5 {
        layer.step(&mut world);
    }
    let e = layer
        .graph()
        .edge_between(
            layer.node_of_body(ground).unwrap(),
            layer.node_of_body(h).unwrap(),
        )
        .unwrap();
    world.remove_body(h);
    layer.step(&mut world);
    let g = layer.graph();
    let live = g.edges().next().unwrap().0;
    for id in [
        e,
        EdgeId::from_raw_parts(live.index(), live.generation() + 1),
        EdgeId::from_raw_parts(u32::MAX, 0),
    ] {
        assert!(g.edge(id).is_none());
        assert_eq!(g.try_edge(id).map(|_| ()), Err(Error::StaleEdge(id)));
    }
    assert!(g.edge_by_key(PairKey::new(u32::MAX, 0)).is_none());
    assert!(g.edge_by_key(PairKey::new(7, 7)).is_none());
    // Edge accessors with foreign nodes and any step.
    let edge = g.edge(live).unwrap();
    let b = g.node_of_body(ball).unwrap();
    for f in foreign_nodes(b) {
        assert!(edge.other(f).is_none());
    }
    assert!(edge.proximity_mark(u64::MAX).is_none() && edge.touching_mark(0).is_none());
}

#[test]
fn graph_edge_between_with_bad_ids() {
    let (mut world, ground, ball, mut layer) = stepped(2);
    let (stale, removed) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let (gn, bn) = (
        g.node_of_body(ground).unwrap(),
        g.node_of_body(ball).unwrap(),
    );
    assert!(g.edge_between(gn, bn).is_some());
    for n in [stale].into_iter().chain(foreign_nodes(bn)) {
        assert!(g.edge_between(gn, n).is_none() && g.edge_between(n, gn).is_none());
        assert_eq!(g.try_edge_between(gn, n), Err(Error::StaleNode(n)));
        assert_eq!(g.try_edge_between(n, gn), Err(Error::StaleNode(n)));
    }
    // A stale id whose slot a live node reuses does not name the live node's edges.
    let (reuse, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 2.0)),
        ColliderBuilder::ball(0.5),
    );
    layer.step(&mut world);
    let g = layer.graph();
    assert_eq!(g.node_of_body(reuse).unwrap().index(), stale.index());
    assert!(g.edge_between(gn, stale).is_none());
    // Same node twice: no edge, not an error.
    assert!(g.edge_between(bn, bn).is_none());
    assert_eq!(g.try_edge_between(bn, bn), Ok(None));
    for f in [removed].into_iter().chain(foreign_bodies(ball)) {
        assert!(g.edge_of_bodies(ground, f).is_none() && g.edge_of_bodies(f, f).is_none());
    }
    assert!(g.edge_of_bodies(ball, ball).is_none());
}

#[test]
fn graph_neighbors_and_touching_with_bad_ids() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert_eq!(g.neighbors(n).count(), 0);
        assert_eq!(g.touching(n).count(), 0);
    }
}

#[test]
fn graph_try_is_supported_with_bad_input() {
    let (mut world, _, ball, mut layer) = stepped(30);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    let down = Vector::new(0.0, -9.81, 0.0);
    assert_eq!(g.try_is_supported(b, down, 0.0), Ok(true));
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert_eq!(g.try_is_supported(n, down, 0.0), Err(Error::StaleNode(n)));
    }
    // Zero gravity supports nothing (documented).
    assert_eq!(g.try_is_supported(b, Vector::ZERO, 0.0), Ok(false));
    // min_cos outside [-1, 1] is not checked: above 1 nothing, below -1 anything.
    assert_eq!(g.try_is_supported(b, down, 2.0), Ok(false));
    assert_eq!(g.try_is_supported(b, -down, -2.0), Ok(true));
    // Non-finite gravity and a NaN min_cos are errors.
    for (gravity, min_cos) in [
        (Vector::splat(Real::NAN), 0.0),
        (Vector::new(0.0, -Real::INFINITY, 0.0), 0.0),
        (down, Real::NAN),
    ] {
        assert!(matches!(
            g.try_is_supported(b, gravity, min_cos),
            Err(Error::NonFinite(_))
        ));
    }
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_try_is_supported_non_finite_input_is_not_an_error() {
    let (_, _, ball, layer) = stepped(30);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    let down = Vector::new(0.0, -9.81, 0.0);
    for (gravity, min_cos) in [
        (Vector::splat(Real::NAN), 0.0),
        (Vector::new(0.0, -Real::INFINITY, 0.0), 0.0),
        (down, Real::NAN),
    ] {
        let r = g.try_is_supported(b, gravity, min_cos);
        assert!(
            matches!(r, Err(Error::NonFinite(_))),
            "{gravity:?} {min_cos}: {r:?}"
        );
    }
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_try_is_supported_huge_or_tiny_gravity() {
    let (_, _, ball, layer) = stepped(30);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    for y in [-1e20, -1e-23] {
        assert_eq!(
            g.try_is_supported(b, Vector::new(0.0, y, 0.0), 0.0),
            Ok(true),
            "gravity (0, {y}, 0)"
        );
    }
}

#[test]
fn graph_supports_of_with_bad_input() {
    let (mut world, _, ball, mut layer) = stepped(30);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let b = g.node_of_body(ball).unwrap();
    assert_eq!(g.supports_of(b, Vector::Y, 0.0).count(), 1);
    assert_eq!(g.supports_of(stale, Vector::Y, 0.0).count(), 0);
    for f in foreign_nodes(b) {
        assert_eq!(g.supports_of(f, Vector::Y, 0.0).count(), 0);
    }
    // No error channel (an iterator): NaN `up` or `min_cos` give nothing.
    assert_eq!(g.supports_of(b, Vector::splat(Real::NAN), 0.0).count(), 0);
    assert_eq!(g.supports_of(b, Vector::Y, Real::NAN).count(), 0);
    assert_eq!(g.supports_of(b, Vector::ZERO, 0.0).count(), 0);
}

#[test]
fn graph_whole_graph_calls_on_empty_and_used_graphs() {
    let empty = ContactGraph::new();
    assert_eq!(empty.to_petgraph().node_count(), 0);
    empty.validate().unwrap();
    assert_eq!(empty.nodes().count() + empty.edges().count(), 0);
    assert_eq!(empty.count_of_kind(NodeKind::Timer), 0);
    let (mut world, _, _, mut layer) = stepped(5);
    stale_node(&mut layer, &mut world);
    let g = layer.graph();
    let pg = g.to_petgraph();
    assert_eq!(pg.node_count(), g.node_count());
    assert_eq!(pg.edge_count(), g.edge_count());
    g.validate().unwrap();
    assert_eq!(g.nodes_of_kind(NodeKind::Rigid).count(), 1);
    // The obsolete test on non-finite boxes: never obsolete.
    use rapier3d::parry::bounding_volume::Aabb;
    let nan = Aabb::new(Vector::splat(Real::NAN), Vector::splat(Real::NAN));
    let unit = Aabb::new(Vector::ZERO, Vector::ONE);
    assert!(!coherence::aabbs_obsolete(&nan, &unit) && !coherence::aabbs_obsolete(&unit, &nan));
}

// ── Groups, events, rules ──────────────────────────────────────────────────

#[test]
fn groups_get_with_stale_group_id() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let b = layer.node_of_body(ball).unwrap();
    let gid = layer.graph().node(b).unwrap().group().unwrap();
    assert!(layer.groups().get(gid).is_some());
    world.remove_body(ball);
    layer.step(&mut world);
    assert!(layer.groups().get(gid).is_none(), "dissolved with its body");
    assert!(layer.groups().iter().all(|(id, _)| id != gid));
    assert_eq!(layer.groups().stats().mean_variables(), 0.0);
    // A foreign GroupId (another layer's) names whatever group holds that slot here:
    // ids carry no layer identity (aliasing, undetectable).
    let (_, _, _, other) = stepped(2);
    let foreign = other.groups().iter().next().unwrap().0;
    let _ = layer.groups().get(foreign);
}

#[test]
fn filter_builders_accept_anything() {
    let stale = NodeId::from_raw_parts(9, 9);
    let f = Filter::all().with_nodes(&[stale, stale, NodeId::from_raw_parts(0, 0)]);
    assert_eq!(f.nodes().unwrap().len(), 2, "sorted, deduplicated");
    assert_eq!(Filter::all().with_nodes(&[]).nodes(), Some(&[][..]));
    assert!(KindSet::of(&[]).is_empty());
    let k = Filter::kinds(KindSet::NONE)
        .or_kind(EventKind::WokeUp)
        .or_kind(EventKind::WokeUp);
    assert_eq!(k.kinds_set(), KindSet::of(&[EventKind::WokeUp]));
}

#[test]
fn rule_values_with_stale_nodes() {
    let (a, b) = (NodeId::from_raw_parts(1, 0), NodeId::from_raw_parts(2, 0));
    let stale = NodeId::from_raw_parts(1, 5);
    let r = Rule::ignore_between(&[a, a], &[b]);
    assert_eq!(r.members(), vec![a, b]);
    assert!(!r.ignores(stale, b) && r.ignores(b, a));
    assert!(!Rule::ignore_pair(a, b).ignores(a, a));
    let (_, _, _, layer) = stepped(2);
    let table = layer.hooks().table();
    assert!(!table.ignores(stale, b) && !table.names(stale));
    assert!(!layer.hooks().mods().is_sleepy(RigidBodyHandle::invalid()));
}

// ── Speed-ups and monitor ──────────────────────────────────────────────────

#[test]
fn speedups_validate() {
    let ok = SpeedUps::contact_graph();
    ok.validate().unwrap();
    for bad in [
        SpeedUps {
            sleepy_energy: Real::NEG_INFINITY,
            ..ok.clone()
        },
        SpeedUps {
            reduce_depth: -0.0001,
            ..ok.clone()
        },
        SpeedUps {
            damping: Real::NAN,
            ..ok.clone()
        },
        SpeedUps {
            release_speed: -1.0,
            ..ok.clone()
        },
        SpeedUps {
            sleepy_steps: 0,
            ..ok.clone()
        },
        SpeedUps {
            iterations: 0,
            ..ok.clone()
        },
        SpeedUps {
            tweak_iterations: 0,
            ..ok.clone()
        },
    ] {
        assert!(
            matches!(bad.validate(), Err(Error::InvalidParameter { .. })),
            "{bad:?}"
        );
    }
    // Bits above the seven switches are ignored.
    assert_eq!(SpeedUps::combination(255), SpeedUps::combination(127));
}

#[test]
fn speedup_state_queries_with_foreign_handles() {
    let (mut world, _, ball, mut layer) = stepped(0);
    layer
        .set_speedups(Some(SpeedUps::combination(127)))
        .unwrap();
    for _ in 0..200 {
        layer.step(&mut world);
    }
    let s = layer.speedups().unwrap();
    for f in foreign_bodies(ball) {
        assert!(!s.is_sleepy(f) && !s.is_fixated(f));
    }
    let _ = s.fixated().count();
    let _ = s.stats();
}

#[test]
fn monitor_config_validate() {
    let ok = MonitorConfig::default();
    for (name, bad) in [
        (
            "hang_time",
            MonitorConfig {
                hang_time: Real::NAN,
                ..ok
            },
        ),
        (
            "hang_time",
            MonitorConfig {
                hang_time: -1.0,
                ..ok
            },
        ),
        (
            "penetration_fraction",
            MonitorConfig {
                penetration_fraction: Real::INFINITY,
                ..ok
            },
        ),
        (
            "launch_relative",
            MonitorConfig {
                launch_relative: Real::NAN,
                ..ok
            },
        ),
        (
            "launch_per_kg",
            MonitorConfig {
                launch_per_kg: -0.1,
                ..ok
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: 1.0,
                ..ok
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: Real::NAN,
                ..ok
            },
        ),
    ] {
        match bad.validate() {
            Err(Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{bad:?}: {other:?}"),
        }
        assert!(Monitor::new(bad).is_err());
    }
}

#[test]
fn monitor_check_with_a_world_the_layer_never_saw() {
    let (mut world, _, ball, mut layer) = stepped(10);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let empty = PhysicsWorld::new();
    let mut other = PhysicsWorld::new();
    other.gravity = Vector::splat(Real::NAN);
    for i in 0..4 {
        other.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(i as Real, Real::NAN, 0.0))
                .linvel(Vector::splat(Real::INFINITY)),
            ColliderBuilder::ball(0.6),
        );
    }
    for w in [&empty, &other, &world] {
        no_panic("check with a foreign world", || {
            monitor.check(&layer, &WorldView::from(w), &|_| true, &|_| true);
            monitor.check(&layer, &WorldView::from(w), &|_| false, &|_| false);
        });
    }
    // Quarantine reports of handles the world lacks are taken as given.
    let ghost = RigidBodyHandle::from_raw_parts(99, 0);
    layer.step(&mut world);
    let found = monitor
        .check_with_quarantine(
            &layer,
            &WorldView::from(&world),
            &|_| false,
            &|_| false,
            &[ghost],
        )
        .to_vec();
    assert!(found
        .iter()
        .any(|v| v.kind == ViolationKind::Escape && v.body == ghost && v.node.is_none()));
    // Priming foreign or removed handles is a no-op.
    for f in foreign_bodies(ball) {
        monitor.prime_body(&WorldView::from(&world), f);
    }
    monitor.prime(&WorldView::from(&empty));
    let _ = (
        monitor.totals(),
        monitor.peaks(),
        monitor.unsupported_held().count(),
    );
}

// ── Measure, report, export ────────────────────────────────────────────────

#[test]
fn dot_export_on_empty_and_odd_labels() {
    let empty = ContactLayer::new();
    let d = dot::to_dot(&empty, &dot::DotOptions::default());
    assert!(d.contains("0 nodes, 0 edges"));
    assert!(
        dot::graph_to_dot(&ContactGraph::new(), None, &dot::DotOptions::default())
            .contains("graph contact_graph {")
    );
    // Labels with quotes, backslashes and line breaks are escaped; a label for a stale
    // node is never asked for.
    let (_, _, _, layer) = stepped(5);
    let label = |n: NodeId| Some(format!("\"{}\\\n\r\0", n.index()));
    let d = dot::to_dot(
        &layer,
        &dot::DotOptions {
            label: Some(&label),
            ..Default::default()
        },
    );
    assert!(!d.contains("\"0\\\n"), "escaped");
    assert_eq!(dot::escape("a\"b\\c\nd\r"), "a\\\"b\\\\c\\nd");
}

#[test]
fn text_export_on_empty_layer() {
    let empty = ContactLayer::new();
    assert!(text::describe(&empty, &|_| None).starts_with("step 0: 0 nodes"));
    let (_, _, _, layer) = stepped(5);
    let s = text::describe(&layer, &|n| Some(format!("{}\n\u{0}", n.index())));
    assert!(s.contains("nodes:"));
}

// ── Scenes ─────────────────────────────────────────────────────────────────

#[test]
fn scenes_with_degenerate_parameters() {
    no_panic("degenerate scenes", || {
        let mut s = scenes::sphere_stack(0);
        s.run_plain(0, 2);
        let _ = scenes::sphere_pile(0, u64::MAX);
        for (spheres, radius, incline) in [
            (0, 0.5, 20.0),
            (10, Real::NAN, Real::NAN),
            (10, 0.0, 90.0),
            (10, -1.0, -720.0),
            (10, 1e30, Real::INFINITY),
        ] {
            let p = scenes::DikuParams {
                spheres,
                radius,
                incline_deg: incline,
                seed: 0,
            };
            let _ = scenes::diku(&p);
            let _ = scenes::diku::is_on_plane(&p, Vector::splat(Real::NAN));
        }
        let _ = scenes::diku::plane_width(usize::MAX);
        let _ = scenes::pile::wall_height(usize::MAX);
        let _ = scenes::diku::surface(0);
    });
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_scenes_step_index_overflow_panics() {
    no_panic("platform_x_after(u64::MAX)", || {
        scenes::kinematic_platform::platform_x_after(u64::MAX, DT)
    });
    no_panic("before_step(u64::MAX)", || {
        scenes::kinematic_platform().before_step(u64::MAX)
    });
    no_panic("run_plain(u64::MAX, 1)", || {
        scenes::ball_on_box().run_plain(u64::MAX, 1)
    });
}

// ── Rapier's own panics (the audit's last table) ───────────────────────────

/// A floor, a chain root – link (a multibody) and a free ball overlapping the link,
/// stepped once; a ball `spare` that is no multibody member.
fn multibody_scene() -> (PhysicsWorld, ContactLayer, [RigidBodyHandle; 3]) {
    let mut world = PhysicsWorld::new();
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.25, 0.0)),
        ColliderBuilder::cuboid(3.0, 0.25, 3.0),
    );
    let ball = |x: f32, y: f32| RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0));
    let root = world.insert(ball(0.0, 1.0), ColliderBuilder::ball(0.25)).0;
    let link = world.insert(ball(0.0, 0.5), ColliderBuilder::ball(0.25)).0;
    let joint = RevoluteJointBuilder::new(Vector::Z).local_anchor2(Vector::new(0.0, 0.6, 0.0));
    world.insert_multibody_joint(root, link, joint).unwrap();
    world.insert(ball(0.0, 0.5), ColliderBuilder::ball(0.25));
    let spare = world.insert(ball(2.0, 0.5), ColliderBuilder::ball(0.25)).0;
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    (world, layer, [root, link, spare])
}

#[test]
fn rapier_panics_set_passive_on_a_multibody_member_is_refused() {
    let (mut world, mut layer, [root, link, spare]) = multibody_scene();
    // At the call: a `Link` node (the root and the link) is refused, nothing changes.
    for h in [root, link] {
        assert!(matches!(
            layer.set_passive(h, true),
            Err(Error::Unsupported { .. })
        ));
    }
    no_panic("steps after refused set_passive", || {
        for _ in 0..3 {
            layer.step(&mut world);
        }
    });
    assert!(world.bodies[root].is_enabled() && world.bodies[link].is_enabled());
    assert!(layer.refusals().is_empty());
    // Wrong time: joined to the multibody between `set_passive` and the pre-step.
    layer.set_passive(spare, true).unwrap();
    let joint = RevoluteJointBuilder::new(Vector::Z).local_anchor2(Vector::new(0.0, 0.6, 0.0));
    world.insert_multibody_joint(link, spare, joint).unwrap();
    no_panic("step after a refused queued change", || {
        layer.step(&mut world)
    });
    assert!(world.bodies[spare].is_enabled());
    assert_eq!(layer.refusals().len(), 1);
    assert_eq!(layer.refusals()[0].0, spare);
    assert!(matches!(layer.refusals()[0].1, Error::Unsupported { .. }));
    layer.validate(&world).unwrap();
    no_panic("the next step", || layer.step(&mut world));
    assert!(layer.refusals().is_empty(), "cleared by every pre-step");
    // Making a member active is always accepted.
    layer.set_passive(root, false).unwrap();
    no_panic("set_passive(false) on a member", || layer.step(&mut world));
    layer.validate(&world).unwrap();
}

#[test]
fn rapier_panics_a_passive_body_joined_to_a_multibody_is_made_active_again() {
    let (mut world, mut layer, [_, _, spare]) = multibody_scene();
    layer.set_passive(spare, true).unwrap();
    layer.step(&mut world);
    assert!(!world.bodies[spare].is_enabled());
    // The user makes the passive body the root of a new multibody whose link rests on
    // the floor (a contact of the link: Rapier's solver panics on it).
    let (other, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(2.0, 0.2, 0.0)),
        ColliderBuilder::ball(0.25),
    );
    world
        .insert_multibody_joint(spare, other, RevoluteJointBuilder::new(Vector::Z))
        .unwrap();
    no_panic("step with a passive multibody root", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(world.bodies[spare].is_enabled(), "made active again");
}

#[test]
fn rapier_panics_joints_of_passive_bodies_are_held_disabled() {
    let (mut world, ground, ball, mut layer) = stepped(3);
    for x in [-2.0, 2.0] {
        world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, 1.0, 0.0)),
            ColliderBuilder::ball(0.5),
        );
    }
    layer.step(&mut world);
    layer.set_passive(ball, true).unwrap();
    layer.step(&mut world);
    // Joints added by the user to the passive body: to the fixed ground, and to a new
    // fixed body (Rapier enables the `DisabledByAttachedBody` joints of a body it
    // inserts, whatever the other end).
    let j1 = world.insert_impulse_joint(ground, ball, FixedJointBuilder::new());
    let (post, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(4.0, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.4, 0.4, 0.4),
    );
    let j2 = world.insert_impulse_joint(post, ball, FixedJointBuilder::new());
    // A joint the user disabled himself.
    let mut off: GenericJoint = FixedJointBuilder::new().into();
    off.set_enabled(false);
    let j3 = world.insert_impulse_joint(ground, ball, off);
    no_panic("steps with joints to a passive body", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    let enabled = |w: &PhysicsWorld, j| w.impulse_joints.get(j).unwrap().data.is_enabled();
    assert!(!enabled(&world, j1) && !enabled(&world, j2) && !enabled(&world, j3));
    // Active again: the layer's joints come back, the user's stays disabled.
    layer.set_passive(ball, false).unwrap();
    no_panic("steps after set_passive(false)", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(enabled(&world, j1) && enabled(&world, j2) && !enabled(&world, j3));
    // Another world handed to the pre-step loses nothing.
    layer.set_passive(ball, true).unwrap();
    layer.step(&mut world);
    assert!(!enabled(&world, j1));
    let mut other = PhysicsWorld::new();
    no_panic("pre_step on another world", || {
        layer.pre_step(WorldMut::from(&mut other))
    });
    layer.set_passive(ball, false).unwrap();
    layer.step(&mut world);
    assert!(enabled(&world, j1), "still held, enabled again");
}

#[test]
fn rapier_panics_a_deferred_fixation_is_checked_again_when_applied() {
    let mut world = PhysicsWorld::new();
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let ball = |x: f32| RigidBodyBuilder::dynamic().translation(Vector::new(x, 1.0, 0.0));
    let root = world.insert(ball(-2.0), ColliderBuilder::ball(0.5)).0;
    let link = world.insert(ball(2.0), ColliderBuilder::ball(0.5)).0;
    let mut layer = ContactLayer::new();
    layer
        .set_speedups(Some(SpeedUps {
            fixate: true,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    for _ in 0..200 {
        layer.step(&mut world);
        if layer.speedups().unwrap().stats().fixations > 0 {
            break;
        }
    }
    assert!(layer.speedups().unwrap().stats().fixations > 0);
    // Wrong time: between the decision and its application, the body becomes a link.
    world
        .insert_multibody_joint(root, link, RevoluteJointBuilder::new(Vector::Z))
        .unwrap();
    no_panic("steps after a deferred fixation of a new link", || {
        for _ in 0..5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(world.bodies[link].is_dynamic());
}

// ── Incidental (found while auditing; not bad input) ───────────────────────

#[test]
// Fixed: the hooks resolve any body through the graph and ask the predicate.
fn bug_incidental_predicate_rule_with_a_non_member() {
    let (mut world, _, ball, mut layer) = stepped(5);
    let b = layer.node_of_body(ball).unwrap();
    // "Ignore every interaction of the ball": only the ball is a member.
    layer
        .add_rule(Rule::ignore_if(&[b], move |x, y| x == b || y == b))
        .unwrap();
    for _ in 0..60 {
        layer.step(&mut world);
    }
    assert!(
        world.bodies[ball].translation().y < 0.0,
        "the ball fell through the ground"
    );
}

#[test]
fn monitor_entry_points_take_bad_input() {
    let (mut world, _, ball, mut layer) = stepped(5);
    // With the monitor off: priming and pushes are no-ops.
    layer.prime_monitor(&WorldView::from(&world));
    layer.mark_pushed(ball);
    assert!(layer.monitor().is_none());
    layer
        .set_monitor(
            MonitorMode::Off,
            MonitorConfig::default(),
            RepairConfig::default(),
        )
        .unwrap();
    assert!(layer.monitor().is_none(), "Off twice: no-op");
    layer
        .set_monitor(
            MonitorMode::Repair,
            MonitorConfig::default(),
            RepairConfig::default(),
        )
        .unwrap();
    type Edit = fn(&mut RepairConfig);
    let bad_repairs: [(&str, Edit); 7] = [
        ("corrective_cap", |r| r.corrective_cap = 0.0),
        ("corrective_cap", |r| r.corrective_cap = Real::NAN),
        ("penetration_warning", |r| r.penetration_warning = 0.0),
        ("penetration_warning", |r| r.penetration_warning = 1.5),
        ("fast_travel", |r| r.fast_travel = -0.1),
        ("fast_travel", |r| r.fast_travel = Real::NAN),
        ("fast_travel", |r| r.fast_travel = Real::INFINITY),
    ];
    for (want, edit) in bad_repairs {
        let mut r = RepairConfig::default();
        edit(&mut r);
        match layer.set_monitor(MonitorMode::Report, MonitorConfig::default(), r) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, want),
            other => panic!("{r:?}: expected an error on {want}, got {other:?}"),
        }
        assert_eq!(
            layer.monitor().unwrap().mode(),
            MonitorMode::Repair,
            "the monitor in force is kept"
        );
    }
    let bad_thresholds = MonitorConfig {
        hang_time: Real::INFINITY,
        ..MonitorConfig::default()
    };
    assert!(matches!(
        layer.set_monitor(MonitorMode::Report, bad_thresholds, RepairConfig::default()),
        Err(Error::InvalidParameter {
            name: "hang_time",
            ..
        })
    ));
    // A removed body: pushes are ignored, and it is not held.
    world.remove_body(ball);
    layer.mark_pushed(ball);
    assert!(!layer.holds(&world.bodies, ball));
    no_panic("step after pushing a removed body", || {
        layer.step(&mut world)
    });
    layer.validate(&world).unwrap();
    assert_eq!(layer.monitor().unwrap().monitor().totals().total(), 0);
}
