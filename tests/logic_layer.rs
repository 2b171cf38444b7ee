//! Rules, triggers, timers, passive bodies and containers (paper Tables 1–2, §3.2),
//! with the event streams of scripted scenes pinned by snapshots.

mod common;

use common::build::{ball_at, box_at};
use common::contract::ContractLog;
use rapier3d::prelude::*;
use rapier_contact_graph::events::EventKind;
use rapier_contact_graph::{ContactLayer, EdgeKind, Error, NodeId, NodeKind, Rule};
use rcg_scenes as scenes;

fn transitions(log: &ContractLog) -> Vec<rapier_contact_graph::Event> {
    log.events
        .iter()
        .copied()
        .filter(|e| {
            !matches!(
                e.kind,
                EventKind::ProximityPersisted | EventKind::ContactPersisted
            )
        })
        .collect()
}

#[test]
fn a_timer_ticks_on_time_for_ten_simulated_seconds() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    let t = layer.logic_mut().add_timer(0.75).unwrap();
    let mut names = common::Names::default();
    names.set(t, "timer");
    common::run_validated(&mut scene, &mut layer, 0, 1000);
    log.drain();
    let ticks: Vec<_> = log
        .events
        .iter()
        .filter(|e| e.kind == EventKind::TimerTick)
        .collect();
    assert_eq!(ticks.len(), 13, "10 s / 0.75 s");
    for e in &ticks {
        // Tick k fires on the step where time first reaches k·0.75 s: step ceil(75k).
        let due = (75 * e.tick).div_ceil(1);
        assert_eq!(e.step, due, "tick {}", e.tick);
    }
    assert_eq!(layer.logic().timer_ticks(t).unwrap(), 13);
    let timer_events: Vec<_> = log
        .events
        .iter()
        .copied()
        .filter(|e| e.kind == EventKind::TimerTick)
        .collect();
    insta::assert_snapshot!(
        "timer_10s_events",
        common::format_events(&timer_events, &names)
    );
    layer.logic_mut().remove_timer(t).unwrap();
    assert_eq!(layer.logic_mut().remove_timer(t), Err(Error::StaleNode(t)));
}

#[test]
fn bad_logical_input_is_an_error_and_changes_nothing() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 2);
    let nodes = layer.graph().node_count();
    for p in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            layer.logic_mut().add_timer(p),
            Err(Error::InvalidParameter { .. })
        ));
    }
    let ball = layer
        .graph()
        .try_node_of_body(scene.body("ball").unwrap())
        .unwrap();
    let ghost = NodeId::from_raw_parts(999, 0);
    assert_eq!(
        layer.logic_mut().add_rule(Rule::ignore_pair(ball, ghost)),
        Err(Error::StaleNode(ghost))
    );
    let t = layer.logic_mut().add_timer(1.0).unwrap();
    assert!(matches!(
        layer.logic_mut().add_rule(Rule::ignore_pair(ball, t)),
        Err(Error::WrongKind { .. })
    ));
    layer.logic_mut().remove_timer(t).unwrap();
    assert!(matches!(
        layer.logic_mut().remove_rule(ball),
        Err(Error::WrongKind { .. })
    ));
    let gone = RigidBodyHandle::from_raw_parts(77, 0);
    assert_eq!(
        layer
            .logic_mut()
            .set_body_disabled(&scene.world.bodies, gone, true),
        Err(Error::UnknownBody(gone))
    );
    assert!(layer.logic_mut().declare_composite_nodes(&[]).is_err());
    let ground = layer
        .graph()
        .try_node_of_body(scene.body("ground").unwrap())
        .unwrap();
    assert!(matches!(
        layer.logic_mut().declare_composite_nodes(&[ground]),
        Err(Error::WrongKind { .. })
    ));
    assert_eq!(layer.graph().node_count(), nodes, "nothing was added");
    common::run_validated(&mut scene, &mut layer, 2, 5);
}

#[test]
fn a_rule_switched_on_mid_run_lets_the_ball_fall_through_the_box() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    let mut names = common::Names::default();
    common::run_validated(&mut scene, &mut layer, 0, 120);
    names.learn(&scene, &layer);
    let (ball, bx) = (
        layer
            .graph()
            .try_node_of_body(scene.body("ball").unwrap())
            .unwrap(),
        layer
            .graph()
            .try_node_of_body(scene.body("box").unwrap())
            .unwrap(),
    );
    assert_eq!(layer.analysis().flagged_colliders(), 0, "no rule, no flag");
    let rule = layer
        .logic_mut()
        .add_rule(Rule::ignore_pair(ball, bx))
        .unwrap();
    names.set(rule, "rule");
    assert_eq!(layer.graph().node(rule).unwrap().kind(), NodeKind::Rule);
    assert_eq!(
        layer
            .graph()
            .neighbors(rule)
            .filter(|(_, _, e)| e.kind() == EdgeKind::Logical)
            .count(),
        2
    );
    common::run_validated(&mut scene, &mut layer, 120, 1);
    log.drain();
    // From here on, no event may name the pair.
    log.excluded.insert(if ball.index() < bx.index() {
        (ball, bx)
    } else {
        (bx, ball)
    });
    assert_eq!(
        layer.analysis().flagged_colliders(),
        2,
        "flags only on the ball's and the box's colliders"
    );
    let ground = scene.world.bodies[scene.body("ground").unwrap()].colliders()[0];
    assert!(scene.world.colliders[ground].active_hooks().is_empty());
    common::run_validated(&mut scene, &mut layer, 121, 150);
    log.drain();
    log.agrees_with(&layer);
    let ball_y = scene.world.bodies[scene.body("ball").unwrap()]
        .translation()
        .y;
    assert!(
        ball_y < 0.3,
        "the ball fell through the box to the ground: y = {ball_y}"
    );
    // Removing the rule restores the flags and the interaction.
    layer.logic_mut().remove_rule(rule).unwrap();
    common::run_validated(&mut scene, &mut layer, 271, 30);
    assert_eq!(layer.analysis().flagged_colliders(), 0);
    assert!(scene
        .world
        .colliders
        .iter()
        .all(|(_, c)| c.active_hooks().is_empty()));
    log.excluded.clear();
    log.drain();
    insta::assert_snapshot!(
        "rule_mid_run_events",
        common::format_events(&transitions(&log), &names)
    );
}

#[test]
fn a_passive_body_keeps_its_node_and_has_no_edges_or_events() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    let mut names = common::Names::default();
    common::run_validated(&mut scene, &mut layer, 0, 80);
    names.learn(&scene, &layer);
    let h = scene.body("ball").unwrap();
    let ball = layer.graph().try_node_of_body(h).unwrap();
    scene.world.bodies[h].user_data = 42;
    layer
        .logic_mut()
        .set_body_disabled(&scene.world.bodies, h, true)
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 80, 1);
    log.drain();
    log.passive.insert(ball);
    let node = layer.graph().node(ball).unwrap();
    assert!(node.is_body_disabled());
    assert_eq!(node.degree(), 0, "no edges while passive");
    common::run_validated(&mut scene, &mut layer, 81, 100);
    log.drain();
    assert_eq!(
        layer.graph().try_node_of_body(h),
        Ok(ball),
        "same node, same handle"
    );
    assert_eq!(scene.world.bodies[h].user_data, 42);
    layer
        .logic_mut()
        .set_body_disabled(&scene.world.bodies, h, false)
        .unwrap();
    log.passive.clear();
    common::run_validated(&mut scene, &mut layer, 181, 100);
    log.drain();
    log.agrees_with(&layer);
    assert!(!layer.graph().node(ball).unwrap().is_body_disabled());
    assert!(layer.graph().touching(ball).count() > 0, "back on the box");
    insta::assert_snapshot!(
        "passive_toggle_events",
        common::format_events(&transitions(&log), &names)
    );
}

/// A fixed sensor region with, inside or passing through it: a dynamic ball falling
/// through, a kinematic platform sliding through, a fixed block, and a dynamic box that
/// starts asleep inside it.
fn trigger_zoo() -> (PhysicsWorld, Vec<(&'static str, RigidBodyHandle)>) {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(20.0, 0.5, 20.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let (zone, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, 2.0, 0.0)),
        ColliderBuilder::cuboid(2.0, 2.0, 2.0).sensor(true),
    );
    let (ball, _) = ball_at(&mut world, [0.0, 6.0, 0.0], 0.3);
    let (slider, _) = world.insert(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(-5.0, 3.0, 1.0))
            .linvel(Vector::new(4.0, 0.0, 0.0)),
        ColliderBuilder::cuboid(0.3, 0.1, 0.3),
    );
    let (block, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(1.0, 1.0, -1.0)),
        ColliderBuilder::cuboid(0.2, 0.2, 0.2),
    );
    let (sleeper, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-1.0, 0.25, -1.0))
            .sleeping(true),
        ColliderBuilder::cuboid(0.25, 0.25, 0.25),
    );
    // A trigger carried by a dynamic body, falling onto the sleeper's region.
    let (carrier, _) = ball_at(&mut world, [-1.0, 8.0, -1.0], 0.2);
    world.insert_collider(ColliderBuilder::ball(0.6).sensor(true), Some(carrier));
    let names = vec![
        ("ground", ground),
        ("zone", zone),
        ("ball", ball),
        ("slider", slider),
        ("block", block),
        ("sleeper", sleeper),
        ("carrier", carrier),
    ];
    (world, names)
}

#[test]
fn triggers_on_every_body_type_see_bodies_of_every_type() {
    let (world, bodies) = trigger_zoo();
    let mut scene = scenes::Scene {
        name: "trigger_zoo",
        world,
        bodies,
        script: None,
    };
    let mut layer = ContactLayer::new();
    // Opt in: sensors see every body type (Rapier's default types leave some out).
    layer.logic_mut().set_trigger_widening(true);
    let mut log = ContractLog::attach(&mut layer);
    let mut names = common::Names::default();
    common::run_validated(&mut scene, &mut layer, 0, 1);
    names.learn(&scene, &layer);
    let zone_sensor = scene.world.bodies[scene.body("zone").unwrap()].colliders()[0];
    let carrier_sensor = scene.world.bodies[scene.body("carrier").unwrap()].colliders()[1];
    let zone_t = layer.graph().node_of_sensor(zone_sensor).unwrap();
    let carrier_t = layer.graph().node_of_sensor(carrier_sensor).unwrap();
    names.set(zone_t, "zone-trigger");
    names.set(carrier_t, "carrier-trigger");
    assert_eq!(layer.graph().count_of_kind(NodeKind::Sensor), 2);
    common::run_validated(&mut scene, &mut layer, 1, 300);
    log.drain();
    log.agrees_with(&layer);
    let entered = |t: NodeId, body: &str| {
        let b = layer
            .graph()
            .try_node_of_body(scene.body(body).unwrap())
            .unwrap();
        log.events
            .iter()
            .any(|e| e.kind == EventKind::SensorStarted && e.node1 == t && e.node2 == Some(b))
    };
    assert!(entered(zone_t, "ball"), "dynamic through a fixed trigger");
    assert!(
        entered(zone_t, "slider"),
        "kinematic through a fixed trigger"
    );
    assert!(entered(zone_t, "block"), "fixed inside a fixed trigger");
    assert!(
        entered(zone_t, "sleeper"),
        "sleeping body inside a fixed trigger"
    );
    assert!(
        entered(carrier_t, "sleeper"),
        "a moving trigger finds a sleeping body"
    );
    assert!(
        entered(carrier_t, "ground"),
        "a moving trigger finds fixed geometry"
    );
    let exited = log
        .events
        .iter()
        .any(|e| e.kind == EventKind::SensorStopped && e.node1 == zone_t);
    assert!(exited, "the slider leaves the zone");
    assert!(
        !log.events
            .iter()
            .any(|e| e.node1 == zone_t && e.node2 == Some(carrier_t)),
        "trigger–trigger ignored"
    );
    insta::assert_snapshot!(
        "trigger_zoo_events",
        common::format_events(
            &transitions(&log)
                .into_iter()
                .filter(|e| matches!(e.kind, EventKind::SensorStarted | EventKind::SensorStopped))
                .collect::<Vec<_>>(),
            &names
        )
    );
}

#[test]
fn triggers_do_not_change_motion() {
    let (mut plain, _) = trigger_zoo();
    let (mut observed, _) = trigger_zoo();
    let mut layer = ContactLayer::new();
    for _ in 0..300 {
        plain.step();
        layer.step(&mut observed);
    }
    assert_eq!(common::pose_bits(&plain), common::pose_bits(&observed));
}

#[test]
fn joints_make_containers_with_structural_edges() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let bx = |world: &mut PhysicsWorld, x: f32| box_at(world, [x, 0.5, 0.0], 0.25).0;
    let (a, b, c, d) = (
        bx(&mut world, -3.0),
        bx(&mut world, -2.4),
        bx(&mut world, 2.0),
        bx(&mut world, 2.6),
    );
    let fixed = world.insert_impulse_joint(
        a,
        b,
        FixedJointBuilder::new()
            .local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0)),
    );
    world.insert_impulse_joint(
        c,
        d,
        RevoluteJointBuilder::new(Vector::Z)
            .local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0)),
    );
    let mut scene = scenes::Scene {
        name: "joints",
        world,
        bodies: vec![],
        script: None,
    };
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 5);
    assert_eq!(layer.graph().count_of_kind(NodeKind::Composite), 1);
    assert_eq!(layer.graph().count_of_kind(NodeKind::Multibody), 1);
    let na = layer.graph().try_node_of_body(a).unwrap();
    let nb = layer.graph().try_node_of_body(b).unwrap();
    let ga = layer.graph().node(na).unwrap().group();
    assert!(
        ga.is_some() && ga == layer.graph().node(nb).unwrap().group(),
        "the composite is one group"
    );
    // Removing the fixed joint removes the composite.
    scene.world.remove_impulse_joint(fixed);
    common::run_validated(&mut scene, &mut layer, 5, 5);
    assert_eq!(layer.graph().count_of_kind(NodeKind::Composite), 0);
    assert_eq!(layer.graph().count_of_kind(NodeKind::Multibody), 1);
    // A declared composite joins free bodies.
    let comp = layer
        .logic_mut()
        .declare_composite_nodes(&[na, nb])
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 10, 1);
    assert_eq!(
        layer.graph().node(na).unwrap().group(),
        layer.graph().node(nb).unwrap().group()
    );
    layer.logic_mut().remove_composite(comp).unwrap();
    common::run_validated(&mut scene, &mut layer, 11, 1);
    assert_ne!(
        layer.graph().node(na).unwrap().group(),
        layer.graph().node(nb).unwrap().group()
    );
}

#[test]
fn multibody_links_are_link_nodes_of_one_multibody() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    let (anchor, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, 3.0, 0.0)),
        ColliderBuilder::ball(0.1),
    );
    let (l0, _) = ball_at(&mut world, [1.0, 3.0, 0.0], 0.2);
    let (l1, _) = ball_at(&mut world, [2.0, 3.0, 0.0], 0.2);
    let j = RevoluteJointBuilder::new(Vector::Z).local_anchor2(Vector::new(-1.0, 0.0, 0.0));
    world.insert_multibody_joint(anchor, l0, j).unwrap();
    world.insert_multibody_joint(l0, l1, j).unwrap();
    let mut scene = scenes::Scene {
        name: "chain",
        world,
        bodies: vec![],
        script: None,
    };
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 50);
    let g = layer.graph();
    assert_eq!(g.count_of_kind(NodeKind::Multibody), 1);
    assert_eq!(g.count_of_kind(NodeKind::Link), 2);
    let (m, _) = g.nodes_of_kind(NodeKind::Multibody).next().unwrap();
    let links: Vec<_> = g
        .neighbors(m)
        .map(|(n, _, _)| g.node(n).unwrap().kind())
        .collect();
    assert_eq!(
        links,
        vec![NodeKind::Link, NodeKind::Link],
        "the fixed anchor is not a member"
    );
    let n0 = layer.graph().try_node_of_body(l0).unwrap();
    let n1 = layer.graph().try_node_of_body(l1).unwrap();
    assert_eq!(
        g.node(n0).unwrap().group(),
        g.node(n1).unwrap().group(),
        "one group through the container"
    );
}

/// Runs a shared scene with a contract-checking log and returns its transition
/// stream (persist events left out) with body names.
fn scene_stream(mut scene: scenes::Scene, steps: u64) -> String {
    let mut layer = ContactLayer::new();
    let mut log = ContractLog::attach(&mut layer);
    let mut names = common::Names::default();
    for step in 0..steps {
        common::run_validated(&mut scene, &mut layer, step, 1);
        names.learn(&scene, &layer);
        log.drain();
        log.agrees_with(&layer);
    }
    common::format_events(&transitions(&log), &names)
}

#[test]
fn a_ball_rolling_through_a_trigger_and_off_a_ledge_event_stream() {
    let stream = scene_stream(scenes::trigger_ledge(), 300);
    assert!(stream.contains("SensorStarted") && stream.contains("SensorStopped"));
    insta::assert_snapshot!("trigger_ledge_events", stream);
}

#[test]
fn a_toppling_stack_event_stream() {
    insta::assert_snapshot!(
        "toppling_stack_events",
        scene_stream(scenes::toppling_stack(), 250)
    );
}

#[test]
fn a_multibody_pendulum_hitting_a_wall_event_stream() {
    let stream = scene_stream(scenes::pendulum_wall(), 200);
    assert!(stream.contains("ContactStarted wall l2") || stream.contains("ContactStarted l2 wall"));
    insta::assert_snapshot!("pendulum_wall_events", stream);
}
