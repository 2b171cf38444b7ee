//! Contact groups (paper §3.5, Figs. 7–8): connected components of the contact graph
//! over touching physical edges and structural edges, where fixed and scripted bodies
//! insulate ("they behave as if they had infinite mass").
//!
//! Kept **incrementally**, as Rapier's islands are: merged (smaller into larger) when a
//! contact begins (`incremental.rs`); split lazily when contacts end, each ended edge
//! checked by a bounded two-sided search ([`Groups::DEFAULT_SPLIT_BUDGET`] node
//! expansions) whose smaller side leaves (`split.rs`); a group whose search runs out
//! is deferred, and at most one deferred group a step (the sleepiest) is rebuilt by
//! the paper's traversal (`traverse.rs`; [`crate::LayerAnalysisMut::settle_groups`]
//! rebuilds all). A member turning insulator leaves its group, split as an ended
//! contact would be, and a body turning member (an insulator no longer, or a body
//! without a group) joins the groups around it as a contact that began would
//! (`insulation.rs`: under subgrouping, sleepy bodies; held bodies released).
//! Everything else that changes which bodies may be grouped dissolves the groups
//! concerned and the traversal rebuilds them.
//!
//! **What a query sees.** Exact at the end of every step, except that a deferred
//! group ([`Groups::deferred`], [`GroupStats::deferred`]) may be the union of whole
//! groups until its full split; a union sleeps later, never earlier. Proximity-only
//! edges join no group, a lone body is its own group, insulators belong to none
//! ([`Group::insulators`] lists the ones it rests on). Design, the paper's traversal
//! and the rejected alternatives: `docs/ARCHITECTURE.md` ("Contact groups").
//!
//! Cost: a merge O(smaller group); a split O(smaller part), bounded by the budget; a
//! full split O(members + edges) of one group a step.

mod check;
mod incremental;
mod insulation;
mod split;
mod traverse;

use crate::graph::{Arena, ContactGraph, EdgeId, EdgeKind, NodeId, NodeKind, NO_SLOT};

/// A contact group's id: generational, valid while the group lives. A group lives
/// until it is dissolved (a member removed, made passive or changing kind), merged
/// into a larger group, or rebuilt by a full split; it keeps its id through merges of
/// smaller groups into it, splits that take a part away, and (under subgrouping) a
/// member leaving it as it turns sleepy.
#[repr(transparent)]
#[derive(Copy, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GroupId(u64);

impl std::fmt::Debug for GroupId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "g{}v{}", self.index(), self.generation())
    }
}

impl GroupId {
    fn new(index: u32, generation: u32) -> Self {
        Self(((generation as u64) << 32) | index as u64)
    }
    /// Slot index.
    pub fn index(self) -> u32 {
        self.0 as u32
    }
    /// Generation of the slot.
    pub fn generation(self) -> u32 {
        (self.0 >> 32) as u32
    }
}

/// One contact group.
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Group {
    /// Member nodes (simulated bodies and containers), unordered.
    pub bodies: Vec<NodeId>,
    /// Member edges (touching physical edges, structural edges), unordered.
    pub edges: Vec<EdgeId>,
    /// Insulators (fixed, scripted bodies) the group touches, sorted, without repeats.
    pub insulators: Vec<NodeId>,
    /// Active solver contacts over the group's edges.
    pub contacts: u32,
    /// Contact variables (3 per contact: normal and two friction directions).
    pub variables: u32,
    /// Whether every member is asleep.
    pub asleep: bool,
    /// The step the group's members last changed (built, merged or split).
    pub built_step: u64,
    /// Members awake in Rapier (rebuilt on restore).
    #[cfg_attr(feature = "serde", serde(skip))]
    awake: u32,
    /// For each insulator, the number of the group's edges to it (rebuilt on restore).
    #[cfg_attr(feature = "serde", serde(skip))]
    links: Vec<u32>,
}

impl Group {
    /// Counts one more edge to insulator `n`. O(log insulators + insulators).
    fn link(&mut self, n: NodeId, count: u32) {
        match self.insulators.binary_search(&n) {
            Ok(i) => {
                if let Some(c) = self.links.get_mut(i) {
                    *c = c.saturating_add(count);
                }
            }
            Err(i) => {
                self.insulators.insert(i, n);
                self.links.insert(i.min(self.links.len()), count);
            }
        }
    }

    /// Takes the edge at `pos` out of the list; the last edge takes its place and is
    /// told its new position. O(1).
    fn take_edge_at(&mut self, graph: &mut ContactGraph, pos: usize) {
        self.edges.swap_remove(pos);
        if let Some(e) = self.edges.get(pos).and_then(|&moved| graph.edge_mut(moved)) {
            e.group_slot = pos as u32;
        }
    }

    /// Takes the member at `pos` out of the list, as [`Self::take_edge_at`]. O(1).
    fn take_body_at(&mut self, graph: &mut ContactGraph, pos: usize) {
        self.bodies.swap_remove(pos);
        if let Some(n) = self
            .bodies
            .get(pos)
            .and_then(|&moved| graph.node_mut(moved))
        {
            n.group_slot = pos as u32;
        }
    }

    /// Counts one edge less to insulator `n`; the insulator goes with its last edge.
    fn unlink(&mut self, n: NodeId) {
        if let Ok(i) = self.insulators.binary_search(&n) {
            let left = self.links.get(i).map_or(0, |c| c.saturating_sub(1));
            if left == 0 {
                self.insulators.remove(i);
                if i < self.links.len() {
                    self.links.remove(i);
                }
            } else if let Some(c) = self.links.get_mut(i) {
                *c = left;
            }
        }
    }
}

/// Per-step statistics of the groups, as the paper plots them (Figs. 13–14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GroupStats {
    /// Number of groups (awake and sleeping).
    pub count: usize,
    /// Number of groups with at least one awake member.
    pub awake_groups: usize,
    /// Members of the largest group.
    pub largest_bodies: usize,
    /// Contact variables of the group with the most.
    pub largest_variables: u32,
    /// Contact variables over all groups.
    pub total_variables: u64,
    /// Contact variables of the awake groups (what a solver must handle this step).
    pub awake_variables: u64,
    /// Groups built, merged into or split this step.
    pub rebuilt: usize,
    /// Groups whose split is deferred (see [`Groups::deferred`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub deferred: usize,
}

impl GroupStats {
    /// Mean contact variables per group (0 without groups).
    pub fn mean_variables(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            self.total_variables as f64 / self.count as f64
        }
    }
}

/// The insulator test of a traversal: fixed and scripted bodies, plus whatever the
/// caller adds (sleepy bodies under subgrouping).
pub(crate) type Insulates<'a> = &'a dyn Fn(&ContactGraph, NodeId) -> bool;

/// The contact groups of a scene.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Groups {
    arena: Arena<Group>,
    stamp: u64,
    /// Roots of this step's traversal (scratch).
    roots: Vec<NodeId>,
    stack: Vec<NodeId>,
    stats: GroupStats,
    /// Running totals over sleeping groups, so a settled scene's statistics cost O(1).
    sleeping: SleepingTotals,
    /// The groups with an awake member (their statistics are summed every step).
    awake: std::collections::BTreeSet<GroupId>,
    /// Groups whose split was deferred, oldest first.
    #[cfg_attr(feature = "serde", serde(default))]
    deferred: Vec<GroupId>,
    /// Node expansions a local split may make before it defers.
    #[cfg_attr(feature = "serde", serde(default = "default_budget"))]
    budget: u32,
    /// Edges that began joining this step (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    began: Vec<EdgeId>,
    /// Edges that stopped joining this step and are still in the graph (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    ended: Vec<EdgeId>,
    /// Members whose awake flag changed this step (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    flips: Vec<NodeId>,
    /// Nodes that may have become members or stopped being members this step, as
    /// insulators turning members or members turning insulators (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    membership: Vec<NodeId>,
    /// Ends of the step's ended edges, to be searched for a split (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    cuts: Vec<(NodeId, NodeId)>,
    /// The two search fronts of a local split (scratch).
    #[cfg_attr(feature = "serde", serde(skip))]
    fronts: [Vec<NodeId>; 2],
    /// Groups changed this step (statistics).
    #[cfg_attr(feature = "serde", serde(skip))]
    changed: usize,
}

#[cfg(feature = "serde")]
fn default_budget() -> u32 {
    Groups::DEFAULT_SPLIT_BUDGET
}

impl Default for Groups {
    fn default() -> Self {
        Self {
            arena: Arena::default(),
            stamp: 0,
            roots: Vec::new(),
            stack: Vec::new(),
            stats: GroupStats::default(),
            sleeping: SleepingTotals::default(),
            awake: Default::default(),
            deferred: Vec::new(),
            budget: Self::DEFAULT_SPLIT_BUDGET,
            began: Vec::new(),
            ended: Vec::new(),
            flips: Vec::new(),
            membership: Vec::new(),
            cuts: Vec::new(),
            fronts: Default::default(),
            changed: 0,
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct SleepingTotals {
    count: usize,
    variables: u64,
    largest_bodies: usize,
    largest_variables: u32,
    /// A sleeping group holding a maximum was dissolved: recompute the maxima.
    dirty: bool,
}

/// Whether an edge joins groups: touching physical edges and structural edges.
#[inline]
pub(crate) fn traversable(kind: EdgeKind, touching: bool) -> bool {
    match kind {
        EdgeKind::Physical => touching,
        EdgeKind::Structural => true,
        EdgeKind::Logical | EdgeKind::Geometric => false,
    }
}

/// Whether a node can be a group member.
#[inline]
fn member_kind(kind: NodeKind) -> bool {
    matches!(
        kind,
        NodeKind::Dynamic | NodeKind::Link | NodeKind::Composite | NodeKind::Multibody
    )
}

impl Groups {
    /// Node expansions a local split makes before it defers the group to a full
    /// split: Rapier's own budget (`island_manager/local_split.rs`).
    pub const DEFAULT_SPLIT_BUDGET: u32 = 1024;

    /// The group `id`, if it still lives. O(1).
    pub fn get(&self, id: GroupId) -> Option<&Group> {
        self.arena.get(id.index(), id.generation())
    }

    /// All live groups in slot order. O(slots).
    pub fn iter(&self) -> impl Iterator<Item = (GroupId, &Group)> + '_ {
        self.arena
            .iter()
            .map(|(i, g, grp)| (GroupId::new(i, g), grp))
    }

    /// The awake groups (those not asleep), in id order (generation, then slot).
    /// O(awake groups), however many groups sleep and however many slots the groups
    /// have used.
    pub fn iter_awake(&self) -> impl Iterator<Item = (GroupId, &Group)> + '_ {
        self.awake
            .iter()
            .filter_map(|&id| self.get(id).map(|g| (id, g)))
    }

    /// Number of live groups. O(1).
    pub fn len(&self) -> usize {
        self.arena.len()
    }

    /// Whether there is no group. O(1).
    pub fn is_empty(&self) -> bool {
        self.arena.len() == 0
    }

    /// The statistics of the last update. O(1).
    pub fn stats(&self) -> GroupStats {
        self.stats
    }

    /// The groups whose split is deferred, oldest first: each may hold components that
    /// no longer touch (whole groups of a from-scratch traversal), until its full
    /// split (one per step; see the module docs). O(1).
    pub fn deferred(&self) -> &[GroupId] {
        &self.deferred
    }

    /// Whether group `id`'s split is deferred. O(deferred groups).
    pub fn is_deferred(&self, id: GroupId) -> bool {
        self.deferred.contains(&id)
    }

    /// Node expansions a local split makes before deferring. O(1).
    pub fn split_budget(&self) -> u32 {
        self.budget
    }

    /// Sets the local split budget (0 defers every split that is not settled by the
    /// ended edge's own ends). O(1).
    pub(crate) fn set_split_budget(&mut self, budget: u32) {
        self.budget = budget;
    }

    fn get_mut(&mut self, id: GroupId) -> Option<&mut Group> {
        self.arena.get_mut(id.index(), id.generation())
    }

    /// Takes group `id` out of the statistics (awake set or sleeping totals) before
    /// it changes. O(log groups).
    fn file_out(&mut self, id: GroupId) {
        let Some(g) = self.arena.get(id.index(), id.generation()) else {
            return;
        };
        if g.asleep {
            let t = &mut self.sleeping;
            t.count = t.count.saturating_sub(1);
            t.variables = t.variables.saturating_sub(g.variables as u64);
            if g.bodies.len() >= t.largest_bodies || g.variables >= t.largest_variables {
                t.dirty = true;
            }
        } else {
            self.awake.remove(&id);
        }
    }

    /// Files group `id` into the statistics after it changed, its sleep following its
    /// awake members. O(log groups).
    fn file_in(&mut self, id: GroupId) {
        let Some(g) = self.arena.get_mut(id.index(), id.generation()) else {
            return;
        };
        g.variables = g.contacts.saturating_mul(3);
        g.asleep = g.awake == 0;
        if g.asleep {
            let t = &mut self.sleeping;
            t.count += 1;
            t.variables = t.variables.saturating_add(g.variables as u64);
            t.largest_bodies = t.largest_bodies.max(g.bodies.len());
            t.largest_variables = t.largest_variables.max(g.variables);
        } else {
            self.awake.insert(id);
        }
    }

    /// Inserts a new group and files it. O(members + log groups).
    fn insert(&mut self, graph: &mut ContactGraph, group: Group) -> GroupId {
        let (i, g) = self.arena.insert(group);
        let id = GroupId::new(i, g);
        if let Some(group) = self.arena.get(i, g) {
            for (slot, &n) in group.bodies.iter().enumerate() {
                if let Some(node) = graph.node_mut(n) {
                    node.group = Some(id);
                    node.group_slot = slot as u32;
                }
            }
        }
        self.file_in(id);
        self.changed += 1;
        id
    }

    /// Dissolves a group: its members lose their group and become roots of the next
    /// traversal. O(members + edges).
    pub(crate) fn dissolve(&mut self, graph: &mut ContactGraph, id: GroupId) {
        self.file_out(id);
        if let Some(g) = self.arena.remove(id.index(), id.generation()) {
            for e in g.edges {
                if let Some(e) = graph.edge_mut(e) {
                    e.group_slot = NO_SLOT;
                    e.group_counted = 0;
                }
            }
            for n in g.bodies {
                if let Some(node) = graph.node_mut(n) {
                    if node.group == Some(id) {
                        node.group = None;
                        node.group_slot = 0;
                    }
                    self.roots.push(n);
                }
            }
        }
    }

    /// Sets the traversal stamp (tests of the wrap at the end of its range).
    #[cfg(test)]
    pub(crate) fn set_stamp(&mut self, stamp: u64) {
        self.stamp = stamp;
    }

    /// Forgets the queued work (groups switched off).
    pub(crate) fn clear_queued(&mut self) {
        self.roots.clear();
        self.began.clear();
        self.ended.clear();
        self.flips.clear();
        self.membership.clear();
        self.deferred.clear();
    }

    /// Queues a node as a traversal root, dissolving the group it is in.
    pub(crate) fn disturb(&mut self, graph: &mut ContactGraph, n: NodeId) {
        match graph.node(n).and_then(|node| node.group) {
            Some(g) => self.dissolve(graph, g),
            None => self.roots.push(n),
        }
    }

    /// Notes that edge `e` began (`true`) or stopped (`false`) joining groups this
    /// step (a touch began or ended); the next [`Self::update`] merges or splits.
    /// Edges removed from the graph need no call. O(1).
    pub(crate) fn touch_changed(&mut self, e: EdgeId, began: bool) {
        if began {
            self.began.push(e);
        } else {
            self.ended.push(e);
        }
    }

    /// Notes that node `n`'s awake flag changed: its group's sleep is counted again at
    /// the next [`Self::update`]. O(1).
    pub(crate) fn awake_changed(&mut self, n: NodeId) {
        self.flips.push(n);
    }

    /// A new traversal stamp, clearing every stamp at the end of the
    /// range (reachable only from restored bytes) so that an old stamp never equals a
    /// new one. O(1), or O(nodes + edges) at the wrap.
    fn next_stamp(&mut self, graph: &mut ContactGraph) -> u64 {
        if self.stamp >= u64::MAX - 2 {
            graph.clear_stamps();
            self.stamp = 0;
        }
        self.stamp += 1;
        self.stamp
    }

    /// Combines the awake groups (summed: O(awake groups)) with the running sleeping
    /// totals (O(1), or O(groups) on a step that dissolved a sleeping group holding a
    /// maximum).
    fn update_stats(&mut self, rebuilt: usize) {
        let t = &mut self.sleeping;
        if t.dirty {
            t.dirty = false;
            t.largest_bodies = 0;
            t.largest_variables = 0;
            for (_, _, g) in self.arena.iter().filter(|(_, _, g)| g.asleep) {
                t.largest_bodies = t.largest_bodies.max(g.bodies.len());
                t.largest_variables = t.largest_variables.max(g.variables);
            }
        }
        let mut awake = GroupStats::default();
        for id in &self.awake {
            if let Some(g) = self.arena.get(id.index(), id.generation()) {
                awake.awake_groups += 1;
                awake.awake_variables += g.variables as u64;
                awake.largest_bodies = awake.largest_bodies.max(g.bodies.len());
                awake.largest_variables = awake.largest_variables.max(g.variables);
            }
        }
        self.stats = GroupStats {
            count: awake.awake_groups + t.count,
            awake_groups: awake.awake_groups,
            largest_bodies: awake.largest_bodies.max(t.largest_bodies),
            largest_variables: awake.largest_variables.max(t.largest_variables),
            total_variables: awake.awake_variables + t.variables,
            awake_variables: awake.awake_variables,
            rebuilt,
            deferred: self.deferred.len(),
        };
        debug_assert_eq!(self.stats.count, self.arena.len());
    }
}
