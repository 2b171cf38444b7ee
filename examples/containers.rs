//! Containers (Table 1's M and C): the pendulum's Rapier multibody becomes a
//! `Multibody` node with structural edges to its `Link` nodes, and the links form one
//! contact group even before anything touches. Two free boxes declared a `Composite`
//! with `declare_composite` likewise join into one group.
//!
//! ```text
//! cargo run --example containers
//! ```

use rapier_contact_graph::logic::ContainerSource;
use rapier_contact_graph::rapier3d::math::Vector;
use rapier_contact_graph::rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};
use rapier_contact_graph::{ContactLayer, EdgeKind, GroupId, NodeId, NodeKind, NodeSource};
use rcg_scenes::{self as scenes, Scene};

fn name(scene: &Scene, layer: &ContactLayer, n: NodeId) -> String {
    let h = layer.graph().body_of(n);
    match scene.bodies.iter().find(|(_, b)| Some(*b) == h) {
        Some((s, _)) => s.to_string(),
        None => format!("{n}:{:?}", layer.graph().node(n).unwrap().kind()),
    }
}

fn print_groups(scene: &Scene, layer: &ContactLayer) {
    println!("{} contact groups:", layer.groups().len());
    for (_, g) in layer.groups().iter() {
        let members: Vec<String> = g.bodies.iter().map(|&n| name(scene, layer, n)).collect();
        let insulators: Vec<String> = g
            .insulators
            .iter()
            .map(|&n| name(scene, layer, n))
            .collect();
        println!(
            "  {members:?}  insulators {insulators:?}  contacts {}  asleep {}",
            g.contacts, g.asleep
        );
    }
}

fn main() {
    let mut scene = scenes::pendulum_wall();
    let mut layer = ContactLayer::new();
    let mut hit = false;
    for step in 1..=100u64 {
        layer.step(&mut scene.world);
        let wall = layer
            .node_of_body(&scene.world.bodies, scene.body("wall").unwrap())
            .unwrap();
        if !hit && layer.graph().touching(wall).next().is_some() {
            hit = true;
            println!("== step {step}: the chain hits the wall");
            print_groups(&scene, &layer);
        }
    }
    println!("== after {} steps", layer.analysis().current_step());
    for (m, node) in layer.graph().nodes_of_kind(NodeKind::Multibody) {
        let NodeSource::Container(ContainerSource::Multibody(root)) = node.source() else {
            continue;
        };
        let root = scene.bodies.iter().find(|b| b.1 == root).map(|b| b.0);
        println!(
            "container {m} {:?}, multibody rooted at {root:?}:",
            node.kind()
        );
        for (other, e, edge) in layer.graph().neighbors(m) {
            if edge.kind() == EdgeKind::Structural {
                let kind = layer.graph().node(other).unwrap().kind();
                println!(
                    "  structural edge {e} -> {other} {kind:?} {}",
                    name(&scene, &layer, other)
                );
            }
        }
    }
    let anchor = layer
        .node_of_body(&scene.world.bodies, scene.body("anchor").unwrap())
        .unwrap();
    println!(
        "anchor {anchor} is {:?}, edges {}: fixed bodies insulate, they join no container",
        layer.graph().node(anchor).unwrap().kind(),
        layer.graph().node(anchor).unwrap().degree()
    );
    print_groups(&scene, &layer);

    // Two free boxes on the ground, apart: two groups, until declared one composite.
    let boxes = [("box A", 2.0), ("box B", 3.0)].map(|(label, x)| {
        let (h, _) = scene.world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, 0.25, 0.0)),
            ColliderBuilder::cuboid(0.25, 0.25, 0.25),
        );
        scene.bodies.push((label, h));
        h
    });
    layer.step(&mut scene.world);
    let nodes: [NodeId; 2] = boxes.map(|h| layer.node_of_body(&scene.world.bodies, h).unwrap());
    // Groups are named by slot index here (their ids are generational).
    let report = |layer: &ContactLayer, what: &str| {
        let g = nodes.map(|n| layer.graph().node(n).unwrap().group());
        let show = |g: Option<GroupId>| g.map_or("none".into(), |g| format!("g{}", g.index()));
        let (a, b) = (show(g[0]), show(g[1]));
        println!(
            "== {what}: A in {a}, B in {b} (same group: {})",
            g[0] == g[1]
        );
    };
    report(&layer, "boxes added");
    let c = layer
        .logic_mut()
        .declare_composite(&scene.world, &boxes)
        .unwrap();
    layer.step(&mut scene.world);
    report(
        &layer,
        &format!(
            "declared composite {c} {:?}",
            layer.graph().node(c).unwrap().kind()
        ),
    );
    print_groups(&scene, &layer);
    layer
        .validate(&scene.world)
        .expect("the graph matches the world");
}
