//! A member turning insulator, or a body turning member, without rebuilding the
//! groups around it: under subgrouping a body becomes an insulator when it turns
//! sleepy and a member again when it stops (paper §7, sleepy objects insulating), and
//! a held body released is a member without a group; in a settling pile one or the
//! other happens somewhere nearly every step. A traversal of the whole group each
//! time would cost O(group) a step; instead:
//! - a member that **turns insulator** leaves its group: its edges to members stay
//!   (they are now the group's edges to an insulator), its edges to insulators leave,
//!   and its member neighbours are searched for a split as the ends of an ended
//!   contact are (`split.rs`). Of the nodes leaving in one step, those that touched
//!   form clusters; the group stays connected exactly when the member neighbours of
//!   each cluster still reach each other, so the searches queued for a leaver pass
//!   on to its neighbours, or, if it has none left, join its searches' other ends;
//! - a body that **turns member** becomes a group of its own, and each of its
//!   joining edges is taken out of the group that held it as an edge to an insulator
//!   and joins as a contact that began: the groups around it merge into one
//!   (`incremental.rs`).
//!
//! Cost: O(the node's edges · log insulators + the step's queued searches) per
//! flip, plus the merges and the bounded split searches this queues.

use crate::graph::{ContactGraph, NodeId};

use super::incremental::group_of_ends;
use super::{member_kind, traversable, Group, GroupId, Groups, Insulates};

impl Groups {
    /// Notes that node `n` may have become a member or stopped being one (under
    /// subgrouping, it became sleepy or stopped being sleepy; a body without a group,
    /// e.g. a held body released): the next update takes it out of its group or into
    /// one. O(1).
    pub(crate) fn membership_changed(&mut self, n: NodeId) {
        self.membership.push(n);
    }

    /// The noted nodes, in node order: a member that insulates now leaves its group,
    /// a member without a group enters one; the others (already where they
    /// belong, in a group dissolved this step, or queued as a root: the traversal
    /// builds those) are left alone. O(noted nodes' edges · log insulators + roots ·
    /// log roots).
    pub(super) fn apply_membership(
        &mut self,
        graph: &mut ContactGraph,
        step: u64,
        insulates: Insulates,
    ) {
        let mut noted = std::mem::take(&mut self.membership);
        if noted.is_empty() {
            self.membership = noted;
            return;
        }
        noted.sort_unstable();
        noted.dedup();
        // New nodes are queued as roots: entering them one by one would only build
        // groups the traversal dissolves again.
        let mut roots = self.roots.clone();
        roots.sort_unstable();
        for &n in &noted {
            let Some(node) = graph.node(n) else { continue };
            let member = member_kind(node.kind) && !node.passive && !insulates(graph, n);
            match (member, node.group) {
                (false, Some(gid)) => self.leave(graph, gid, n, step),
                (true, None) if roots.binary_search(&n).is_err() => self.enter(graph, n, step),
                _ => {}
            }
        }
        noted.clear();
        self.membership = noted;
    }

    /// Takes insulator `n` out of its group `gid`, with its edges to other
    /// insulators; queues its member neighbours, with the other ends of the split
    /// searches queued with `n` as an end, for the split search as a chain.
    /// O(its edges · log insulators + queued searches).
    fn leave(&mut self, graph: &mut ContactGraph, gid: GroupId, n: NodeId, step: u64) {
        let Some(slot) = graph.node(n).map(|m| m.group_slot as usize) else {
            return;
        };
        if self.get(gid).is_none_or(|g| g.bodies.get(slot) != Some(&n)) {
            // Out of step (not expected): the traversal rebuilds the group.
            self.dissolve(graph, gid);
            return;
        }
        // Its edges to insulators leave the group (between two insulators now, in
        // none); those to members stay, as the group's edges to an insulator.
        let mut neighbours: Vec<NodeId> = Vec::new();
        let degree = graph.node(n).map_or(0, |node| node.edges.len());
        for k in 0..degree {
            let Some(eid) = graph.nth_edge(n, k) else {
                break;
            };
            let Some(e) = graph.edge(eid) else { continue };
            let (a, b, at, counted) = (e.a, e.b, e.group_slot, e.group_counted);
            if self
                .get(gid)
                .is_none_or(|g| g.edges.get(at as usize) != Some(&eid))
            {
                continue; // not one of the group's edges
            }
            let Some(m) = e.other(n) else { continue };
            if graph.node(m).and_then(|x| x.group) == Some(gid) {
                neighbours.push(m);
            } else {
                self.take_edge(graph, gid, eid, at, counted, a, b);
            }
        }
        self.file_out(gid);
        let Some(g) = self.arena.get_mut(gid.index(), gid.generation()) else {
            return;
        };
        // One link for each of its edges to a member.
        if !neighbours.is_empty() {
            g.link(n, u32::try_from(neighbours.len()).unwrap_or(u32::MAX));
        }
        g.take_body_at(graph, slot);
        g.built_step = step;
        // Its awake members are counted again in the update's next phase (the leaver's
        // awake flag may have changed this step, after it was last counted).
        let recount = g.bodies.first().copied();
        if let Some(m) = graph.node_mut(n) {
            m.group = None;
            m.group_slot = 0;
        }
        match recount {
            Some(m) => {
                self.file_in(gid);
                self.flips.push(m);
            }
            None => {
                self.arena.remove(gid.index(), gid.generation());
            }
        }
        self.changed += 1;
        // The split searches queued already with `n` as an end (an edge of `n` that
        // ended this step, or an earlier leaver's neighbours) were for what `n` joined:
        // their other ends join `n`'s member neighbours. All of them must still reach
        // each other, and a chain of searches checks it.
        let mut ends = neighbours;
        self.cuts.retain(|&(a, b)| {
            if a == n || b == n {
                ends.push(if a == n { b } else { a });
                false
            } else {
                true
            }
        });
        ends.retain(|&m| m != n);
        ends.sort_unstable();
        ends.dedup();
        for pair in ends.windows(2) {
            self.cuts.push((pair[0], pair[1]));
        }
    }

    /// Makes member `n` a group of its own, and queues its joining edges as contacts
    /// that began (each taken first out of the group that held it as an edge to `n`,
    /// the insulator), so that the update's merges join the groups around it.
    /// O(its edges · log insulators).
    fn enter(&mut self, graph: &mut ContactGraph, n: NodeId, step: u64) {
        let degree = graph.node(n).map_or(0, |node| node.edges.len());
        for k in 0..degree {
            let Some(eid) = graph.nth_edge(n, k) else {
                break;
            };
            let Some(e) = graph.edge(eid) else { continue };
            if !traversable(e.kind, e.cache.touching) {
                continue;
            }
            // Held by a member's group as its edge to `n`, the insulator: out first.
            let (a, b, slot, counted) = (e.a, e.b, e.group_slot, e.group_counted);
            if let Some(holder) = group_of_ends(graph, a, b) {
                self.take_edge(graph, holder, eid, slot, counted, a, b);
            }
            self.began.push(eid);
        }
        let awake = graph.node(n).is_some_and(|m| m.awake);
        self.insert(
            graph,
            Group {
                bodies: vec![n],
                awake: u32::from(awake),
                built_step: step,
                ..Group::default()
            },
        );
    }
}
