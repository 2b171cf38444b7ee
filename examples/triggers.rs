//! Trigger volumes: a ball rolls along a table, through a trigger, off the ledge and
//! onto the floor (`scenes::trigger_ledge`). One subscription takes the trigger events
//! (`KindSet::SENSOR`), another the ball's touch begin / end, to tell the whole story.
//!
//! ```text
//! cargo run --example triggers
//! ```

use rapier_contact_graph::{ContactLayer, Event, EventKind, Filter, KindSet, NodeId, NodeSource};
use rcg_scenes::{self as scenes, Scene};

/// The scene's name for a node: its body's, or for a trigger its sensor's body's.
fn name(scene: &Scene, layer: &ContactLayer, node: NodeId) -> String {
    let named = |h| scene.bodies.iter().find(|(_, b)| *b == h).map(|(n, _)| *n);
    match layer.graph().node(node).map(|n| n.source()) {
        Some(NodeSource::Body(h)) => named(h).unwrap_or("?").to_string(),
        Some(NodeSource::Sensor(c)) => {
            let parent = scene.world.colliders[c].parent().and_then(named);
            format!("{}'s sensor", parent.unwrap_or("?"))
        }
        _ => format!("{node}"),
    }
}

fn print(scene: &Scene, layer: &ContactLayer, ev: &Event, dt: f64) {
    let x = scene.world.bodies[scene.body("ball").unwrap()]
        .translation()
        .x;
    println!(
        "step {:>3}  t = {:.2} s  {:<13} {:<17} {:<5} (ball x = {x:+.2})",
        ev.step,
        ev.step as f64 * dt,
        format!("{:?}", ev.kind),
        name(scene, layer, ev.node1),
        ev.node2.map_or("-".into(), |b| name(scene, layer, b)),
    );
}

fn main() {
    let mut scene = scenes::trigger_ledge();
    let dt = scenes::DT as f64;
    let mut layer = ContactLayer::new();
    let triggers = layer.subscribe(Filter::kinds(KindSet::SENSOR));

    // The first step makes the nodes; then the ball's node can be named in a filter.
    layer.step(&mut scene.world);
    let ball = layer
        .node_of_body(&scene.world.bodies, scene.body("ball").unwrap())
        .unwrap();
    let touches = layer.subscribe(
        Filter::kinds(KindSet::of(&[
            EventKind::ContactStarted,
            EventKind::ContactStopped,
        ]))
        .with_nodes(&[ball]),
    );
    let trigger_body = layer
        .node_of_body(&scene.world.bodies, scene.body("trigger").unwrap())
        .unwrap();
    for (id, node) in layer
        .graph()
        .nodes_of_kind(rapier_contact_graph::NodeKind::Sensor)
    {
        println!(
            "trigger node {id} ({:?}); its fixed body is node {trigger_body}",
            node.source()
        );
    }

    let (mut enters, mut exits) = (0, 0);
    for _ in 1..300 {
        layer.step(&mut scene.world);
        // Events of one step, trigger ones first (two channels: merge by arrival).
        for ev in triggers.try_iter() {
            match ev.kind {
                EventKind::SensorStarted => enters += 1,
                EventKind::SensorStopped => exits += 1,
                _ => unreachable!("filtered"),
            }
            print(&scene, &layer, &ev, dt);
        }
        for ev in touches.try_iter() {
            print(&scene, &layer, &ev, dt);
        }
    }
    let p = scene.world.bodies[scene.body("ball").unwrap()].translation();
    println!(
        "after {} steps: {enters} enter, {exits} exit; ball at ({:.2}, {:.2}, {:.2})",
        layer.analysis().current_step(),
        p.x,
        p.y,
        p.z
    );
    layer
        .validate(&scene.world)
        .expect("the graph matches the world");
}
