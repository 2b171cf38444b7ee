//! Containers (Table 1's C and M) and their structural edges (Table 2).
//!
//! Where they come from:
//! - one `Multibody` node per Rapier multibody, its dynamic links as `Link` nodes;
//! - articulations built from impulse joints: the simulated bodies joined by impulse
//!   joints form connected components; a component whose joints are all fixed joints
//!   is a `Composite` (bodies rigidly attached), any other one a `Multibody`;
//! - composites declared by the user ([`crate::LayerLogicMut::declare_composite`]).
//!
//! Fixed and kinematic bodies never join a container: they insulate (a pendulum hung
//! from the world is a mechanism of its moving links, not of the world).
//!
//! Upkeep: containers derived from joints are recomputed when the joint sets change
//! (their sizes are compared every step: O(multibodies)); the recomputation is
//! O(joints + links) and keeps the node of a container whose key (its root body, or
//! the first body of its component) survives, adjusting its structural edges.

use std::collections::BTreeMap;

use rapier3d::dynamics::JointAxesMask;
use rapier3d::prelude::RigidBodyHandle;

use crate::graph::mirror::ensure_body_node;
use crate::graph::{ContactGraph, ContainerSource, EdgeKind, NodeId, NodeSource};
use crate::WorldView;

/// The joint-derived containers of a layer.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Containers {
    signature: Option<u64>,
    nodes: BTreeMap<ContainerSource, NodeId>,
}

fn handle_key(h: RigidBodyHandle) -> (u32, u32) {
    h.into_raw_parts()
}

/// Union-find over small integer ids.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

impl Containers {
    /// Brings the containers in line with Rapier's joints. Returns the nodes whose
    /// structure changed (their groups must be rebuilt). Cost: O(multibodies) when
    /// nothing changed.
    // Long: compares every multibody and joint set with its container in one pass.
    pub(crate) fn sync(
        &mut self,
        graph: &mut ContactGraph,
        view: &WorldView,
        step: u64,
        created: &mut Vec<NodeId>,
        force: bool,
        groups: &mut crate::Groups,
    ) -> Vec<NodeId> {
        // A fingerprint of the joints (which bodies they join, fixed or not): a joint
        // swapped for another between two steps changes it even when the counts do not.
        // O(joints + links); nothing without joints.
        let mut fp: u64 = 0xcbf2_9ce4_8422_2325;
        let mut mix = |v: u64| {
            fp ^= v;
            fp = fp.wrapping_mul(0x0000_0100_0000_01b3);
        };
        for (jh, j) in view.impulse_joints.iter() {
            let (i, g) = jh.into_raw_parts();
            mix(((g as u64) << 32) | i as u64);
            for b in [j.body1(), j.body2()] {
                let (i, g) = b.into_raw_parts();
                mix(((g as u64) << 32) | i as u64);
            }
            mix(j.data.locked_axes.bits() as u64);
        }
        for mb in view.multibody_joints.multibodies() {
            for l in mb.links() {
                let (i, g) = l.rigid_body_handle().into_raw_parts();
                mix(((g as u64) << 32) | i as u64);
            }
            mix(u64::MAX);
        }
        let signature = fp;
        if !force && self.signature == Some(signature) {
            return Vec::new();
        }
        self.signature = Some(signature);

        let desired = desired(view, &|_| false);

        let mut changed = Vec::new();
        // Remove containers that are gone.
        let stale: Vec<ContainerSource> = self
            .nodes
            .keys()
            .filter(|k| !desired.contains_key(k))
            .copied()
            .collect();
        for k in stale {
            if let Some(n) = self.nodes.remove(&k) {
                changed.extend(graph.neighbors(n).map(|(m, _, _)| m));
                if let Some(g) = graph.node(n).and_then(|x| x.group()) {
                    groups.dissolve(graph, g);
                }
                graph.remove_node(n);
            }
        }
        // Create or adjust the others.
        for (source, members) in desired {
            let node = match self.nodes.get(&source) {
                Some(&n) if graph.contains_node(n) => n,
                _ => {
                    let n = graph.add_node(source.kind(), NodeSource::Container(source));
                    created.push(n);
                    self.nodes.insert(source, n);
                    n
                }
            };
            let mut want: Vec<NodeId> = members
                .iter()
                .filter_map(|&h| ensure_body_node(graph, view, h, created))
                .collect();
            want.sort();
            let have: Vec<(NodeId, crate::EdgeId)> = graph
                .neighbors(node)
                .filter(|(_, _, e)| e.kind() == EdgeKind::Structural)
                .map(|(m, id, _)| (m, id))
                .collect();
            for &(m, e) in &have {
                if want.binary_search(&m).is_err() {
                    graph.remove_edge(e);
                    changed.push(m);
                }
            }
            for &m in &want {
                if !have.iter().any(|&(x, _)| x == m) {
                    graph.ensure_edge(node, m, EdgeKind::Structural, step);
                    changed.push(m);
                }
            }
            if !changed.is_empty() {
                changed.push(node);
            }
        }
        changed.sort();
        changed.dedup();
        changed
    }
}

/// The containers Rapier's joints make (see the module docs), each with its member
/// bodies sorted by handle: what [`Containers::sync`] brings the graph to, and what
/// `validate()` checks the graph against. `seen_fixed` tells the dynamic bodies to
/// count as fixed (`validate()`'s bodies given back after the analysis). O(joints +
/// links).
pub(crate) fn desired(
    view: &WorldView,
    seen_fixed: &dyn Fn(RigidBodyHandle) -> bool,
) -> BTreeMap<ContainerSource, Vec<RigidBodyHandle>> {
    let simulated =
        |h: RigidBodyHandle| view.bodies.get(h).is_some_and(|b| b.is_dynamic()) && !seen_fixed(h);
    let mut desired: BTreeMap<ContainerSource, Vec<RigidBodyHandle>> = BTreeMap::new();

    // Rapier multibodies.
    for mb in view.multibody_joints.multibodies() {
        let root = mb.root().rigid_body_handle();
        let mut members: Vec<RigidBodyHandle> = mb
            .links()
            .map(|l| l.rigid_body_handle())
            .filter(|&h| simulated(h))
            .collect();
        members.sort_by_key(|h| handle_key(*h));
        if !members.is_empty() {
            desired.insert(ContainerSource::Multibody(root), members);
        }
    }

    // Impulse-joint components of simulated bodies.
    let mut ids: BTreeMap<(u32, u32), usize> = BTreeMap::new();
    let mut handles: Vec<RigidBodyHandle> = Vec::new();
    let mut joints: Vec<(usize, usize, bool)> = Vec::new();
    for (_, j) in view.impulse_joints.iter() {
        let (b1, b2) = (j.body1(), j.body2());
        if !simulated(b1) || !simulated(b2) || b1 == b2 {
            continue;
        }
        let mut id = |h: RigidBodyHandle| {
            *ids.entry(handle_key(h)).or_insert_with(|| {
                handles.push(h);
                handles.len() - 1
            })
        };
        let (i1, i2) = (id(b1), id(b2));
        let fixed = j.data.locked_axes == JointAxesMask::LOCKED_FIXED_AXES;
        joints.push((i1, i2, fixed));
    }
    let mut parent: Vec<usize> = (0..handles.len()).collect();
    for &(i1, i2, _) in &joints {
        let (r1, r2) = (find(&mut parent, i1), find(&mut parent, i2));
        if r1 != r2 {
            parent[r1.max(r2)] = r1.min(r2);
        }
    }
    let mut all_fixed: BTreeMap<usize, bool> = BTreeMap::new();
    for &(i1, _, fixed) in &joints {
        let r = find(&mut parent, i1);
        *all_fixed.entry(r).or_insert(true) &= fixed;
    }
    let mut comps: BTreeMap<usize, Vec<RigidBodyHandle>> = BTreeMap::new();
    for (i, &h) in handles.iter().enumerate() {
        let r = find(&mut parent, i);
        comps.entry(r).or_default().push(h);
    }
    for (r, mut members) in comps {
        members.sort_by_key(|h| handle_key(*h));
        let key = members[0];
        let source = if all_fixed.get(&r).copied().unwrap_or(false) {
            ContainerSource::Composite(key)
        } else {
            ContainerSource::Articulation(key)
        };
        desired.insert(source, members);
    }
    desired
}
