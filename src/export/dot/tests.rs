//! Unit tests of the DOT export.

use rapier3d::prelude::*;

use super::*;
use rcg_scenes::{self as scenes, Scene};

/// Runs `steps` layer steps on a scene.
fn run(scene: &mut Scene, steps: u64) -> ContactLayer {
    let mut layer = ContactLayer::new();
    for step in 0..steps {
        scene.before_step(step);
        layer.step(&mut scene.world);
        if let Err(e) = layer.validate(&scene.world) {
            panic!("step {step}: {e}");
        }
    }
    layer
}

/// The scene's body names by node.
fn names(scene: &Scene, layer: &ContactLayer) -> Vec<(NodeId, &'static str)> {
    scene
        .bodies
        .iter()
        .filter_map(|&(name, h)| Some((layer.graph().node_of_body(h)?, name)))
        .collect()
}

/// The line declaring node `n`.
fn node_line(dot: &str, n: NodeId) -> &str {
    let prefix = format!("n{} [", n.index());
    dot.lines()
        .map(str::trim)
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no line for {n:?} in\n{dot}"))
}

/// The line of the edge between `a` and `b`.
fn edge_line(dot: &str, a: NodeId, b: NodeId) -> &str {
    let (a, b) = (a.index().min(b.index()), a.index().max(b.index()));
    let prefix = format!("n{b} -- n{a} [");
    dot.lines()
        .map(str::trim)
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no edge n{b} -- n{a} in\n{dot}"))
}

#[test]
fn ground_is_a_filled_insulator_and_contact_is_solid() {
    let mut world = PhysicsWorld::new();
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.99, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    let mut layer = ContactLayer::new();
    for _ in 0..5 {
        layer.step(&mut world);
    }
    let g = layer.graph().try_node_of_body(ground).unwrap();
    let b = layer.graph().try_node_of_body(ball).unwrap();
    assert!(layer
        .graph()
        .edge_of_bodies(ground, ball)
        .unwrap()
        .is_touching());

    let dot = to_dot(&layer, &DotOptions::default());
    assert!(dot.contains("graph contact_graph {"), "{dot}");
    assert!(dot.trim_end().ends_with('}'));
    let ground_line = node_line(&dot, g);
    assert!(ground_line.starts_with(&format!("n{} [label=\"F{}\"", g.index(), g.index())));
    assert!(ground_line.contains("shape=circle"));
    assert!(ground_line.contains("style=filled"), "{ground_line}");
    let ball_line = node_line(&dot, b);
    assert!(ball_line.contains(&format!("label=\"R{}\"", b.index())));
    assert!(
        !ball_line.contains("style="),
        "awake: plain outline: {ball_line}"
    );
    let contact = edge_line(&dot, g, b);
    let count = layer
        .graph()
        .edge_of_bodies(ground, ball)
        .unwrap()
        .cache()
        .contact_count;
    assert!(contact.contains("style=solid"), "{contact}");
    assert!(contact.contains(&format!("label=\"{count}\"")), "{contact}");

    // One group (the ball), the ground outside it.
    assert_eq!(dot.matches("subgraph cluster_").count(), 1);
    let cluster = &dot[dot.find("subgraph cluster_g0").unwrap()..];
    let cluster = &cluster[..cluster.find("\n  }").unwrap()];
    assert!(cluster.contains(&format!("n{} [", b.index())));
    assert!(!cluster.contains(&format!("n{} [", g.index())));

    // Without counts or groups.
    let plain = to_dot(
        &layer,
        &DotOptions {
            groups: false,
            contact_counts: false,
            ..DotOptions::default()
        },
    );
    assert!(!plain.contains("cluster"));
    assert!(edge_line(&plain, g, b).ends_with("[style=solid];"));
}

#[test]
fn sleeping_bodies_are_dashed() {
    let mut scene = scenes::ball_on_box();
    let layer = run(&mut scene, 400);
    let ball = layer
        .graph()
        .try_node_of_body(scene.body("ball").unwrap())
        .unwrap();
    let node = layer.graph().node(ball).unwrap();
    assert!(!node.is_awake(), "the ball should sleep after 4 s");
    let dot = to_dot(&layer, &DotOptions::default());
    assert!(node_line(&dot, ball).contains("style=dashed"), "{dot}");
    assert!(dot.contains(", asleep\""), "a sleeping group: {dot}");
}

#[test]
fn two_piles_give_two_clusters_sharing_the_insulators() {
    let mut scene = scenes::two_piles_with_wall();
    let layer = run(&mut scene, 100);
    let names = names(&scene, &layer);
    let label = |n: NodeId| {
        names
            .iter()
            .find(|(m, _)| *m == n)
            .map(|(_, s)| s.to_string())
    };
    let options = DotOptions {
        label: Some(&label),
        ..DotOptions::default()
    };
    let dot = to_dot(&layer, &options);

    assert_eq!(layer.groups().len(), 2, "two piles, two groups");
    let clusters = dot.matches("subgraph cluster_").count();
    assert_eq!(clusters, layer.groups().len(), "{dot}");

    // Split the text into the two cluster bodies and the rest.
    let c0 = dot.find("subgraph cluster_g0").unwrap();
    let c1 = dot.find("subgraph cluster_g1").unwrap();
    let end = c1 + dot[c1..].find("\n  }").unwrap();
    let (first, second, outside) = (&dot[c0..c1], &dot[c1..end], &dot[end..]);
    for (cluster, side) in [(first, "\\nl"), (second, "\\nr")] {
        assert_eq!(cluster.matches(side).count(), 4, "{side} pile: {cluster}");
    }
    for insulator in ["ground", "wall"] {
        let h = scene.body(insulator).unwrap();
        let n = layer.graph().try_node_of_body(h).unwrap();
        let line = node_line(&dot, n);
        assert!(line.contains(&format!("\\n{insulator}\"")), "{line}");
        assert!(line.contains("style=filled"), "{line}");
        assert!(outside.contains(line), "{insulator} outside every cluster");
        // Shared: touched by a body of each pile.
        let piles: Vec<char> = layer
            .graph()
            .touching(n)
            .filter_map(|m| label(m)?.chars().next())
            .collect();
        assert!(
            piles.contains(&'l') && piles.contains(&'r'),
            "{insulator}: {piles:?}"
        );
    }

    // Deterministic and stable.
    let mut again = scenes::two_piles_with_wall();
    let layer2 = run(&mut again, 100);
    assert_eq!(to_dot(&layer2, &options), dot);
    assert_eq!(
        graph_to_dot(layer.graph(), Some(layer.groups()), &options),
        dot[dot.find('\n').unwrap() + 1..]
    );
}

#[test]
fn non_touching_edges_are_dashed_grey_and_optional() {
    // Two touching balls flying apart: the pair outlives the contact for a few
    // steps (proximity only), and the edge outlives the pair until the obsolete
    // test removes it.
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::ZERO;
    let (a, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
    let (b, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(1.0, 0.0, 0.0))
            .linvel(Vector::new(1.0, 0.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    // Proximity edges exist under proximity tracking only.
    let mut layer = ContactLayer::with_tracking(crate::coherence::Tracking::Proximity);
    layer.step(&mut world);
    assert!(layer.graph().edge_of_bodies(a, b).unwrap().is_touching());
    let mut proximate = false;
    for _ in 0..30 {
        layer.step(&mut world);
        let edge = layer.graph().edge_of_bodies(a, b).expect("an edge");
        if !edge.is_touching() {
            proximate = edge.is_proximate();
            break;
        }
    }
    let (na, nb) = (
        layer.graph().try_node_of_body(a).unwrap(),
        layer.graph().try_node_of_body(b).unwrap(),
    );

    let dot = to_dot(&layer, &DotOptions::default());
    let line = edge_line(&dot, na, nb);
    let grey = if proximate { "grey50" } else { "grey80" };
    assert!(
        line.contains("style=dashed") && line.contains(grey),
        "{line}"
    );
    assert_eq!(
        dot.matches("subgraph cluster_").count(),
        2,
        "each ball alone"
    );

    let lean = to_dot(
        &layer,
        &DotOptions {
            proximity_edges: false,
            ..DotOptions::default()
        },
    );
    assert!(!lean.contains(" -- "), "{lean}");
}

#[test]
fn names_are_escaped() {
    assert_eq!(escape("plain"), "plain");
    assert_eq!(escape(r#"say "hi""#), r#"say \"hi\""#);
    assert_eq!(escape(r"back\slash"), r"back\\slash");
    assert_eq!(escape("two\r\nlines"), r"two\nlines");

    let mut world = PhysicsWorld::new();
    world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::ball(0.5));
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let label = |_| Some("a \"quoted\" \\ name".to_string());
    let dot = to_dot(
        &layer,
        &DotOptions {
            label: Some(&label),
            ..DotOptions::default()
        },
    );
    assert!(dot.contains(r#"label="F0\na \"quoted\" \\ name""#), "{dot}");
}

#[test]
fn empty_graph() {
    let dot = graph_to_dot(&ContactGraph::new(), None, &DotOptions::default());
    assert!(dot.starts_with("graph contact_graph {"));
    assert!(!dot.contains(" -- ") && !dot.contains("cluster"));
}
