//! The graph's mirror of Rapier's sets: bodies, static colliders and sensors
//! (triggers) become nodes; removed ones go. The coherence analysis and the
//! containers both create nodes through these functions.
//!
//! Why not scan every body every step: a settled scene's step costs Rapier a few
//! microseconds, and the layer must cost in proportion to what moves (`docs/ARCHITECTURE.md` §6). So
//! the per-step work touches only the bodies awake now or awake at the last update
//! (the second set catches bodies that just fell asleep, turned fixed or were removed).
//! A full scan runs only when the number of bodies or colliders changed, or when the
//! user asks for one ([`crate::LayerAnalysisMut::request_full_sync`]) after changing a
//! sleeping or fixed body in place.

use rapier3d::dynamics::{RigidBody, RigidBodyType};
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::{ContactGraph, NodeId, NodeKind, NodeSource, Storage};
use crate::WorldView;

/// The node kind of a Rapier body (paper §2, Tables 1–2).
pub(crate) fn kind_of_body(view: &WorldView, handle: RigidBodyHandle, rb: &RigidBody) -> NodeKind {
    match rb.body_type() {
        RigidBodyType::Fixed => NodeKind::Fixed,
        RigidBodyType::KinematicPositionBased | RigidBodyType::KinematicVelocityBased => {
            NodeKind::Kinematic
        }
        // A soft-body cluster's proxy moves and takes part in contacts like a rigid body.
        RigidBodyType::Dynamic | RigidBodyType::SoftFrame => {
            if view.multibody_joints.rigid_body_link(handle).is_some() {
                NodeKind::Link
            } else {
                NodeKind::Dynamic
            }
        }
    }
}

/// Whether a collider without parent gets its own node: static geometry that takes
/// part in contacts (sensors are the logic layer's business).
pub(crate) fn is_static_collider_node(view: &WorldView, h: ColliderHandle) -> bool {
    view.colliders
        .get(h)
        .is_some_and(|c| c.parent().is_none() && !c.is_sensor())
}

/// Finds or creates the node of a body, fixing its kind; records what was created.
pub(crate) fn ensure_body_node(
    graph: &mut ContactGraph,
    view: &WorldView,
    handle: RigidBodyHandle,
    created: &mut Vec<NodeId>,
) -> Option<NodeId> {
    let rb = view.bodies.get(handle)?;
    Some(ensure_node_of(graph, view, handle, rb, created))
}

/// [`ensure_body_node`] for a body the caller has looked up already (`rb` is
/// `handle`'s): the per-step refresh reads each body once. O(1).
pub(crate) fn ensure_node_of(
    graph: &mut ContactGraph,
    view: &WorldView,
    handle: RigidBodyHandle,
    rb: &RigidBody,
    created: &mut Vec<NodeId>,
) -> NodeId {
    let kind = kind_of_body(view, handle, rb);
    let id = match graph.node_of_body(handle) {
        Some(id) => {
            if graph.node(id).map(|n| n.kind) != Some(kind) {
                graph.set_kind(id, kind);
            }
            id
        }
        None => {
            let id = graph.add_node(kind, NodeSource::Body(handle));
            if let Some(n) = graph.node_mut(id) {
                n.collider_count = rb.colliders().len() as u32;
                n.collider_sig = colliders_sig(rb.colliders());
            }
            created.push(id);
            id
        }
    };
    // Read again only when the collider list moved or changed length (its first
    // collider's shape is then looked up): one compare on the way of every refresh.
    if let Some(n) = graph.node_mut(id) {
        if n.storage.list != Storage::list_of(rb) {
            n.storage = body_storage(view, rb);
        }
    }
    id
}

/// Where Rapier keeps a body's collider list and its first collider's shape
/// ([`Storage`]). O(1).
fn body_storage(view: &WorldView, rb: &RigidBody) -> Storage {
    let first = rb.colliders().first().copied();
    let shape = first
        .and_then(|c| view.colliders.get(c))
        .map_or(0, Storage::shape_of);
    Storage {
        list: Storage::list_of(rb),
        shape: (first, shape),
    }
}

/// The [`Storage`] of a collider standing for its own node (static geometry, a
/// sensor). O(1).
fn collider_storage(collider: ColliderHandle, c: &rapier3d::geometry::Collider) -> Storage {
    Storage {
        list: (0, 0),
        shape: (Some(collider), Storage::shape_of(c)),
    }
}

/// A signature of a body's collider list (handles and order), never 0: a body that
/// gained and lost colliders, or had one moved to or from it with
/// `ColliderSet::set_parent`, shows a different one even when its collider count is
/// the same. O(its colliders).
pub(crate) fn colliders_sig(colliders: &[ColliderHandle]) -> u64 {
    let mut h = 0x9E37_79B9_7F4A_7C15_u64 ^ colliders.len() as u64;
    for c in colliders {
        let (i, g) = c.into_raw_parts();
        h = (h ^ ((u64::from(i) << 32) | u64::from(g)))
            .wrapping_mul(0x0000_0100_0000_01B3)
            .rotate_left(23);
    }
    h | 1
}

/// A signature of which of a body's colliders are disabled (their own flag or by
/// their parent), 0 when none is: order-insensitive, so a change in the set shows
/// whatever the collider order. O(its colliders), one collider lookup each.
pub(crate) fn disabled_sig(view: &WorldView, colliders: &[ColliderHandle]) -> u64 {
    let mut h = 0u64;
    for &c in colliders {
        if view.colliders.get(c).is_some_and(|co| !co.is_enabled()) {
            let (i, g) = c.into_raw_parts();
            h ^= ((u64::from(i) << 32) | u64::from(g))
                .wrapping_add(0x9E37_79B9_7F4A_7C15)
                .wrapping_mul(0xBF58_476D_1CE4_E5B9)
                | 1;
        }
    }
    h
}

/// Whether a collider still belongs to the node standing for `source` (its parent
/// body's, or its own as static geometry). O(1).
pub(crate) fn owns(view: &WorldView, collider: ColliderHandle, source: NodeSource) -> bool {
    let Some(c) = view.colliders.get(collider) else {
        return false;
    };
    match source {
        NodeSource::Body(h) => c.parent() == Some(h),
        NodeSource::StaticCollider(h) => h == collider && c.parent().is_none() && !c.is_sensor(),
        _ => false,
    }
}

/// The node standing for the body (or static geometry) of a collider, if the graph has
/// it: what [`ensure_collider_owner`] finds, without creating one. `None` for a
/// parentless sensor or an unknown collider. O(1).
pub(crate) fn collider_owner(
    graph: &ContactGraph,
    view: &WorldView,
    collider: ColliderHandle,
) -> Option<NodeId> {
    let c = view.colliders.get(collider)?;
    match c.parent() {
        Some(parent) => graph.node_of_body(parent),
        None if !c.is_sensor() => graph.node_of_static_collider(collider),
        None => None,
    }
}

/// Finds or creates the node standing for the body (or static geometry) of a collider.
pub(crate) fn ensure_collider_owner(
    graph: &mut ContactGraph,
    view: &WorldView,
    collider: ColliderHandle,
    created: &mut Vec<NodeId>,
) -> Option<NodeId> {
    let c = view.colliders.get(collider)?;
    match c.parent() {
        Some(parent) => ensure_body_node(graph, view, parent, created),
        None if !c.is_sensor() => {
            let id = match graph.node_of_static_collider(collider) {
                Some(id) => id,
                None => {
                    let id = graph.add_node(NodeKind::Fixed, NodeSource::StaticCollider(collider));
                    created.push(id);
                    id
                }
            };
            if let Some(n) = graph.node_mut(id) {
                n.storage = collider_storage(collider, c);
            }
            Some(id)
        }
        None => None,
    }
}

/// Finds or creates the trigger node of a sensor collider.
pub(crate) fn ensure_trigger_node(
    graph: &mut ContactGraph,
    view: &WorldView,
    collider: ColliderHandle,
    created: &mut Vec<NodeId>,
) -> Option<NodeId> {
    let c = view.colliders.get(collider)?;
    if !c.is_sensor() {
        return None;
    }
    let id = match graph.node_of_sensor(collider) {
        Some(id) => {
            // The sensor may have been moved to another body in place.
            if let Some(n) = graph.node_mut(id).filter(|n| n.carrier != c.parent()) {
                n.carrier = c.parent();
            }
            id
        }
        None => {
            let id = graph.add_node(NodeKind::Sensor, NodeSource::Sensor(collider));
            if let Some(n) = graph.node_mut(id) {
                n.carrier = c.parent();
            }
            created.push(id);
            id
        }
    };
    if let Some(n) = graph.node_mut(id) {
        n.storage = collider_storage(collider, c);
    }
    Some(id)
}

/// Whether the Rapier object behind a node still exists (containers and logical
/// nodes are the layer's own: they exist until the layer removes them).
pub(crate) fn source_exists(view: &WorldView, source: NodeSource) -> bool {
    match source {
        NodeSource::Body(h) => view.bodies.contains(h),
        NodeSource::StaticCollider(h) => is_static_collider_node(view, h),
        NodeSource::Sensor(h) => view.colliders.get(h).is_some_and(|c| c.is_sensor()),
        NodeSource::Container(_) | NodeSource::Layer(_) => true,
    }
}

/// Full scan: one node per body and per static collider, no node without its object.
/// Returns the nodes whose object is gone (the caller removes them and reports), and
/// adds to `resized` the body nodes whose number of colliders changed since the last
/// scan (the caller refreshes them). O(bodies + colliders + nodes).
pub(crate) fn full_sync(
    graph: &mut ContactGraph,
    view: &WorldView,
    created: &mut Vec<NodeId>,
    resized: &mut Vec<NodeId>,
) -> Vec<NodeId> {
    let gone: Vec<NodeId> = graph
        .nodes()
        .filter(|(_, n)| !source_exists(view, n.source))
        .map(|(id, _)| id)
        .collect();
    for (h, rb) in view.bodies.iter() {
        let Some(id) = ensure_body_node(graph, view, h, created) else {
            continue;
        };
        let count = rb.colliders().len() as u32;
        let sig = colliders_sig(rb.colliders());
        if let Some(n) = graph.node_mut(id) {
            if n.collider_count != count || (n.collider_sig != 0 && n.collider_sig != sig) {
                n.collider_count = count;
                resized.push(id);
            }
            n.collider_sig = sig;
        }
    }
    for (h, c) in view.colliders.iter() {
        if c.is_sensor() {
            ensure_trigger_node(graph, view, h, created);
        } else if c.parent().is_none() {
            ensure_collider_owner(graph, view, h, created);
        }
    }
    gone
}
