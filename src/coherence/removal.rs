//! Node removal in the analysis: the edges a removed node or a kind change drops are
//! reported as ended, and their ends regrouped.

use crate::graph::{ContactGraph, EdgeKind, NodeId};
use crate::groups::Groups;

use super::*;

impl Coherence {
    /// Reports the edges a kind change dropped (ended, with `Vanished` marks) and
    /// regroups their ends.
    pub(crate) fn take_dropped(&mut self, graph: &mut ContactGraph, groups: &mut Groups) {
        let step = self.step;
        graph.drop_disallowed_edges();
        for n in std::mem::take(&mut graph.evicted) {
            self.remove_node(graph, groups, n);
        }
        // Bodies given back before this step: their frozen edges are thawed and
        // counted from this step's events (`held.rs`), not read again.
        self.released_now.sort_unstable();
        for n in std::mem::take(&mut graph.kind_changed) {
            // A held body the user gave another type, or a body touching a held one
            // that now moves: Rapier computes their kept contacts again (and reports
            // them started): they are counted again, unless they are thawed.
            let thawed = self.released_now.binary_search(&n).is_ok();
            let unfreezes = !thawed
                && graph.node(n).is_some_and(|node| {
                    !node.kind().is_insulator()
                        && (node.is_held()
                            || graph.neighbors(n).any(|(m, _, e)| {
                                e.kind() == EdgeKind::Physical
                                    && e.is_touching()
                                    && graph.node(m).is_some_and(|o| o.is_held())
                            }))
                });
            if unfreezes {
                self.stale.push(n);
            }
            self.kind_changes += 1;
            // A body turned from insulator to member (a held body released) joins the
            // groups around it, one turned insulator leaves its group; any other change
            // of kind rebuilds its group.
            match graph
                .node(n)
                .map(|node| (node.kind().is_insulator(), node.group.is_some()))
            {
                Some((false, false) | (true, true)) => groups.membership_changed(n),
                _ => groups.disturb(graph, n),
            }
        }
        for mut e in std::mem::take(&mut graph.dropped) {
            groups.disturb(graph, e.a);
            groups.disturb(graph, e.b);
            if e.cache.proximity {
                e.cache.begin_update(true);
                e.updated_step = step;
                self.removed_edges.push(e);
            }
        }
    }

    pub(super) fn remove_node(
        &mut self,
        graph: &mut ContactGraph,
        groups: &mut Groups,
        id: NodeId,
    ) {
        let Some(node) = graph.node(id) else { return };
        let record = RemovedNode {
            id,
            kind: node.kind,
            source: node.source,
        };
        if let Some(g) = node.group {
            groups.dissolve(graph, g);
        }
        // Neighbours lose an edge: their groups must be rebuilt.
        let neighbours: Vec<NodeId> = graph.neighbors(id).map(|(m, _, _)| m).collect();
        for m in neighbours {
            groups.disturb(graph, m);
        }
        let step = self.step;
        for mut e in graph.remove_node(id) {
            e.cache.begin_update(true);
            e.updated_step = step;
            self.removed_edges.push(e);
        }
        self.removed_nodes.push(record);
    }
}
