//! The paper's traversal (Figs. 7–8), written with an explicit stack (a deep pile
//! would overflow recursion): it builds the groups of the queued roots from scratch.
//! Used for what the incremental rules do not cover (see the module docs) and for
//! the full split of a deferred group.

use crate::graph::{ContactGraph, NodeId};

use super::{member_kind, traversable, Group, Groups, Insulates};

impl Groups {
    /// Builds the groups reachable from the queued roots, dissolving every group a
    /// traversal reaches (a sleeping group reached from an awake one is rebuilt), and
    /// returns how many it built. Cost: O(members + edges of the built groups).
    // Long: the paper's traversal (Figs. 7–8) as one loop over an explicit stack.
    pub(super) fn build_from_roots(
        &mut self,
        graph: &mut ContactGraph,
        step: u64,
        insulates: Insulates,
    ) -> usize {
        if self.roots.is_empty() {
            return 0;
        }
        let stamp = self.next_stamp(graph);
        let mut built = 0;
        let mut r = 0;
        let mut ends: Vec<NodeId> = Vec::new();
        while r < self.roots.len() {
            let root = self.roots[r];
            r += 1;
            let Some(node) = graph.node(root) else {
                continue;
            };
            // A passive body takes part in nothing, groups included.
            if node.visit_stamp == stamp {
                continue; // in a group built by this traversal
            }
            if !member_kind(node.kind) || node.passive || insulates(graph, root) {
                // No longer a member (made passive, turned insulator): out of its group.
                if let Some(old) = node.group {
                    self.dissolve(graph, old);
                }
                continue;
            }
            if let Some(old) = node.group {
                self.dissolve(graph, old);
            }
            let mut group = Group {
                built_step: step,
                ..Group::default()
            };
            ends.clear();
            self.stack.clear();
            self.stack.push(root);
            if let Some(n) = graph.node_mut(root) {
                n.visit_stamp = stamp;
            }
            while let Some(n) = self.stack.pop() {
                group.bodies.push(n);
                let Some(node) = graph.node(n) else { continue };
                if node.awake {
                    group.awake += 1;
                }
                for k in 0..node.edges.len() {
                    let Some(eid) = graph.nth_edge(n, k) else {
                        break;
                    };
                    let Some(e) = graph.edge(eid) else { continue };
                    if !traversable(e.kind, e.cache.touching) || e.colour_stamp == stamp {
                        continue;
                    }
                    let Some(m) = e.other(n) else { continue };
                    let contacts = e.cache.contact_count;
                    let Some(other) = graph.node(m) else { continue };
                    let member = member_kind(other.kind) && !other.passive && !insulates(graph, m);
                    if member && other.visit_stamp != stamp {
                        // The far end's old group goes first: dissolving it afterwards
                        // would take this edge's new place away.
                        if let Some(old) = other.group {
                            self.dissolve(graph, old);
                        }
                        if let Some(o) = graph.node_mut(m) {
                            o.visit_stamp = stamp;
                        }
                        self.stack.push(m);
                    }
                    let slot = group.edges.len() as u32;
                    if let Some(e) = graph.edge_mut(eid) {
                        e.colour_stamp = stamp;
                        e.group_slot = slot;
                        e.group_counted = contacts;
                    }
                    group.edges.push(eid);
                    group.contacts = group.contacts.saturating_add(contacts);
                    if !member {
                        ends.push(m);
                    }
                }
            }
            // Insulators with the number of edges to each.
            ends.sort_unstable();
            for &m in &ends {
                if group.insulators.last() == Some(&m) {
                    if let Some(c) = group.links.last_mut() {
                        *c += 1;
                    }
                } else {
                    group.insulators.push(m);
                    group.links.push(1);
                }
            }
            built += 1;
            self.insert(graph, group);
        }
        self.roots.clear();
        built
    }
}
