//! Bad-input audit (see `tests/common/audit.rs`): the layer's queries —
//! `node_of_body`, a node's kind, `is_supported`, `insulates`, `node_of_collider`,
//! `validate` (of a world or a view) against a foreign world, the accessors of a fresh
//! layer and the errors' messages, and `Groups::get` with a dissolved group.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, EdgeId, Error, NodeId, NodeKind, WorldView};

use common::audit::*;
use common::build::*;

#[test]
fn layer_node_queries_with_bad_ids() {
    let (mut world, _, ball, mut layer) = stepped_proximity(2);
    let (stale, removed) = stale_node(&mut layer, &mut world);
    for f in [removed].into_iter().chain(foreign_bodies(ball)) {
        // Checked against the world, and as of the last step: alike here.
        assert_eq!(
            layer.node_of_body(&world.bodies, f),
            Err(Error::UnknownBody(f))
        );
        assert_eq!(
            layer.graph().try_node_of_body(f),
            Err(Error::UnknownBody(f))
        );
    }
    let b = layer.node_of_body(&world.bodies, ball).unwrap();
    for n in [stale].into_iter().chain(foreign_nodes(b)) {
        assert_eq!(
            layer.graph().try_node(n).map(|x| x.kind()),
            Err(Error::StaleNode(n))
        );
        assert_eq!(layer.analysis().is_supported(n), Err(Error::StaleNode(n)));
        assert!(!layer.analysis().insulates(n));
    }
    assert_eq!(
        layer.graph().try_node(b).map(|x| x.kind()),
        Ok(NodeKind::Dynamic)
    );
    // Non-finite gravity of the last analysed world: an error, not an answer.
    world.gravity = Vector::splat(Real::NAN);
    layer.step(&mut world);
    assert_eq!(
        layer.analysis().is_supported(b),
        Err(Error::NonFinite("gravity"))
    );
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
    let (h, hc) = ball_at(&mut world, [3.0, 1.0, 0.0], 0.5);
    layer.step(&mut world);
    assert!(layer.node_of_collider(&world, hc).is_ok());
    world.remove_body(h);
    layer.step(&mut world);
    assert_eq!(
        layer.node_of_collider(&world, hc),
        Err(Error::UnknownCollider(hc))
    );
    // A world the layer never saw, not told apart here (see `Error::ForeignWorld`):
    // answered from that world's parent handle, a body this layer has no node for
    // (or an alias of a body of the same slot: handles carry no world).
    let mut other = PhysicsWorld::new();
    for _ in 0..5 {
        other.insert_body(RigidBodyBuilder::dynamic());
    }
    let (_, oc) = other.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(1.0));
    assert_eq!(
        layer.node_of_collider(&other, oc),
        Err(Error::UnseenCollider(oc))
    );
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
    // Users of their own sets pass a view of them.
    let view = WorldView::from(&world);
    assert_eq!(layer.node_of_collider(view, s), Ok(trigger));
}

#[test]
fn validate_against_a_foreign_world_is_an_error() {
    let (_, _, _, layer) = stepped(5);
    let empty = PhysicsWorld::new();
    let other = foreign_world(4);
    for w in [&empty, &other] {
        let r = no_panic("validate(foreign world)", || layer.validate(w));
        // Another world with bodies is `ForeignWorld`; the empty world has none to
        // compare, and is checked against the graph (`Error::ForeignWorld`'s limits).
        if w.bodies.is_empty() {
            assert!(matches!(r, Err(Error::Invariant(_))), "{r:?}");
        } else {
            assert_eq!(r, Err(Error::ForeignWorld));
        }
        let view = WorldView {
            gravity: Vector::splat(Real::NAN),
            dt: Real::NAN,
            ..WorldView::from(w)
        };
        assert!(no_panic("validate_view", || layer.validate(&view)).is_err());
    }
}

#[test]
fn accessors_on_a_fresh_layer_and_error_messages() {
    let layer = ContactLayer::default();
    assert_eq!(layer.graph().node_count(), 0);
    assert!(layer.groups().is_empty());
    assert_eq!(layer.analysis().stats().step, 0);
    assert_eq!(layer.analysis().current_step(), 0);
    assert_eq!(layer.analysis().touched_edges().count(), 0);
    assert!(
        layer.analysis().removed_edges().is_empty() && layer.analysis().removed_nodes().is_empty()
    );
    assert!(layer.last_events().is_empty());
    assert_eq!(layer.analysis().event_bus().len(), 0);
    assert_eq!(layer.analysis().flagged_colliders(), 0);
    assert_eq!(layer.logic().simulated_time(), 0.0);
    assert!(layer.speedups().is_none() && layer.analysis().grouping());
    assert!(layer.hooks().table().is_empty());
    assert!(layer.analysis().coherence().contact_details());
    assert!(layer.logic().refusals().is_empty());
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
                what: "set_body_disabled(true) on a multibody link",
                reason: "Rapier panics",
            },
            "multibody link is not supported: Rapier panics",
        ),
    ] {
        assert!(err.to_string().contains(needle), "{err}");
    }
}

#[test]
fn groups_get_with_stale_group_id() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let b = layer.graph().try_node_of_body(ball).unwrap();
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
