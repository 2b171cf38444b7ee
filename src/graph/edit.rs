//! The graph's writes, crate-internal: the layer owns the graph's consistency.

use super::*;

impl ContactGraph {
    pub(crate) fn add_node(&mut self, kind: NodeKind, source: NodeSource) -> NodeId {
        // A live node still holding the Rapier slot of the new object names an older
        // generation of that slot: its object was removed (and the slot reused).
        let occupant = match source {
            NodeSource::Body(h) => self.body_nodes.get(h.into_raw_parts().0 as usize),
            NodeSource::StaticCollider(h) | NodeSource::Sensor(h) => {
                self.collider_nodes.get(h.into_raw_parts().0 as usize)
            }
            _ => None,
        };
        if let Some(&Some(old)) = occupant {
            if self.node(old).is_some_and(|n| n.source != source) {
                self.evicted.push(old);
            }
        }
        let (i, g) = self.nodes.insert(Node::new(kind, source, self.clock));
        let id = NodeId::from_raw_parts(i, g);
        match source {
            NodeSource::Body(h) => set_slot(&mut self.body_nodes, h.into_raw_parts().0, Some(id)),
            NodeSource::StaticCollider(h) | NodeSource::Sensor(h) => {
                set_slot(&mut self.collider_nodes, h.into_raw_parts().0, Some(id))
            }
            NodeSource::Container(_) | NodeSource::Layer(_) => {}
        }
        self.kind_counts[kind_slot(kind)] += 1;
        id
    }

    /// Changes a node's kind. The edges the new kind does not allow (Table 2: a body
    /// turned fixed keeps no physical edge with another fixed body) are removed by
    /// [`Self::drop_disallowed_edges`] once every kind change of the update is made:
    /// two bodies that swap kinds in one step (one held, its fixed neighbour released)
    /// never form a fixed pair in Rapier, and their touching edge stays. O(1).
    pub(crate) fn set_kind(&mut self, id: NodeId, kind: NodeKind) {
        let old = match self.node_mut(id) {
            Some(n) => std::mem::replace(&mut n.kind, kind),
            None => return,
        };
        self.kind_counts[kind_slot(old)] -= 1;
        self.kind_counts[kind_slot(kind)] += 1;
        self.kind_changed.push(id);
    }

    /// Removes the edges of the nodes whose kind changed that their kinds no longer
    /// allow (Table 2), keeping them in `dropped` for the layer to report. O(the
    /// changed nodes' degrees).
    pub(crate) fn drop_disallowed_edges(&mut self) {
        for i in 0..self.kind_changed.len() {
            let id = self.kind_changed[i];
            let Some(kind) = self.node(id).map(|n| n.kind) else {
                continue;
            };
            let incident = self.node(id).map(|n| n.edges.clone()).unwrap_or_default();
            for eid in incident {
                let Some(e) = self.edge(eid) else { continue };
                let other = if e.a == id { e.b } else { e.a };
                let Some(ok) = self
                    .node(other)
                    .map(|o| validate::edge_allowed(e.kind, kind, o.kind))
                else {
                    continue;
                };
                if !ok && !self.edge(eid).is_some_and(|e| self.is_frozen(e)) {
                    if let Some(e) = self.remove_edge(eid) {
                        self.dropped.push(e);
                    }
                }
            }
        }
    }

    /// Removes a node and its edges; the removed edges are returned (in the node's
    /// edge order) so their vanishing can be reported.
    pub(crate) fn remove_node(&mut self, id: NodeId) -> Vec<Edge> {
        let Some(node) = self.node(id) else {
            return Vec::new();
        };
        let incident = node.edges.clone();
        let removed: Vec<Edge> = incident
            .into_iter()
            .filter_map(|e| self.remove_edge(e))
            .collect();
        if let Some(node) = self.nodes.remove(id.index(), id.generation()) {
            self.kind_counts[kind_slot(node.kind)] -= 1;
            match node.source {
                NodeSource::Body(h) => {
                    let i = h.into_raw_parts().0 as usize;
                    if self.body_nodes.get(i) == Some(&Some(id)) {
                        self.body_nodes[i] = None;
                    }
                }
                NodeSource::StaticCollider(h) | NodeSource::Sensor(h) => {
                    let i = h.into_raw_parts().0 as usize;
                    if self.collider_nodes.get(i) == Some(&Some(id)) {
                        self.collider_nodes[i] = None;
                    }
                }
                NodeSource::Container(_) | NodeSource::Layer(_) => {}
            }
        }
        removed
    }

    /// Makes room for `additional` more edges (the edge slots and the pair index)
    /// before a batch of insertions, so that none reallocates. O(edges) when it grows.
    pub(crate) fn reserve_edges(&mut self, additional: usize) {
        self.edges.reserve(additional);
        self.pairs.reserve(additional);
    }

    /// Inserts the edge `{a, b}` of `kind`, or returns the existing one. Both nodes
    /// must be live and distinct.
    pub(crate) fn ensure_edge(
        &mut self,
        a: NodeId,
        b: NodeId,
        kind: EdgeKind,
        step: u64,
    ) -> Option<EdgeId> {
        if a == b || !self.contains_node(a) || !self.contains_node(b) {
            return None;
        }
        let key = PairKey::of(a, b);
        if let Some(&id) = self.pairs.get(&key) {
            return Some(id);
        }
        let (lo, hi) = if a.index() < b.index() {
            (a, b)
        } else {
            (b, a)
        };
        let (i, g) = self.edges.insert(Edge::new(lo, hi, kind, step));
        let id = EdgeId::from_raw_parts(i, g);
        self.pairs.insert(key, id);
        let geometric = u32::from(kind == EdgeKind::Geometric);
        for n in [lo, hi] {
            if let Some(node) = self.node_mut(n) {
                node.edges.push(id);
                node.geometric_edges = node.geometric_edges.saturating_add(geometric);
            }
        }
        Some(id)
    }

    pub(crate) fn remove_edge(&mut self, id: EdgeId) -> Option<Edge> {
        let edge = self.edges.remove(id.index(), id.generation())?;
        self.pairs.remove(&PairKey::of(edge.a, edge.b));
        if edge.group_slot != NO_SLOT {
            self.left.push(LeftEdge {
                id,
                a: edge.a,
                b: edge.b,
                slot: edge.group_slot,
                counted: edge.group_counted,
            });
        }
        let geometric = u32::from(edge.kind == EdgeKind::Geometric);
        for n in [edge.a, edge.b] {
            if let Some(node) = self.node_mut(n) {
                if let Some(pos) = node.edges.iter().position(|&e| e == id) {
                    node.edges.remove(pos);
                }
                node.geometric_edges = node.geometric_edges.saturating_sub(geometric);
            }
        }
        Some(edge)
    }

    /// Counts each node's geometric edges again from the edges (after a restore: the
    /// counts are not in the bytes). O(nodes + edges).
    #[cfg(feature = "serde")]
    pub(crate) fn recount_geometric(&mut self) {
        for n in self.nodes.values_mut() {
            n.geometric_edges = 0;
        }
        for (_, _, e) in self.edges.iter() {
            if e.kind != EdgeKind::Geometric {
                continue;
            }
            for id in [e.a, e.b] {
                if let Some(n) = self.nodes.get_mut(id.index(), id.generation()) {
                    n.geometric_edges = n.geometric_edges.saturating_add(1);
                }
            }
        }
    }
}
