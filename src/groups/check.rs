//! Checks of the groups against their graph: after a restore (the arena, members and
//! counts), and in `validate()` (every group equal to a from-scratch traversal, or the
//! union of such groups while its split is deferred).

use std::collections::HashMap;

use crate::graph::{ContactGraph, NodeId, PairBuildHasher, NO_SLOT};

use super::{member_kind, traversable, Group, GroupId, Groups};

impl Groups {
    /// Rebuilds what a snapshot does not carry (each member's and edge's position in
    /// its group, the counted contacts, the awake counts and the insulators' edge
    /// counts) from the groups' lists. Safe on any bytes: [`Self::check`] then tells
    /// whether they agree. O(nodes + edges + members).
    #[cfg(feature = "serde")]
    pub(crate) fn reindex(&mut self, graph: &mut ContactGraph) {
        for e in graph.edges.values_mut() {
            e.group_slot = NO_SLOT;
            e.group_counted = 0;
        }
        for g in self.arena.values_mut() {
            g.awake = 0;
            for (slot, &n) in g.bodies.iter().enumerate() {
                if let Some(node) = graph.node_mut(n) {
                    node.group_slot = slot as u32;
                    if node.awake {
                        g.awake += 1;
                    }
                }
            }
            let mut ends: Vec<NodeId> = Vec::new();
            for (slot, &eid) in g.edges.iter().enumerate() {
                if let Some(e) = graph.edge_mut(eid) {
                    e.group_slot = slot as u32;
                    e.group_counted = e.cache.contact_count;
                    ends.push(e.a);
                    ends.push(e.b);
                }
            }
            ends.retain(|n| g.insulators.binary_search(n).is_ok());
            g.links = g.insulators.iter().map(|_| 0).collect();
            for n in ends {
                if let Ok(i) = g.insulators.binary_search(&n) {
                    g.links[i] += 1;
                }
            }
        }
    }

    /// Checks deserialised groups against their graph: the arena, members and edges
    /// live, members and nodes pointing at each other, the awake set and the sleeping
    /// totals agreeing with the groups, the deferred groups alive. O(groups + members
    /// + nodes).
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
            if g.asleep != (g.awake == 0) {
                return Err(format!("group {id:?} is asleep with awake members, or not"));
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
        if let Some(id) = self.deferred.iter().find(|&&id| self.get(id).is_none()) {
            return Err(format!("deferred list holds dead group {id:?}"));
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

    /// Checks every group against the graph as a from-scratch traversal would build
    /// it: members are live, simulated, non-passive, non-insulating nodes pointing
    /// back and knowing their place; the group's edges are exactly the joining edges
    /// of its members (so none joins another member), each knowing its place and
    /// counted contacts, which sum to the group's; its insulators exactly the far ends
    /// of those edges, with their edge counts; its awake count and sleep the members';
    /// and it is connected, unless its split is deferred. O(members + edges).
    pub(crate) fn verify(
        &self,
        graph: &ContactGraph,
        insulates: &dyn Fn(NodeId) -> bool,
    ) -> Result<(), String> {
        let mut reached: HashMap<NodeId, (), PairBuildHasher> = HashMap::default();
        let mut stack = Vec::new();
        for (gid, g) in self.iter() {
            let awake = verify_members(graph, gid, g, insulates)?;
            let (ends, counted) = verify_edges(graph, gid, g, insulates)?;
            verify_tallies(gid, g, ends, awake, counted)?;
            if self.is_deferred(gid) || g.bodies.is_empty() {
                continue;
            }
            verify_connected(graph, gid, g, &mut reached, &mut stack)?;
        }
        self.verify_edge_slots(graph)
    }

    /// Every edge naming a group slot is that slot's edge in the group of its ends.
    /// O(edges).
    fn verify_edge_slots(&self, graph: &ContactGraph) -> Result<(), String> {
        for (eid, e) in graph.edges() {
            if e.group_slot == NO_SLOT {
                continue;
            }
            let held = super::incremental::group_of_ends(graph, e.a, e.b)
                .and_then(|g| self.get(g))
                .is_some_and(|g| g.edges.get(e.group_slot as usize) == Some(&eid));
            if !held {
                return Err(format!("edge {eid:?} names a group slot no group gives it"));
            }
        }
        Ok(())
    }
}

/// A group's members: live, simulated, non-passive, non-insulating nodes pointing back
/// and knowing their place, their joining edges in the group. Returns the awake
/// members' count. O(members + their edges).
fn verify_members(
    graph: &ContactGraph,
    gid: GroupId,
    g: &Group,
    insulates: &dyn Fn(NodeId) -> bool,
) -> Result<u32, String> {
    let mut awake = 0u32;
    for (slot, &n) in g.bodies.iter().enumerate() {
        let Some(node) = graph.node(n) else {
            return Err(format!("group {gid:?} holds dead node {n:?}"));
        };
        if !member_kind(node.kind) || node.passive || insulates(n) {
            return Err(format!(
                "group {gid:?} holds {n:?}, which cannot be a member"
            ));
        }
        if node.group != Some(gid) {
            return Err(format!(
                "node {n:?} is in group {gid:?} but points to {:?}",
                node.group
            ));
        }
        if node.group_slot as usize != slot {
            return Err(format!("member {n:?} of {gid:?} has a wrong slot"));
        }
        awake += node.awake as u32;
        for &eid in &node.edges {
            let Some(e) = graph.edge(eid) else { continue };
            if !traversable(e.kind, e.cache.touching) {
                continue;
            }
            if g.edges.get(e.group_slot as usize) != Some(&eid) {
                return Err(format!(
                    "joining edge {eid:?} of member {n:?} is missing from group {gid:?}"
                ));
            }
        }
    }
    Ok(awake)
}

/// A group's edges: live, joining, knowing their place and counted contacts, each
/// with an end in the group and the other end a member or an insulator. Returns the
/// insulator ends (one per edge) and the counted contacts. O(edges).
fn verify_edges(
    graph: &ContactGraph,
    gid: GroupId,
    g: &Group,
    insulates: &dyn Fn(NodeId) -> bool,
) -> Result<(Vec<NodeId>, u32), String> {
    let mut ends: Vec<NodeId> = Vec::new();
    let mut counted = 0u32;
    for (slot, &eid) in g.edges.iter().enumerate() {
        let Some(e) = graph.edge(eid) else {
            return Err(format!("group {gid:?} holds dead edge {eid:?}"));
        };
        if !traversable(e.kind, e.cache.touching) {
            return Err(format!(
                "group {gid:?} holds edge {eid:?}, which joins nothing"
            ));
        }
        if e.group_slot as usize != slot {
            return Err(format!("edge {eid:?} of {gid:?} has a wrong slot"));
        }
        if e.group_counted != e.cache.contact_count {
            return Err(format!("edge {eid:?} of {gid:?} is counted wrong"));
        }
        counted = counted.saturating_add(e.group_counted);
        let inside = |n| graph.node(n).and_then(|n| n.group) == Some(gid);
        let far = match (inside(e.a), inside(e.b)) {
            (true, true) => continue,
            (true, false) => e.b,
            (false, true) => e.a,
            (false, false) => {
                return Err(format!("edge {eid:?} of {gid:?} has no end in it"));
            }
        };
        // The far end insulates; a member there would be a second group joined.
        let member = graph
            .node(far)
            .is_some_and(|f| member_kind(f.kind) && !f.passive && !insulates(far));
        if member {
            return Err(format!(
                "edge {eid:?} joins groups {gid:?} and {:?}",
                graph.node(far).and_then(|f| f.group)
            ));
        }
        ends.push(far);
    }
    Ok((ends, counted))
}

/// A group's insulators (with their edge counts), awake count, sleep and contact
/// counts against what its members and edges give. O(edges · log edges).
fn verify_tallies(
    gid: GroupId,
    g: &Group,
    mut ends: Vec<NodeId>,
    awake: u32,
    counted: u32,
) -> Result<(), String> {
    ends.sort_unstable();
    let mut links: Vec<(NodeId, u32)> = Vec::new();
    for n in ends {
        match links.last_mut() {
            Some((m, c)) if *m == n => *c += 1,
            _ => links.push((n, 1)),
        }
    }
    let have: Vec<(NodeId, u32)> = g
        .insulators
        .iter()
        .copied()
        .zip(g.links.iter().copied())
        .collect();
    if have != links || g.insulators.len() != g.links.len() {
        return Err(format!(
            "group {gid:?} lists insulators {have:?}, its edges reach {links:?}"
        ));
    }
    if g.awake != awake || g.asleep != (awake == 0) {
        return Err(format!(
            "group {gid:?} counts {} awake members (asleep: {}), it has {awake}",
            g.awake, g.asleep
        ));
    }
    if counted != g.contacts || g.variables != 3 * counted {
        return Err(format!(
            "group {gid:?} counts {} contacts / {} variables, its edges {counted}",
            g.contacts, g.variables
        ));
    }
    Ok(())
}

/// A group is connected over its own edges. O(members + their edges).
fn verify_connected(
    graph: &ContactGraph,
    gid: GroupId,
    g: &Group,
    reached: &mut HashMap<NodeId, (), PairBuildHasher>,
    stack: &mut Vec<NodeId>,
) -> Result<(), String> {
    // Connected over its own edges.
    reached.clear();
    stack.clear();
    stack.push(g.bodies[0]);
    reached.insert(g.bodies[0], ());
    while let Some(n) = stack.pop() {
        let Some(node) = graph.node(n) else { continue };
        for &eid in &node.edges {
            let Some(e) = graph.edge(eid) else { continue };
            if e.group_slot == NO_SLOT || g.edges.get(e.group_slot as usize) != Some(&eid) {
                continue;
            }
            let Some(m) = e.other(n) else { continue };
            if graph.node(m).and_then(|m| m.group) == Some(gid) && reached.insert(m, ()).is_none() {
                stack.push(m);
            }
        }
    }
    if reached.len() != g.bodies.len() {
        let apart: Vec<NodeId> = g
            .bodies
            .iter()
            .copied()
            .filter(|n| !reached.contains_key(n))
            .take(4)
            .collect();
        return Err(format!(
            "group {gid:?} falls apart: {} of its {} members reach each other \
             (not {apart:?}), and its split is not deferred",
            reached.len(),
            g.bodies.len()
        ));
    }
    Ok(())
}
