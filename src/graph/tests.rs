//! Unit tests of the graph.

use super::*;

fn body(i: u32) -> RigidBodyHandle {
    RigidBodyHandle::from_raw_parts(i, 0)
}

#[test]
fn edges_are_unique_per_pair_and_found_both_ways() {
    let mut g = ContactGraph::new();
    let a = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(0)));
    let b = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(1)));
    let e1 = g.ensure_edge(b, a, EdgeKind::Physical, 1).unwrap();
    let e2 = g.ensure_edge(a, b, EdgeKind::Physical, 2).unwrap();
    assert_eq!(e1, e2);
    assert_eq!(g.edge_between(a, b), Some(e1));
    assert_eq!(g.edge_between(b, a), Some(e1));
    assert_eq!(g.edge(e1).unwrap().a(), a, "A is the smaller index");
    assert_eq!(g.neighbors(a).count(), 1);
    assert!(g.ensure_edge(a, a, EdgeKind::Physical, 1).is_none());
    g.validate().unwrap();
}

#[test]
fn removing_a_node_removes_its_edges_and_stales_its_id() {
    let mut g = ContactGraph::new();
    let a = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(0)));
    let b = g.add_node(NodeKind::Fixed, NodeSource::Body(body(1)));
    let c = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(2)));
    g.ensure_edge(a, b, EdgeKind::Physical, 0);
    g.ensure_edge(a, c, EdgeKind::Physical, 0);
    let removed = g.remove_node(a);
    assert_eq!(removed.len(), 2);
    assert_eq!(g.edge_count(), 0);
    assert_eq!(g.try_node(a).unwrap_err(), Error::StaleNode(a));
    assert_eq!(g.node_of_body(body(0)), None);
    // Slot reuse does not revive the old id.
    let d = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(3)));
    assert_eq!(d.index(), a.index());
    assert!(g.node(a).is_none());
    assert_eq!(g.edge_between(a, b), None);
    assert_eq!(g.count_of_kind(NodeKind::Dynamic), 2);
    g.validate().unwrap();
}

#[test]
fn body_lookup_checks_generation() {
    let mut g = ContactGraph::new();
    let n = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(4)));
    assert_eq!(g.node_of_body(body(4)), Some(n));
    let newer = RigidBodyHandle::from_raw_parts(4, 1);
    assert_eq!(g.node_of_body(newer), None);
    assert_eq!(g.try_node_of_body(newer), Err(Error::UnknownBody(newer)));
}

#[test]
fn support_follows_normal_orientation() {
    let mut g = ContactGraph::new();
    let ground = g.add_node(NodeKind::Fixed, NodeSource::Body(body(0)));
    let ball = g.add_node(NodeKind::Dynamic, NodeSource::Body(body(1)));
    let e = g.ensure_edge(ground, ball, EdgeKind::Physical, 0).unwrap();
    let gravity = Vector::new(0.0, -9.81, 0.0);
    assert!(!g.try_is_supported(ball, gravity, 0.0).unwrap());
    let c = &mut g.edge_mut(e).unwrap().cache;
    c.touching = true;
    c.normal = Vector::Y; // from A (ground) to B (ball): pushes the ball up.
    assert!(g.try_is_supported(ball, gravity, 0.5).unwrap());
    assert!(!g.try_is_supported(ground, gravity, 0.5).unwrap());
    assert!(!g.try_is_supported(ball, Vector::ZERO, 0.0).unwrap());
}
