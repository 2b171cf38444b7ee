//! Passive bodies (paper §3.2): a body taken out of the simulation without being
//! deallocated. In the ball-on-box scene the ball, resting on the box, is made passive
//! after step 100 — its edges end, it keeps its node and hangs where it was — and active
//! again after step 150, when it rests on the box anew.
//!
//! ```text
//! cargo run --example passive
//! ```

use rapier_contact_graph::EventKind::{
    ContactStarted, ContactStopped, ProximityStarted, ProximityStopped,
};
use rapier_contact_graph::{ContactLayer, Filter, KindSet, NodeId};
use rcg_scenes::{self as scenes, Scene};

fn name(scene: &Scene, layer: &ContactLayer, n: NodeId) -> &'static str {
    let h = layer.graph().body_of(n);
    let found = scene.bodies.iter().find(|(_, b)| Some(*b) == h);
    found.map_or("?", |(s, _)| *s)
}

fn show(scene: &Scene, layer: &ContactLayer, ball: NodeId, when: &str) {
    let node = layer.graph().node(ball).expect("the ball keeps its node");
    let rb = &scene.world.bodies[scene.body("ball").unwrap()];
    let group = node.group().and_then(|g| layer.groups().get(g));
    let members: Vec<&str> = group.map_or(Vec::new(), |g| {
        g.bodies.iter().map(|&n| name(scene, layer, n)).collect()
    });
    println!(
        "{when:<17} node {ball} {:?}: passive {}, edges {}, group {members:?}; enabled {}, y {:.3}",
        node.kind(),
        node.is_body_disabled(),
        node.degree(),
        rb.is_enabled(),
        rb.translation().y,
    );
}

fn main() {
    let mut scene = scenes::ball_on_box();
    let ball_body = scene.body("ball").unwrap();
    let mut layer = ContactLayer::new();
    // Begin / end and sleep events (persist events would repeat every step).
    let events = layer.subscribe(Filter::kinds(
        KindSet::of(&[
            ProximityStarted,
            ProximityStopped,
            ContactStarted,
            ContactStopped,
        ])
        .union(KindSet::SLEEP),
    ));
    layer.step(&mut scene.world);
    let ball = layer.node_of_body(&scene.world.bodies, ball_body).unwrap();
    for step in 1..250u64 {
        match step {
            100 => {
                show(&scene, &layer, ball, "before step 101:");
                layer
                    .logic_mut()
                    .set_body_disabled(&scene.world.bodies, ball_body, true)
                    .unwrap();
                println!("-- set_body_disabled(ball, true)");
            }
            150 => {
                layer
                    .logic_mut()
                    .set_body_disabled(&scene.world.bodies, ball_body, false)
                    .unwrap();
                println!("-- set_body_disabled(ball, false)");
            }
            _ => {}
        }
        layer.step(&mut scene.world);
        if step == 100 || step == 149 || step == 150 || step == 249 {
            show(&scene, &layer, ball, &format!("after step {}:", step + 1));
        }
        for ev in events.try_iter() {
            let b = ev.node2.map_or("-", |b| name(&scene, &layer, b));
            let kind = format!("{:?}", ev.kind);
            println!(
                "step {:>3}  {kind:<14} {:<6} {b}",
                ev.step,
                name(&scene, &layer, ev.node1)
            );
        }
        layer
            .validate(&scene.world)
            .expect("the graph matches the world");
    }
}
