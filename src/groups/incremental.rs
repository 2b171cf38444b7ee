//! One step of the groups: edges leave their groups, dissolved groups are rebuilt,
//! sleep is counted again where it changed, groups merge where contacts began, split
//! where they ended (see [`super::split`]), and contact counts follow the edges.

use crate::graph::{ContactGraph, EdgeId, EdgeKind, NodeId, NO_SLOT};

use super::{member_kind, traversable, GroupId, Groups, Insulates};

impl Groups {
    /// Brings the groups up to date with the step's changes (the queued roots, the
    /// edges that began or stopped joining, the removed edges the graph recorded, the
    /// awake flags that changed), then follows the contact counts of `touched`
    /// edges. Cost: O(removed and changed edges) for the bookkeeping, plus O(smaller
    /// group) per merge, O(smaller part) per local split (at most the split budget
    /// per ended edge), O(members) of every dissolved group, of every group whose
    /// sleep changed and of at most one deferred group, plus O(awake groups) for the
    /// statistics.
    pub(crate) fn update(
        &mut self,
        graph: &mut ContactGraph,
        step: u64,
        insulates: Insulates,
        touched: &[EdgeId],
    ) {
        // Nothing began, ended, woke, slept or was disturbed, and no split waits: the
        // groups stand as they are (a settled or held scene pays O(1) here, and
        // O(awake groups) for the statistics as always).
        if graph.left.is_empty()
            && self.ended.is_empty()
            && self.roots.is_empty()
            && self.flips.is_empty()
            && self.membership.is_empty()
            && self.began.is_empty()
            && self.deferred.is_empty()
            && touched.is_empty()
        {
            self.changed = 0;
            self.update_stats(0);
            return;
        }
        self.changed = 0;
        self.cuts.clear();
        // 1. Edges that left: removed from the graph, or no longer touching.
        for left in std::mem::take(&mut graph.left) {
            let Some(gid) = group_of_ends(graph, left.a, left.b) else {
                continue;
            };
            if self.take_edge(graph, gid, left.id, left.slot, left.counted, left.a, left.b) {
                self.cuts.push((left.a, left.b));
            }
        }
        for eid in std::mem::take(&mut self.ended) {
            let Some(e) = graph.edge(eid) else { continue };
            if traversable(e.kind, e.cache.touching) || e.group_slot == NO_SLOT {
                continue;
            }
            let (a, b, slot, counted) = (e.a, e.b, e.group_slot, e.group_counted);
            let Some(gid) = group_of_ends(graph, a, b) else {
                continue;
            };
            if self.take_edge(graph, gid, eid, slot, counted, a, b) {
                self.cuts.push((a, b));
            }
        }
        // 2. Members turned insulators leave their groups, members without a group
        //    enter (their edges join in 4); then dissolved groups and disturbed nodes,
        //    from scratch.
        self.apply_membership(graph, step, insulates);
        self.build_from_roots(graph, step, insulates);
        // 3. Sleep, where a member's awake flag changed.
        let mut flips = std::mem::take(&mut self.flips);
        let mut regroup: Vec<GroupId> = flips
            .iter()
            .filter_map(|&n| graph.node(n).and_then(|n| n.group))
            .collect();
        regroup.sort_unstable();
        regroup.dedup();
        for gid in regroup {
            self.recount_awake(graph, gid);
        }
        flips.clear();
        self.flips = flips;
        // 4. Merges where contacts began.
        for eid in std::mem::take(&mut self.began) {
            self.join(graph, eid, step, insulates);
        }
        // A member left without a group by the merges (none expected) is built now.
        self.build_from_roots(graph, step, insulates);
        // 5. Splits where contacts ended: local first, then at most one full split.
        self.cut_all(graph, step);
        self.split_one_deferred(graph, step, insulates);
        // 6. Contact counts of the edges that stayed.
        self.follow_counts(graph, touched);
        self.update_stats(self.changed);
        self.clear_scratch();
    }

    /// Empties the per-step scratch, so that a layer's state between steps is what a
    /// restored one rebuilds. O(1) amortised.
    fn clear_scratch(&mut self) {
        self.cuts.clear();
        for f in &mut self.fronts {
            f.clear();
        }
        self.changed = 0;
    }

    /// Rebuilds every deferred group by traversal. O(members + edges of the
    /// deferred groups).
    pub(crate) fn settle(&mut self, graph: &mut ContactGraph, step: u64, insulates: Insulates) {
        for gid in std::mem::take(&mut self.deferred) {
            self.dissolve(graph, gid);
        }
        self.build_from_roots(graph, step, insulates);
        self.update_stats(self.stats.rebuilt + self.changed);
        self.clear_scratch();
    }

    /// Counts group `gid`'s awake members again. O(members).
    fn recount_awake(&mut self, graph: &ContactGraph, gid: GroupId) {
        let Some(g) = self.get(gid) else { return };
        let awake = g
            .bodies
            .iter()
            .filter(|&&n| graph.node(n).is_some_and(|n| n.awake))
            .count() as u32;
        if g.awake == awake {
            return;
        }
        self.file_out(gid);
        if let Some(g) = self.get_mut(gid) {
            g.awake = awake;
        }
        self.file_in(gid);
    }

    /// Takes edge `eid` (between `a` and `b`) out of group `gid`: its contacts, and its
    /// insulator's link. `slot` is where the edge was; the list is searched only if
    /// the edge moved since it was removed from the graph. Returns whether both ends
    /// are members of the group (a split is then possible). O(1), O(edges) when the
    /// slot is stale.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn take_edge(
        &mut self,
        graph: &mut ContactGraph,
        gid: GroupId,
        eid: EdgeId,
        slot: u32,
        counted: u32,
        a: NodeId,
        b: NodeId,
    ) -> bool {
        let Some(g) = self.arena.get(gid.index(), gid.generation()) else {
            return false;
        };
        let pos = if g.edges.get(slot as usize) == Some(&eid) {
            slot as usize
        } else if graph.edge(eid).is_some() {
            return false; // a live edge's slot is exact: not in this group
        } else {
            match g.edges.iter().position(|&e| e == eid) {
                Some(p) => p,
                None => return false,
            }
        };
        let in_a = graph.node(a).and_then(|n| n.group) == Some(gid);
        let in_b = graph.node(b).and_then(|n| n.group) == Some(gid);
        self.file_out(gid);
        if let Some(g) = self.arena.get_mut(gid.index(), gid.generation()) {
            g.take_edge_at(graph, pos);
            g.contacts = g.contacts.saturating_sub(counted);
            match (in_a, in_b) {
                (true, false) => g.unlink(b),
                (false, true) => g.unlink(a),
                _ => {}
            }
            g.built_step = graph.clock; // the step being analysed
        }
        if let Some(e) = graph.edge_mut(eid) {
            e.group_slot = NO_SLOT;
            e.group_counted = 0;
        }
        self.file_in(gid);
        in_a && in_b
    }

    /// Adds edge `eid`, which began joining, to its group, merging the groups of its
    /// ends if they differ. O(1), or O(smaller group) for a merge.
    fn join(&mut self, graph: &mut ContactGraph, eid: EdgeId, step: u64, insulates: Insulates) {
        let Some(e) = graph.edge(eid) else { return };
        if !traversable(e.kind, e.cache.touching) {
            return;
        }
        let (a, b, slot, counted) = (e.a, e.b, e.group_slot, e.cache.contact_count);
        let member = |graph: &ContactGraph, n: NodeId| {
            graph
                .node(n)
                .is_some_and(|node| member_kind(node.kind) && !node.passive)
                && !insulates(graph, n)
        };
        let (ma, mb) = (member(graph, a), member(graph, b));
        let ga = graph.node(a).and_then(|n| n.group).filter(|_| ma);
        let gb = graph.node(b).and_then(|n| n.group).filter(|_| mb);
        // A member without a group (none expected: new and changed nodes are roots)
        // is built by traversal, which takes this edge too.
        if (ma && ga.is_none()) || (mb && gb.is_none()) {
            for (m, g, n) in [(ma, ga, a), (mb, gb, b)] {
                if m && g.is_none() {
                    self.roots.push(n);
                }
            }
            return;
        }
        let Some(first) = ga.or(gb) else {
            return; // between two insulators
        };
        if self
            .get(first)
            .is_some_and(|g| g.edges.get(slot as usize) == Some(&eid))
        {
            return; // taken already (by a traversal this step)
        }
        let gid = match (ga, gb) {
            (Some(x), Some(y)) if x != y => self.merge(graph, x, y, step),
            _ => first,
        };
        self.file_out(gid);
        if let Some(g) = self.arena.get_mut(gid.index(), gid.generation()) {
            let slot = g.edges.len() as u32;
            g.edges.push(eid);
            g.contacts = g.contacts.saturating_add(counted);
            if !ma {
                g.link(a, 1);
            } else if !mb {
                g.link(b, 1);
            }
            g.built_step = step;
            if let Some(e) = graph.edge_mut(eid) {
                e.group_slot = slot;
                e.group_counted = counted;
            }
        }
        self.file_in(gid);
        self.changed += 1;
    }

    /// Merges the smaller of groups `x` and `y` into the larger (by members; the lower
    /// id on a tie) and returns the survivor. O(smaller group's members + edges +
    /// insulators × log).
    fn merge(&mut self, graph: &mut ContactGraph, x: GroupId, y: GroupId, step: u64) -> GroupId {
        let size = |id: GroupId| self.get(id).map_or(0, |g| g.bodies.len());
        let (keep, gone) = match size(x).cmp(&size(y)) {
            std::cmp::Ordering::Greater => (x, y),
            std::cmp::Ordering::Less => (y, x),
            std::cmp::Ordering::Equal => (x.min(y), x.max(y)),
        };
        self.file_out(gone);
        let Some(small) = self.arena.remove(gone.index(), gone.generation()) else {
            return keep;
        };
        // A deferred group merged into another leaves the union deferred.
        if let Some(i) = self.deferred.iter().position(|&d| d == gone) {
            if self.deferred.contains(&keep) {
                self.deferred.remove(i);
            } else {
                self.deferred[i] = keep;
            }
        }
        self.file_out(keep);
        if let Some(g) = self.arena.get_mut(keep.index(), keep.generation()) {
            for n in small.bodies {
                if let Some(node) = graph.node_mut(n) {
                    node.group = Some(keep);
                    node.group_slot = g.bodies.len() as u32;
                }
                g.bodies.push(n);
            }
            for e in small.edges {
                if let Some(edge) = graph.edge_mut(e) {
                    edge.group_slot = g.edges.len() as u32;
                }
                g.edges.push(e);
            }
            for (n, c) in small.insulators.into_iter().zip(small.links) {
                g.link(n, c);
            }
            g.contacts = g.contacts.saturating_add(small.contacts);
            g.awake = g.awake.saturating_add(small.awake);
            g.built_step = step;
        }
        self.file_in(keep);
        self.changed += 1;
        keep
    }

    /// Follows the contact counts of the step's touched edges that stayed in their
    /// groups, by differences. O(touched edges).
    fn follow_counts(&mut self, graph: &mut ContactGraph, touched: &[EdgeId]) {
        for &eid in touched {
            let Some(e) = graph.edge(eid) else { continue };
            if e.kind != EdgeKind::Physical || e.group_slot == NO_SLOT {
                continue;
            }
            let (now, counted, slot) = (e.cache.contact_count, e.group_counted, e.group_slot);
            if now == counted {
                continue;
            }
            let Some(gid) = group_of_ends(graph, e.a, e.b) else {
                continue;
            };
            if self
                .get(gid)
                .is_none_or(|g| g.edges.get(slot as usize) != Some(&eid))
            {
                continue;
            }
            self.file_out(gid);
            if let Some(g) = self.get_mut(gid) {
                g.contacts = g.contacts.saturating_sub(counted).saturating_add(now);
            }
            self.file_in(gid);
            if let Some(e) = graph.edge_mut(eid) {
                e.group_counted = now;
            }
        }
    }
}

/// The group holding an edge between `a` and `b`: the group of a member end.
pub(super) fn group_of_ends(graph: &ContactGraph, a: NodeId, b: NodeId) -> Option<GroupId> {
    graph
        .node(a)
        .and_then(|n| n.group)
        .or_else(|| graph.node(b).and_then(|n| n.group))
}
