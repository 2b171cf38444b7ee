//! The touching oracle: the pairs Rapier's narrow phase says touch
//! (`ContactPair::has_any_active_contact()`), by body or static collider, against the
//! graph's touching edges — written from Rapier's API alone, without the crate's own
//! `validate()` code. Screened as `validate()` screens: pairs a rule of the layer
//! ignores, and pairs with a disabled (passive) body, are left out of both sides; so
//! are pairs no physical edge may join (neither end a dynamic body: Table 2 of the
//! paper, fixed–fixed, kinematic–fixed).

use std::collections::{BTreeSet, HashMap};

use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, EdgeKind, NodeId, NodeKind, Rule};

use super::derived::{given_back_keys, key_of, Key};

fn sorted(a: Key, b: Key) -> (Key, Key) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

/// What a collider stands for: its body, or itself as static geometry; `None` for a
/// sensor or a removed collider.
fn key_of_collider(world: &PhysicsWorld, c: ColliderHandle) -> Option<Key> {
    let co = world.colliders.get(c)?;
    if co.is_sensor() {
        return None;
    }
    Some(match co.parent() {
        Some(b) => {
            let (i, g) = b.into_raw_parts();
            Key::Body(i, g)
        }
        None => {
            let (i, g) = c.into_raw_parts();
            Key::Static(i, g)
        }
    })
}

/// Checks the layer's touching edges against Rapier's touching pairs; returns how
/// many touching pairs were compared.
pub(super) fn touching_agrees(layer: &ContactLayer, world: &PhysicsWorld) -> Result<u64, String> {
    let g = layer.graph();
    let ids: HashMap<Key, NodeId> = g
        .nodes()
        .filter_map(|(id, n)| Some((key_of(n.source())?, id)))
        .collect();
    let rules: Vec<&Rule> = g
        .nodes_of_kind(NodeKind::Rule)
        .filter_map(|(id, _)| layer.logic().rule(id))
        .collect();
    let given_back = given_back_keys(layer);
    let body = |k: Key| match k {
        Key::Body(i, gen) => world.bodies.get(RigidBodyHandle::from_raw_parts(i, gen)),
        _ => None,
    };
    let screened = |a: Key, b: Key| {
        if body(a).is_some_and(|rb| !rb.is_enabled()) || body(b).is_some_and(|rb| !rb.is_enabled())
        {
            return true;
        }
        // A body the speed-ups gave back after the analysis is fixed as the step saw
        // it (Rapier pairs it anew in the next step).
        let dynamic = |k| body(k).is_some_and(|rb| rb.is_dynamic()) && !given_back.contains(&k);
        if !dynamic(a) && !dynamic(b) {
            return true;
        }
        match (ids.get(&a), ids.get(&b)) {
            (Some(&x), Some(&y)) => rules.iter().any(|r| r.ignores(x, y)),
            _ => false,
        }
    };

    let mut rapier = BTreeSet::new();
    let mut pairs = 0;
    for p in world.narrow_phase.contact_pairs() {
        if !p.has_any_active_contact() {
            continue;
        }
        let (Some(a), Some(b)) = (
            key_of_collider(world, p.collider1),
            key_of_collider(world, p.collider2),
        ) else {
            continue;
        };
        if a == b || screened(a, b) {
            continue;
        }
        pairs += 1;
        rapier.insert(sorted(a, b));
    }
    let mut graph = BTreeSet::new();
    for (_, e) in g.edges() {
        if e.kind() != EdgeKind::Physical || !e.is_touching() {
            continue;
        }
        let (Some(na), Some(nb)) = (g.node(e.a()), g.node(e.b())) else {
            return Err(format!(
                "touching edge {:?}–{:?} has a dead end",
                e.a(),
                e.b()
            ));
        };
        let (Some(a), Some(b)) = (key_of(na.source()), key_of(nb.source())) else {
            return Err(format!(
                "touching edge between {:?} and {:?}",
                na.source(),
                nb.source()
            ));
        };
        if !screened(a, b) {
            graph.insert(sorted(a, b));
        }
    }
    if rapier == graph {
        return Ok(pairs);
    }
    let only_rapier: Vec<_> = rapier.difference(&graph).collect();
    let only_graph: Vec<_> = graph.difference(&rapier).collect();
    Err(format!(
        "touching set differs from Rapier's: touching in Rapier without a touching \
         edge {only_rapier:?}; touching edges Rapier does not touch {only_graph:?}"
    ))
}
