//! Splitting a group after a contact ended: the bounded local search from both ends
//! (Rapier's `island_manager/local_split.rs`), the move of a finished side to a new
//! group, and the deferred full split, one per step.

use std::collections::BTreeMap;

use crate::graph::{ContactGraph, NodeId};

use super::{traversable, Group, GroupId, Groups, Insulates};

/// How a local search ended.
enum Search {
    /// The two ends still reach each other, or the search could not tell.
    Joined,
    /// Side `0` or `1` ran out of nodes: its front holds a whole component, each of
    /// its nodes stamped with the given stamp.
    Apart(usize, u64),
    /// The budget ran out first.
    Undecided,
}

impl Groups {
    /// After the step's ended edges left their groups: checks that each group they
    /// left is still connected, splitting off what is not.
    ///
    /// A group that was connected stays connected exactly when the two ends of every
    /// ended edge still reach each other (a path of the old group can detour around
    /// each ended edge). So each ended edge is checked by a bounded search from both
    /// ends at once, alternating one node expansion each over the group's joining
    /// edges: a side that meets the other settles it (joined); a side that runs out of
    /// nodes first is a whole *part* of the new graph, and moves to a new group; a
    /// search exceeding the budget defers the group to a full split.
    ///
    /// Once a part has left, the rest may have been held together only through it.
    /// Every piece the rest may have fallen into touches a part by an ended edge (a
    /// piece without one kept all its edges, and the group was connected), so the
    /// rest's ends of the ended edges to one part (or to parts linked by ended edges:
    /// a *class*) must reach each other, and are joined pairwise by the same search.
    /// What splits off there is a part too, and joins the class of the seeds it took;
    /// this repeats until nothing splits. The ends around one part are neighbours of
    /// it, so these searches are short.
    ///
    /// Cost: O(ended edges) searches, each O(smaller side), at most O(budget × degree).
    // Long: the two-sided searches and their deferral share the step's ended edges and budget.
    pub(super) fn cut_all(&mut self, graph: &mut ContactGraph, step: u64) {
        let group = |graph: &ContactGraph, n: NodeId| graph.node(n).and_then(|n| n.group);
        // Parts split off this step, as a union-find of classes; seeds by class.
        let mut class: BTreeMap<GroupId, GroupId> = BTreeMap::new();
        let mut seeds: Vec<(GroupId, NodeId)> = Vec::new();
        let cuts = std::mem::take(&mut self.cuts);
        for &(a, b) in &cuts {
            let (ga, gb) = (group(graph, a), group(graph, b));
            let Some(gid) = ga.filter(|_| ga == gb) else {
                // Apart already: at least one end is in a part that left this step.
                let (pa, pb) = (
                    ga.filter(|g| class.contains_key(g)),
                    gb.filter(|g| class.contains_key(g)),
                );
                match (pa, pb) {
                    (Some(x), Some(y)) => union(&mut class, x, y),
                    (Some(x), None) => seeds.push((x, b)),
                    (None, Some(y)) => seeds.push((y, a)),
                    (None, None) => {} // rebuilt by traversal this step: exact
                }
                continue;
            };
            if self.deferred.contains(&gid) {
                continue; // its full split covers this edge
            }
            match self.search(graph, gid, a, b) {
                Search::Joined => {}
                Search::Apart(side, stamp) => {
                    let stay = if side == 0 { b } else { a };
                    let part = self.split_off(graph, gid, side, stamp, step);
                    class.insert(part, part);
                    seeds.push((part, stay));
                }
                Search::Undecided => self.deferred.push(gid),
            }
        }
        self.cuts = cuts;
        // The seeds of each class, in the group each is in now, joined pairwise.
        loop {
            // A seed taken by a part links its class to the part.
            seeds.retain(|&(c, n)| match group(graph, n) {
                Some(g) if class.contains_key(&g) => {
                    union(&mut class, c, g);
                    false
                }
                Some(_) => true,
                None => false,
            });
            let mut keyed: Vec<(GroupId, GroupId, NodeId)> = seeds
                .iter()
                .filter_map(|&(c, n)| Some((find(&class, c), group(graph, n)?, n)))
                .collect();
            keyed.sort_unstable();
            keyed.dedup();
            let mut split = false;
            let mut kept: Vec<(GroupId, NodeId)> = Vec::with_capacity(keyed.len());
            let mut i = 0;
            while i < keyed.len() {
                let (c, gid, first) = keyed[i];
                kept.push((c, first));
                let mut j = i + 1;
                while j < keyed.len() && (keyed[j].0, keyed[j].1) == (c, gid) {
                    let next = keyed[j].2;
                    j += 1;
                    if split || self.deferred.contains(&gid) {
                        kept.push((c, next));
                        continue;
                    }
                    match self.search(graph, gid, first, next) {
                        Search::Joined => {} // `first` stands for both from now on
                        Search::Apart(side, stamp) => {
                            let part = self.split_off(graph, gid, side, stamp, step);
                            class.insert(part, part);
                            union(&mut class, c, part);
                            kept.push((c, next));
                            split = true;
                        }
                        Search::Undecided => {
                            self.deferred.push(gid);
                            kept.push((c, next));
                        }
                    }
                }
                i = j;
            }
            seeds = kept;
            if !split {
                break;
            }
        }
    }

    /// The bounded two-sided search of [`Self::cut_all`]; the fronts are left in
    /// `self.fronts` (all nodes each side reached, in order).
    fn search(&mut self, graph: &mut ContactGraph, gid: GroupId, a: NodeId, b: NodeId) -> Search {
        let stamps = [self.next_stamp(graph), self.next_stamp(graph)];
        let mut fronts = std::mem::take(&mut self.fronts);
        for (f, (n, s)) in fronts.iter_mut().zip([(a, stamps[0]), (b, stamps[1])]) {
            f.clear();
            f.push(n);
            if let Some(node) = graph.node_mut(n) {
                node.visit_stamp = s;
            }
        }
        let mut heads = [0usize; 2];
        let mut budget = self.budget;
        let mut side = 0;
        let outcome = loop {
            if heads[side] == fronts[side].len() {
                break Search::Apart(side, stamps[side]);
            }
            if budget == 0 {
                break Search::Undecided;
            }
            budget -= 1;
            let n = fronts[side][heads[side]];
            heads[side] += 1;
            let (mine, theirs) = (stamps[side], stamps[1 - side]);
            let mut met = false;
            let degree = graph.node(n).map_or(0, |node| node.edges.len());
            for k in 0..degree {
                let Some(eid) = graph.nth_edge(n, k) else {
                    break;
                };
                let Some(e) = graph.edge(eid) else { continue };
                if !traversable(e.kind, e.cache.touching) {
                    continue;
                }
                let Some(m) = e.other(n) else { continue };
                let Some(other) = graph.node_mut(m) else {
                    continue;
                };
                // Members of the group only: insulators belong to none.
                if other.group != Some(gid) || other.visit_stamp == mine {
                    continue;
                }
                if other.visit_stamp == theirs {
                    met = true;
                    break;
                }
                other.visit_stamp = mine;
                fronts[side].push(m);
            }
            if met {
                break Search::Joined;
            }
            side = 1 - side;
        };
        self.fronts = fronts;
        outcome
    }

    /// Moves the nodes of front `side` (a whole component) out of group `gid` into a
    /// new group, with their edges, contacts, insulators and awake count; the part's
    /// nodes carry `stamp`. O(part's members + edges).
    fn split_off(
        &mut self,
        graph: &mut ContactGraph,
        gid: GroupId,
        side: usize,
        stamp: u64,
        step: u64,
    ) -> GroupId {
        let part = std::mem::take(&mut self.fronts[side]);
        self.file_out(gid);
        let mut fresh = Group {
            built_step: step,
            ..Group::default()
        };
        if let Some(g) = self.arena.get_mut(gid.index(), gid.generation()) {
            // Members first (so that an edge's far end tells inside from insulator).
            for &n in &part {
                let Some(node) = graph.node_mut(n) else {
                    continue;
                };
                let slot = node.group_slot as usize;
                let pos = if g.bodies.get(slot) == Some(&n) {
                    Some(slot)
                } else {
                    g.bodies.iter().position(|&m| m == n)
                };
                node.group = None;
                if node.awake {
                    fresh.awake += 1;
                }
                if let Some(pos) = pos {
                    g.take_body_at(graph, pos);
                }
                fresh.bodies.push(n);
            }
            g.awake = g.awake.saturating_sub(fresh.awake);
            // Then the part's edges: those still in `g` reached from a part member.
            for &n in &part {
                let degree = graph.node(n).map_or(0, |node| node.edges.len());
                for k in 0..degree {
                    let Some(eid) = graph.nth_edge(n, k) else {
                        break;
                    };
                    let Some(e) = graph.edge(eid) else { continue };
                    let slot = e.group_slot as usize;
                    if g.edges.get(slot) != Some(&eid) {
                        continue; // not in the group, or moved already
                    }
                    let counted = e.group_counted;
                    let far = e.other(n);
                    g.take_edge_at(graph, slot);
                    if let Some(e) = graph.edge_mut(eid) {
                        e.group_slot = fresh.edges.len() as u32;
                    }
                    fresh.edges.push(eid);
                    g.contacts = g.contacts.saturating_sub(counted);
                    fresh.contacts = fresh.contacts.saturating_add(counted);
                    // A far end outside the part and outside `g` is an insulator.
                    if let Some(far) = far {
                        let outside = graph
                            .node(far)
                            .is_some_and(|f| f.visit_stamp != stamp && f.group != Some(gid));
                        if outside {
                            g.unlink(far);
                            fresh.link(far, 1);
                        }
                    }
                }
            }
            g.built_step = step;
        }
        self.file_in(gid);
        self.changed += 1;
        let id = self.insert(graph, fresh);
        self.fronts[side] = part;
        id
    }

    /// Rebuilds one deferred group by traversal, if any: the one with the fewest
    /// awake members, then the lowest id (deterministic). O(its members + edges).
    pub(super) fn split_one_deferred(
        &mut self,
        graph: &mut ContactGraph,
        step: u64,
        insulates: Insulates,
    ) {
        let arena = &self.arena;
        self.deferred
            .retain(|id| arena.get(id.index(), id.generation()).is_some());
        let pick = self
            .deferred
            .iter()
            .enumerate()
            .filter_map(|(i, &id)| self.get(id).map(|g| (g.awake, id, i)))
            .min();
        if let Some((_, gid, i)) = pick {
            self.deferred.remove(i);
            self.dissolve(graph, gid);
            self.build_from_roots(graph, step, insulates);
        }
    }
}

/// The class of part `g` (union-find without ranks: a step's parts are few).
fn find(class: &BTreeMap<GroupId, GroupId>, mut g: GroupId) -> GroupId {
    // A chain is at most as long as the parts of one step.
    for _ in 0..=class.len() {
        match class.get(&g) {
            Some(&up) if up != g => g = up,
            _ => break,
        }
    }
    g
}

/// Joins the classes of parts `x` and `y` (the smaller id becomes the root).
fn union(class: &mut BTreeMap<GroupId, GroupId>, x: GroupId, y: GroupId) {
    let (rx, ry) = (find(class, x), find(class, y));
    let (root, child) = (rx.min(ry), rx.max(ry));
    if root != child {
        class.insert(child, root);
    }
}
