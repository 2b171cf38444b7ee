//! Bad-input audit (see `tests/common/audit.rs`): `ContactGraph` — node, body,
//! collider and edge lookups, `edge_between`, `neighbors`, `touching`,
//! `try_is_supported`, `supports_of`, the whole-graph calls — and its exports
//! (`export::dot`, `export::text`).

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::export::{dot, text};
use rapier_contact_graph::{
    coherence, ContactGraph, ContactLayer, EdgeId, Error, NodeId, NodeKind, PairKey,
};

use common::audit::*;
use common::build::*;

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
    let floor = static_ground(&mut world);
    let sensor = world.insert_collider(ColliderBuilder::ball(1.0).sensor(true), None);
    let (_, attached) = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5);
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
    let t = layer.logic_mut().add_timer(1.0).unwrap();
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
    let (h, _) = ball_at(&mut world, [3.0, 1.0, 0.0], 0.5);
    for _ in 0..5 {
        layer.step(&mut world);
    }
    let e = layer
        .graph()
        .edge_between(
            layer.graph().try_node_of_body(ground).unwrap(),
            layer.graph().try_node_of_body(h).unwrap(),
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
    let (reuse, _) = ball_at(&mut world, [0.0, 1.0, 2.0], 0.5);
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
    let (mut world, _, ball, mut layer) = stepped_proximity(30);
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
    let (_, _, ball, layer) = stepped_proximity(30);
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
    let (_, _, ball, layer) = stepped_proximity(30);
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
    let (mut world, _, ball, mut layer) = stepped_proximity(30);
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
    assert_eq!(g.nodes_of_kind(NodeKind::Dynamic).count(), 1);
    // The obsolete test on non-finite boxes: never obsolete.
    use rapier3d::parry::bounding_volume::Aabb;
    let nan = Aabb::new(Vector::splat(Real::NAN), Vector::splat(Real::NAN));
    let unit = Aabb::new(Vector::ZERO, Vector::ONE);
    assert!(!coherence::aabbs_obsolete(&nan, &unit) && !coherence::aabbs_obsolete(&unit, &nan));
}

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
