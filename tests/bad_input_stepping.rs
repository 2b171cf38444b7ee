//! Bad-input audit (see `tests/common/audit.rs`): stepping — `ContactLayer::step`,
//! `pre_step` and `analyze` with non-finite state, odd `dt`, foreign worlds and odd
//! views — and calls at the wrong time: during a Rapier step the user drives, between
//! `pre_step` and Rapier's step, before the first step. The effect of odd `dt` on the
//! clock and the timers is in `bad_input_timers.rs`.

mod common;

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use rapier3d::prelude::*;
use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::monitor::{Monitor, MonitorConfig};
use rapier_contact_graph::{ContactLayer, Error, NodeKind, Rule, WorldMut, WorldView};

use common::audit::*;
use common::build::*;

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
        for speedups in [None, Some(rcg_lab::table5::combination(127))] {
            let (mut world, _, ball, mut layer) = stepped(5);
            layer.speedups_mut().set(speedups.clone()).unwrap();
            let node = layer.graph().try_node_of_body(ball).unwrap();
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
    let c = static_ground(&mut world);
    ball_at(&mut world, [0.0, 1.0, 0.0], 0.5);
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
        box_at(&mut b, [2.0 * i as Real, 3.0, 0.0], 0.5);
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
// the round-robin verification within `slots / verify_budget()` steps (here, one:
// a world this small is checked whole every step).
fn bug_step_remove_and_insert_leaves_ghost_node() {
    // Fixed body removed, another body inserted: the counts do not change, so no full
    // scan runs, and the fixed body was never awake, so nothing refreshes it.
    let (mut world, ground, _, mut layer) = stepped(30);
    let g = layer.graph().try_node_of_body(ground).unwrap();
    world.remove_body(ground);
    ball_at(&mut world, [20.0, 5.0, 0.0], 0.5);
    layer.step(&mut world);
    assert!(
        layer.analysis().removed_nodes().iter().any(|r| r.id == g),
        "the removed ground is reported removed"
    );
    assert!(layer.graph().node(g).is_none(), "its node is gone");
    layer.validate(&world).unwrap();

    // Sleeping body removed, another inserted: its touch span never ends.
    let (mut world, _, ball, mut layer) = stepped(400);
    assert!(world.bodies[ball].is_sleeping());
    let events = layer.subscribe(Filter::kinds(KindSet::CONTACT));
    world.remove_body(ball);
    ball_at(&mut world, [20.0, 5.0, 0.0], 0.5);
    layer.step(&mut world);
    assert!(
        events
            .try_iter()
            .any(|e| e.kind == EventKind::ContactStopped),
        "removing a body ends its spans (events contract)"
    );
    layer.validate(&world).unwrap();

    // Static collider removed, another inserted: the new one never gets a node.
    let mut world = PhysicsWorld::new();
    let c = static_ground(&mut world);
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
fn pre_step_with_a_foreign_world_and_twice() {
    let (mut world, ground, ball, mut layer) = stepped(3);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, true)
        .unwrap();
    let (g, b) = (
        layer.graph().try_node_of_body(ground).unwrap(),
        layer.graph().try_node_of_body(ball).unwrap(),
    );
    layer.logic_mut().add_rule(Rule::ignore_pair(g, b)).unwrap();
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
    let big = foreign_world(5);
    let mixed = WorldView {
        narrow_phase: &big.narrow_phase,
        islands: &big.islands,
        ..WorldView::from(&other)
    };
    no_panic("analyze a mixed view", || {
        layer.analyze(mixed);
        let _ = layer.validate(&mixed);
    });
    // Wrong time: analysed twice for one Rapier step. Counted as two steps (the
    // contract is one call per step; the view cannot tell).
    let timer = layer.logic_mut().add_timer(1.0).unwrap();
    world.step();
    let before = (
        layer.analysis().current_step(),
        layer.logic().simulated_time(),
    );
    layer.analyze(WorldView::from(&world));
    layer.analyze(WorldView::from(&world));
    assert_eq!(layer.analysis().current_step(), before.0 + 2);
    assert!((layer.logic().simulated_time() - before.1 - 2.0 * DT as f64).abs() < 1e-9);
    assert_eq!(layer.logic().timer_ticks(timer), Ok(0));
    layer.validate(&world).unwrap();
}

// ── Wrong time: calls during a Rapier step the user drives, between `pre_step` and
// Rapier's step, before the first step ─────────────────────────────────────────

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
        let node = l.graph().try_node_of_body(self.ball);
        let touching = l
            .graph()
            .edge_of_bodies(self.ball, self.ground)
            .is_some_and(|e| e.is_touching());
        let ok = node.is_ok() && l.graph().validate().is_ok();
        self.seen
            .lock()
            .unwrap()
            .push((l.analysis().current_step(), ok, touching));
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
    let (mut world, ground) = world_with_ground();
    world.integration_parameters.dt = DT;
    let (ball, _) = world.insert(
        dynamic_at([0.0, 1.5, 0.0]),
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
    let b = layer.graph().try_node_of_body(ball).unwrap();
    let g = layer
        .graph()
        .nodes_of_kind(NodeKind::Fixed)
        .next()
        .unwrap()
        .0;
    // The predicate is `'static + Send + Sync` and gets node ids only: it cannot borrow
    // the layer. It can hold a receiver; it sees the events of finished steps only.
    layer
        .logic_mut()
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
        now.store(layer.analysis().current_step() + 1, Ordering::Relaxed);
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
        layer.graph().try_node_of_body(ground).unwrap(),
        layer.graph().try_node_of_body(ball).unwrap(),
    );
    layer.pre_step(WorldMut::from(&mut world));
    // Too late for this step: the hooks were prepared already.
    layer.logic_mut().add_rule(Rule::ignore_pair(g, b)).unwrap();
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
    // The layer has not seen the world yet: its bodies are not seen yet where a node
    // is needed (the graph, asked without the world, has none).
    assert_eq!(
        layer.graph().try_node_of_body(ball),
        Err(Error::UnknownBody(ball))
    );
    assert_eq!(
        layer.node_of_body(&world.bodies, ball),
        Err(Error::UnseenBody(ball))
    );
    assert_eq!(
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, ball, true),
        Err(Error::UnseenBody(ball))
    );
    assert!(Error::UnseenBody(ball)
        .to_string()
        .contains("inserted since the layer's last step"));
    // Nothing analysed yet: nothing to hold against the world.
    assert_eq!(layer.validate(&world), Ok(()));
    assert!(layer.graph().edge_of_bodies(ground, ball).is_none());
    let t = layer.logic_mut().add_timer(1.0).unwrap();
    assert_eq!(
        layer.validate(&world),
        Ok(()),
        "a timer before the first step"
    );
    assert_eq!(layer.logic().timer_ticks(t), Ok(0));
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let found = no_panic("monitor before the first step", || {
        monitor
            .check(&layer, &WorldView::from(&world), &|_| true, &|_| false)
            .len()
    });
    assert_eq!(found, 0);
}

#[test]
fn validate_before_the_first_step_is_ok_and_after_it_checks_the_world() {
    let (mut world, _, _) = ball_on_ground();
    let mut layer = ContactLayer::new();
    layer.validate(&world).unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    // Another world: the layer's graph does not match it.
    let other = foreign_world(3);
    assert!(layer.validate(&other).is_err());
}
