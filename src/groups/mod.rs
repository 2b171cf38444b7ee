//! Contact groups (paper §3.5, Figs. 7–8): connected components of the contact graph
//! over touching physical edges and structural edges, where fixed and scripted bodies
//! insulate ("they behave as if they had infinite mass").
//!
//! # Design
//! The traversal is the paper's edge colouring, written with an explicit stack (a
//! deep pile would overflow recursion): an edge is white unless its colour stamp is
//! this traversal's; it turns black when taken into a group. An insulator's edges
//! join the group of the body on the other side but the insulator itself is not
//! expanded, so one floor carries many independent groups.
//!
//! Choices the paper leaves open:
//! - Proximity-only edges do not join groups: they carry no contact variables, and
//!   Rapier's solver does not couple their bodies either.
//! - A simulated body with no touching edge is a group of its own (Rapier solves it
//!   alone), so "number of groups" counts every independently solved part.
//! - Insulators belong to no group; [`Group::insulators`] lists the ones it rests on.
//!
//! Cost: a group is rebuilt only where its structure changed: a contact started or
//! ended between its bodies, a body was added, removed, woke up, fell asleep, changed
//! kind or became passive (or, under subgrouping, became sleepy or stopped being so).
//! Every other group is kept as it was (its id stays valid), and its contact and
//! variable counts follow the per-edge contact counts by differences. A settled scene,
//! and a moving one whose contacts persist, therefore costs almost nothing here.

use crate::graph::{Arena, ContactGraph, EdgeId, EdgeKind, NodeId, NodeKind};

/// A contact group's id: generational, valid while the group lives: until its
/// structure changes (a contact starts or ends between its bodies, a body joins,
/// leaves, wakes, sleeps or changes kind), when it is rebuilt under a new id.
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
    /// Member nodes (simulated bodies and containers), in traversal order.
    pub bodies: Vec<NodeId>,
    /// Member edges (touching physical edges, structural edges), in traversal order.
    pub edges: Vec<EdgeId>,
    /// Insulators (fixed, scripted bodies) the group touches, sorted, without repeats.
    pub insulators: Vec<NodeId>,
    /// Active solver contacts over the group's edges.
    pub contacts: u32,
    /// Contact variables (3 per contact: normal and two friction directions).
    pub variables: u32,
    /// Whether every member was asleep when the group was built.
    pub asleep: bool,
    /// The step the group was built in.
    pub built_step: u64,
}

/// Per-step statistics of the groups, as the paper plots them (Figs. 13–14).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GroupStats {
    /// Number of groups (awake and sleeping).
    pub groups: usize,
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
    /// Groups rebuilt this step.
    pub rebuilt: usize,
}

impl GroupStats {
    /// Mean contact variables per group (0 without groups).
    pub fn mean_variables(&self) -> f64 {
        if self.groups == 0 {
            0.0
        } else {
            self.total_variables as f64 / self.groups as f64
        }
    }
}

/// The contact groups of a scene.
#[derive(Clone, Debug, Default)]
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
fn traversable(kind: EdgeKind, touching: bool) -> bool {
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
        NodeKind::Rigid | NodeKind::Link | NodeKind::Composite | NodeKind::Multibody
    )
}

impl Groups {
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

    /// Dissolves a group: its members lose their group and become roots of the next
    /// traversal.
    pub(crate) fn dissolve(&mut self, graph: &mut ContactGraph, id: GroupId) {
        if let Some(g) = self.arena.remove(id.index(), id.generation()) {
            self.awake.remove(&id);
            if g.asleep {
                let t = &mut self.sleeping;
                t.count -= 1;
                t.variables -= g.variables as u64;
                if g.bodies.len() >= t.largest_bodies || g.variables >= t.largest_variables {
                    t.dirty = true;
                }
            }
            for n in g.bodies {
                if let Some(node) = graph.node_mut(n) {
                    if node.group == Some(id) {
                        node.group = None;
                    }
                    self.roots.push(n);
                }
            }
        }
    }

    /// Checks deserialised groups against their graph: the arena, members and edges
    /// live, members and nodes pointing at each other, the awake set and the sleeping
    /// totals (dissolving subtracts from them) agreeing with the groups. O(groups +
    /// members + nodes).
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self, graph: &ContactGraph) -> Result<(), String> {
        self.arena
            .check()
            .map_err(|e| format!("group arena: {e}"))?;
        let (mut count, mut variables) = (0usize, 0u64);
        for (id, g) in self.iter() {
            for &n in &g.bodies {
                if graph.node(n).map(|node| node.group) != Some(Some(id)) {
                    return Err(format!(
                        "group {id:?} holds {n:?}, which does not point back"
                    ));
                }
            }
            if let Some(e) = g.edges.iter().find(|&&e| graph.edge(e).is_none()) {
                return Err(format!("group {id:?} holds dead edge {e:?}"));
            }
            if g.asleep {
                count += 1;
                variables += g.variables as u64;
            }
            if g.asleep == self.awake.contains(&id) {
                return Err(format!("group {id:?} is misfiled as awake or asleep"));
            }
        }
        if let Some(id) = self.awake.iter().find(|&&id| self.get(id).is_none()) {
            return Err(format!("awake set holds dead group {id:?}"));
        }
        if (count, variables) != (self.sleeping.count, self.sleeping.variables) {
            return Err("sleeping totals disagree with the sleeping groups".into());
        }
        for (n, node) in graph.nodes() {
            if let Some(g) = node.group.filter(|&g| self.get(g).is_none()) {
                return Err(format!("node {n:?} points to dead group {g:?}"));
            }
            // A stamp ahead of the traversal's would make a later traversal take the
            // node as already visited.
            if node.visit_stamp > self.stamp {
                return Err(format!("node {n:?} has a traversal stamp from the future"));
            }
        }
        if let Some((e, _)) = graph.edges().find(|(_, e)| e.colour_stamp > self.stamp) {
            return Err(format!("edge {e:?} has a traversal stamp from the future"));
        }
        Ok(())
    }

    /// Sets the traversal stamp (tests of the wrap at the end of its range).
    #[cfg(test)]
    pub(crate) fn set_stamp(&mut self, stamp: u64) {
        self.stamp = stamp;
    }

    /// Forgets the queued roots (groups switched off).
    pub(crate) fn clear_roots(&mut self) {
        self.roots.clear();
    }

    /// Queues a node as a traversal root, dissolving the group it is in.
    pub(crate) fn disturb(&mut self, graph: &mut ContactGraph, n: NodeId) {
        match graph.node(n).and_then(|node| node.group) {
            Some(g) => self.dissolve(graph, g),
            None => self.roots.push(n),
        }
    }

    /// Rebuilds the groups reachable from the queued roots (Figs. 7–8), with the given
    /// insulator predicate (fixed and scripted bodies, plus whatever the caller adds:
    /// sleepy bodies under subgrouping). Cost: O(members + edges of the rebuilt
    /// groups) plus O(groups) for the statistics.
    pub(crate) fn rebuild(
        &mut self,
        graph: &mut ContactGraph,
        step: u64,
        insulates: &dyn Fn(&ContactGraph, NodeId) -> bool,
    ) {
        // Stamps only grow, and a node or edge is "visited" when its stamp equals the
        // traversal's. At the end of the range (reachable only from restored bytes)
        // every stamp is cleared and the numbering starts again, so an old stamp can
        // never equal a new one. O(1), or O(nodes + edges) at the wrap.
        if self.stamp == u64::MAX {
            graph.clear_stamps();
            self.stamp = 0;
        }
        self.stamp += 1;
        let stamp = self.stamp;
        let mut rebuilt = 0;
        let mut r = 0;
        while r < self.roots.len() {
            let root = self.roots[r];
            r += 1;
            let Some(node) = graph.node(root) else {
                continue;
            };
            // A passive body takes part in nothing, groups included.
            if node.visit_stamp == stamp
                || !member_kind(node.kind)
                || node.passive
                || insulates(graph, root)
            {
                if node.passive {
                    if let Some(old) = node.group {
                        self.dissolve(graph, old);
                    }
                }
                continue;
            }
            if let Some(old) = node.group {
                self.dissolve(graph, old);
            }
            let mut group = Group {
                built_step: step,
                asleep: true,
                ..Group::default()
            };
            self.stack.clear();
            self.stack.push(root);
            if let Some(n) = graph.node_mut(root) {
                n.visit_stamp = stamp;
            }
            while let Some(n) = self.stack.pop() {
                group.bodies.push(n);
                let Some(node) = graph.node(n) else { continue };
                if node.awake {
                    group.asleep = false;
                }
                for k in 0..node.edges.len() {
                    let Some(eid) = graph.node(n).and_then(|node| node.edges.get(k).copied())
                    else {
                        break;
                    };
                    let Some(e) = graph.edge(eid) else { continue };
                    if !traversable(e.kind, e.cache.touching) || e.colour_stamp == stamp {
                        continue;
                    }
                    let Some(m) = e.other(n) else { continue };
                    let contacts = e.cache.contact_count;
                    let variables = e.cache.variables();
                    if let Some(e) = graph.edge_mut(eid) {
                        e.colour_stamp = stamp;
                    }
                    group.edges.push(eid);
                    group.contacts += contacts;
                    group.variables += variables;
                    let Some(other) = graph.node(m) else { continue };
                    if !member_kind(other.kind) || other.passive || insulates(graph, m) {
                        group.insulators.push(m);
                        continue;
                    }
                    if other.visit_stamp != stamp {
                        if let Some(old) = other.group {
                            // A sleeping group reached from an awake one is rebuilt.
                            self.dissolve(graph, old);
                        }
                        if let Some(o) = graph.node_mut(m) {
                            o.visit_stamp = stamp;
                        }
                        self.stack.push(m);
                    }
                }
            }
            group.insulators.sort();
            group.insulators.dedup();
            rebuilt += 1;
            let asleep = group.asleep;
            if asleep {
                let t = &mut self.sleeping;
                t.count += 1;
                t.variables += group.variables as u64;
                t.largest_bodies = t.largest_bodies.max(group.bodies.len());
                t.largest_variables = t.largest_variables.max(group.variables);
            }
            let members = group.bodies.clone();
            let (i, g) = self.arena.insert(group);
            let id = GroupId::new(i, g);
            if !asleep {
                self.awake.insert(id);
            }
            for n in members {
                if let Some(node) = graph.node_mut(n) {
                    node.group = Some(id);
                }
            }
        }
        self.roots.clear();
        self.update_stats(rebuilt);
    }

    /// Keeps the contact counts of the groups that were not rebuilt in step with their
    /// edges: each refreshed physical edge adds the difference of its contact count to
    /// the group of its bodies. Call after [`Self::rebuild`], with the step's refreshed
    /// edges. O(refreshed edges).
    pub(crate) fn apply_contact_deltas(
        &mut self,
        graph: &ContactGraph,
        edges: &[EdgeId],
        step: u64,
    ) {
        let mut changed = false;
        for &eid in edges {
            let Some(e) = graph.edge(eid) else { continue };
            if e.kind != EdgeKind::Physical || !e.cache.touching || !e.cache.touching_old {
                continue; // starts and ends rebuilt their groups
            }
            let (new, old) = (e.cache.contact_count, e.cache.contact_count_old);
            if new == old {
                continue;
            }
            let gid = [e.a, e.b]
                .iter()
                .filter_map(|&n| graph.node(n).and_then(|n| n.group))
                .next();
            let Some(gid) = gid else { continue };
            let Some(g) = self.arena.get_mut(gid.index(), gid.generation()) else {
                continue;
            };
            if g.built_step == step {
                continue; // counted fresh
            }
            let (dc, dv) = (new as i64 - old as i64, 3 * (new as i64 - old as i64));
            g.contacts = (g.contacts as i64 + dc).max(0) as u32;
            let before = g.variables;
            g.variables = (g.variables as i64 + dv).max(0) as u32;
            if g.asleep {
                let t = &mut self.sleeping;
                t.variables =
                    (t.variables as i64 + (g.variables as i64 - before as i64)).max(0) as u64;
                t.dirty = true;
            }
            changed = true;
        }
        if changed {
            self.update_stats(self.stats.rebuilt);
        }
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
            groups: awake.awake_groups + t.count,
            awake_groups: awake.awake_groups,
            largest_bodies: awake.largest_bodies.max(t.largest_bodies),
            largest_variables: awake.largest_variables.max(t.largest_variables),
            total_variables: awake.awake_variables + t.variables,
            awake_variables: awake.awake_variables,
            rebuilt,
        };
        debug_assert_eq!(self.stats.groups, self.arena.len());
    }
}
