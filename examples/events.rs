//! Subscribing to events on the toppling stack (`scenes::toppling_stack`):
//! - `all`: every event, on a bounded channel of 64 drained only every 50 steps, so
//!   events that do not fit are dropped and counted (`event_bus().dropped()`);
//! - `touch`: touch begin / end of every pair, printed as they come;
//! - `top`: every touch event (persist too) of the top box only, by node filter;
//! - `gone`: every event, but its receiver is dropped after step 50: the step goes
//!   on, and the subscription is pruned at the next event (`event_bus().pruned()`).
//!
//! ```text
//! cargo run --example events
//! ```

use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet, NodeId};
use rcg_scenes::{self as scenes, Scene};

fn name(scene: &Scene, layer: &ContactLayer, n: NodeId) -> &'static str {
    let h = layer.graph().body_of(n);
    let found = scene.bodies.iter().find(|(_, b)| Some(*b) == h);
    found.map_or("?", |(s, _)| *s)
}

fn main() {
    let mut scene = scenes::toppling_stack();
    let mut layer = ContactLayer::new();
    let all = layer.subscribe_bounded(Filter::all(), 64).unwrap();
    let touch = layer.subscribe(Filter::kinds(KindSet::of(&[
        EventKind::ContactStarted,
        EventKind::ContactStopped,
    ])));
    let mut gone = Some(layer.subscribe(Filter::all()));
    layer.step(&mut scene.world); // the nodes exist from here on
    let b4 = layer
        .node_of_body(&scene.world.bodies, scene.body("b4").unwrap())
        .unwrap();
    let top = layer.subscribe(Filter::kinds(KindSet::CONTACT).with_nodes(&[b4]));
    println!("4 subscriptions; top box b4 is node {b4}");

    let (mut received_all, mut received_top) = (0usize, 0usize);
    for _ in 1..300 {
        let stats = layer.step(&mut scene.world);
        let step = stats.step;
        for ev in touch.try_iter() {
            let (a, b) = (
                name(&scene, &layer, ev.node1),
                ev.node2.map_or("-", |b| name(&scene, &layer, b)),
            );
            println!(
                "  step {:>3}  {:<10} {a} - {b}",
                ev.step,
                format!("{:?}", ev.kind)
            );
        }
        received_top += top.try_iter().count();
        if step % 50 == 0 {
            received_all += all.try_iter().count();
            println!(
                "step {:>3}: {:>2} events this step; all: {received_all} received, {} dropped; \
                 top: {received_top}; subscriptions {}, pruned {}",
                step,
                stats.events,
                layer.analysis().event_bus().dropped(),
                layer.analysis().event_bus().len(),
                layer.analysis().event_bus().pruned(),
            );
        }
        if step == 50 {
            let rx = gone.take().unwrap();
            println!("-- dropping `gone` after reading {} events", rx.len());
            drop(rx);
        }
        if step == 51 {
            println!(
                "   step 51 ran: subscriptions {}, pruned {}",
                layer.analysis().event_bus().len(),
                layer.analysis().event_bus().pruned()
            );
        }
    }
    layer
        .validate(&scene.world)
        .expect("the graph matches the world");
    let top_y = scene.world.bodies[scene.body("b4").unwrap()]
        .translation()
        .y;
    println!(
        "after {} steps: {} events delivered in all, top box at y = {top_y:.2}",
        layer.analysis().current_step(),
        layer.analysis().event_bus().sent()
    );
}
