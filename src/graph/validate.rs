//! The graph's own invariants (the layer adds the checks against Rapier).
//!
//! `validate()` is O(nodes + edges) and meant for tests and debugging: the test suite
//! calls it after every step of every scene.

use super::{Category, ContactGraph, Edge, EdgeKind, Node, NodeId, NodeKind, NodeSource, PairKey};
use crate::{Error, Result};

fn fail<T>(msg: String) -> Result<T> {
    Err(Error::Invariant(msg))
}

/// Whether an edge of `kind` may join nodes of kinds `x` and `y` (Table 2).
pub(crate) fn edge_allowed(kind: EdgeKind, x: NodeKind, y: NodeKind) -> bool {
    let pair = |p: fn(NodeKind) -> bool, q: fn(NodeKind) -> bool| (p(x) && q(y)) || (p(y) && q(x));
    let physical = |k: NodeKind| k.category() == Category::Physical;
    match kind {
        // Physical edges need a body the solver moves: no F–F, S–S, F–S.
        EdgeKind::Physical => physical(x) && physical(y) && (x.is_simulated() || y.is_simulated()),
        // Rules name bodies (Table 2) and, in this crate, triggers too.
        EdgeKind::Logical => pair(
            |k| k == NodeKind::Rule,
            |k| k.category() == Category::Physical || k == NodeKind::Sensor,
        ),
        EdgeKind::Geometric => pair(|k| k == NodeKind::Sensor, physical),
        EdgeKind::Structural => pair(|k| k.category() == Category::Container, physical),
    }
}

/// For each edge, whether its A and its B list it.
type Listed = std::collections::HashMap<crate::EdgeId, (bool, bool), super::PairBuildHasher>;

impl ContactGraph {
    /// Checks every invariant of the graph on its own: edge ends live and sorted,
    /// adjacency lists and the pair map agree with the edge arena, edge kinds agree
    /// with node kinds (Table 2), per-kind counts and the body lookup are right.
    /// O(nodes + edges).
    pub fn validate(&self) -> Result<()> {
        let mut kind_counts = [0usize; 9];
        let mut adjacency_total = 0usize;
        // For each edge, whether its A and its B list it: linear in the adjacency,
        // and catches duplicates and missing entries without a per-node search.
        let mut listed = Listed::default();
        for (id, node) in self.nodes() {
            kind_counts[NodeKind::ALL
                .iter()
                .position(|k| *k == node.kind)
                .unwrap_or(0)] += 1;
            adjacency_total += node.edges.len();
            self.validate_node(id, node, &mut listed)?;
        }
        self.validate_counts(&kind_counts, adjacency_total)?;
        for (eid, e) in self.edges() {
            self.validate_edge(eid, e, &listed)?;
        }
        Ok(())
    }

    /// One node: its geometric edge count, its adjacency (noted in `listed`), its
    /// lookup by source, and no physical or geometric edge while passive.
    fn validate_node(&self, id: NodeId, node: &Node, listed: &mut Listed) -> Result<()> {
        let geometric = node
            .edges
            .iter()
            .filter(|&&e| self.edge(e).is_some_and(|e| e.kind == EdgeKind::Geometric))
            .count();
        if geometric != node.geometric_edges as usize {
            return fail(format!(
                "node {id:?} counts {} geometric edges, has {geometric}",
                node.geometric_edges
            ));
        }
        for &eid in &node.edges {
            let Some(e) = self.edge(eid) else {
                return fail(format!("node {id:?} lists dead edge {eid:?}"));
            };
            if e.a != id && e.b != id {
                return fail(format!("node {id:?} lists edge {eid:?} not incident to it"));
            }
            let seen = listed.entry(eid).or_insert((false, false));
            let flag = if e.a == id { &mut seen.0 } else { &mut seen.1 };
            if *flag {
                return fail(format!("node {id:?} lists edge {eid:?} twice"));
            }
            *flag = true;
        }
        match node.source {
            NodeSource::Body(h) => {
                if self.node_of_body(h) != Some(id) {
                    return fail(format!("body lookup of {h:?} does not give {id:?}"));
                }
            }
            NodeSource::StaticCollider(h) => {
                if self.node_of_static_collider(h) != Some(id) {
                    return fail(format!("collider lookup of {h:?} does not give {id:?}"));
                }
                if node.kind != NodeKind::Fixed {
                    return fail(format!("static collider node {id:?} is not Fixed"));
                }
            }
            NodeSource::Sensor(h) => {
                if self.node_of_sensor(h) != Some(id) || node.kind != NodeKind::Sensor {
                    return fail(format!(
                        "sensor lookup of {h:?} does not give trigger {id:?}"
                    ));
                }
            }
            NodeSource::Container(_) | NodeSource::Layer(_) => {}
        }
        if node.passive && !node.edges.is_empty() {
            let physical = node.edges.iter().any(|&e| {
                self.edge(e)
                    .is_some_and(|e| matches!(e.kind, EdgeKind::Physical | EdgeKind::Geometric))
            });
            if physical {
                return fail(format!(
                    "passive node {id:?} has physical or geometric edges"
                ));
            }
        }
        Ok(())
    }

    /// The per-kind counts, the pair map's size and the adjacency's total against the
    /// nodes and edges.
    fn validate_counts(&self, kind_counts: &[usize; 9], adjacency_total: usize) -> Result<()> {
        for (i, k) in NodeKind::ALL.iter().enumerate() {
            if kind_counts[i] != self.count_of_kind(*k) {
                return fail(format!(
                    "count of {k:?} is {} but {} nodes have it",
                    self.count_of_kind(*k),
                    kind_counts[i]
                ));
            }
        }
        if self.pairs.len() != self.edge_count() {
            return fail(format!(
                "pair map holds {} keys for {} edges",
                self.pairs.len(),
                self.edge_count()
            ));
        }
        if adjacency_total != 2 * self.edge_count() {
            return fail(format!(
                "adjacency lists hold {adjacency_total} entries for {} edges",
                self.edge_count()
            ));
        }
        Ok(())
    }

    /// One edge: live sorted ends, found by its pair and listed by both ends, allowed
    /// between its ends' kinds (Table 2) unless frozen, and a consistent cache.
    fn validate_edge(&self, eid: crate::EdgeId, e: &Edge, listed: &Listed) -> Result<()> {
        let (Some(na), Some(nb)) = (self.node(e.a), self.node(e.b)) else {
            return fail(format!("edge {eid:?} has a dead end"));
        };
        if e.a.index() >= e.b.index() {
            return fail(format!("edge {eid:?} ends are not sorted"));
        }
        if self.edge_by_key(PairKey::of(e.a, e.b)) != Some(eid) {
            return fail(format!("pair map does not give {eid:?}"));
        }
        if listed.get(&eid) != Some(&(true, true)) {
            return fail(format!("edge {eid:?} missing from an adjacency list"));
        }
        if !edge_allowed(e.kind, na.kind, nb.kind) && !self.is_frozen(e) {
            return fail(format!(
                "edge {eid:?} of kind {:?} joins {:?} and {:?}",
                e.kind, na.kind, nb.kind
            ));
        }
        let c = &e.cache;
        if e.kind == EdgeKind::Physical {
            if c.touching && !c.proximity {
                return fail(format!("edge {eid:?} touches without proximity"));
            }
            if c.touching_old && !c.proximity_old {
                return fail(format!("edge {eid:?} touched without proximity (old)"));
            }
            if (c.contact_count > 0) != c.touching {
                return fail(format!(
                    "edge {eid:?}: {} contacts but touching = {}",
                    c.contact_count, c.touching
                ));
            }
            if c.max_penetration < 0.0 || c.max_penetration.is_nan() {
                return fail(format!(
                    "edge {eid:?} has penetration {}",
                    c.max_penetration
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_2_pairs() {
        use NodeKind::*;
        assert!(edge_allowed(EdgeKind::Physical, Dynamic, Fixed));
        assert!(edge_allowed(EdgeKind::Physical, Link, Kinematic));
        assert!(!edge_allowed(EdgeKind::Physical, Fixed, Fixed));
        assert!(!edge_allowed(EdgeKind::Physical, Fixed, Kinematic));
        assert!(!edge_allowed(EdgeKind::Geometric, Sensor, Sensor));
        assert!(edge_allowed(EdgeKind::Geometric, Fixed, Sensor));
        assert!(edge_allowed(EdgeKind::Structural, Multibody, Link));
        assert!(!edge_allowed(EdgeKind::Structural, Multibody, Rule));
        assert!(edge_allowed(EdgeKind::Logical, Rule, Kinematic));
    }
}
