//! Contact groups checked independently of the crate's own traversal.

use std::collections::{BTreeMap, BTreeSet};

use petgraph::unionfind::UnionFind;
use rapier_contact_graph::{ContactLayer, EdgeKind, NodeId};

/// The partition of the member bodies into components, by petgraph's union-find over
/// the joining edges whose ends are not insulators (the from-scratch traversal).
pub fn components(layer: &ContactLayer) -> BTreeSet<BTreeSet<NodeId>> {
    let g = layer.graph();
    let slots = g
        .nodes()
        .map(|(id, _)| id.index() as usize + 1)
        .max()
        .unwrap_or(0);
    let mut uf = UnionFind::<usize>::new(slots);
    let member = |n: NodeId| {
        let node = g.node(n).unwrap();
        node.kind().is_simulated() && !node.is_body_disabled() && !layer.analysis().insulates(n)
    };
    for (_, e) in g.edges() {
        let joins = match e.kind() {
            EdgeKind::Physical => e.is_touching(),
            EdgeKind::Structural => true,
            _ => false,
        };
        if joins && member(e.a()) && member(e.b()) {
            uf.union(e.a().index() as usize, e.b().index() as usize);
        }
    }
    let mut parts: BTreeMap<usize, BTreeSet<NodeId>> = BTreeMap::new();
    for (id, _) in g.nodes() {
        if member(id) {
            parts
                .entry(uf.find(id.index() as usize))
                .or_default()
                .insert(id);
        }
    }
    parts.into_values().collect()
}
