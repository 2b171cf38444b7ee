//! Where each node and edge end is drawn: nodes at their centre of mass (containers at
//! their members' hub), the scenery end of a physical edge at its surface point nearest
//! the other end, and each group's colour key for this call.

use rapier3d::math::{Real, Vector};
use rapier3d::pipeline::DebugRenderObject;

use super::overlay::Sets;
use super::style::group_key;
use super::{GraphOverlay, OverlayStats};
use crate::graph::{ContactGraph, EdgeKind, Node, NodeId, NodeKind, NodeSource};
use crate::groups::Groups;
use crate::ContactLayer;

/// Boxes wider than this (metres) are unbounded shapes (half-spaces): they have no centre.
const UNBOUNDED: Real = 1.0e30;

/// A node's end of an edge: its Rapier object and its position.
pub(super) struct End<'a> {
    pub(super) object: Option<DebugRenderObject<'a>>,
    pub(super) pos: Option<Vector>,
    /// A body the solver moves (Dynamic or Link): preferred as the edge's object.
    pub(super) simulated: bool,
}

impl GraphOverlay {
    /// Fills `places`: bodies at their centre of mass, colliders without a body and
    /// sensors at their bounding box's centre, then containers at the mean of their
    /// members. O(node slots + structural edges).
    pub(super) fn place_nodes(&mut self, sets: Sets, stats: &mut OverlayStats) {
        let graph = sets.layer.graph();
        self.places.clear();
        if self.place_own(sets, stats) {
            self.place_containers(graph, stats);
        }
    }

    /// Places every node with a place of its own (bodies, colliders without a body,
    /// sensors); returns whether the graph has containers to place after them.
    fn place_own(&mut self, sets: Sets, stats: &mut OverlayStats) -> bool {
        let Sets {
            layer,
            bodies,
            colliders,
        } = sets;
        let mut containers = false;
        for (id, n) in layer.graph().nodes() {
            let pos = match n.source() {
                NodeSource::Body(h) => bodies
                    .get(h)
                    .filter(|_| !n.is_non_finite())
                    .map(|rb| rb.center_of_mass()),
                NodeSource::StaticCollider(c) | NodeSource::Sensor(c) => {
                    colliders.get(c).and_then(|co| {
                        let aabb = co.compute_aabb();
                        // A half-space's box spans the float range: no centre.
                        (aabb.extents().max_element() < UNBOUNDED).then(|| aabb.center())
                    })
                }
                NodeSource::Container(_) => {
                    containers = true;
                    continue;
                }
                NodeSource::Layer(_) => {
                    if n.kind() == NodeKind::Composite {
                        containers = true;
                    }
                    continue;
                }
            };
            match pos.filter(|p| p.is_finite()) {
                Some(p) => self.set_place(id, p),
                None => stats.unplaced_nodes += 1,
            }
        }
        containers
    }

    /// Places every container at the mean of its placed members (its hub).
    fn place_containers(&mut self, graph: &ContactGraph, stats: &mut OverlayStats) {
        for (id, n) in graph.nodes() {
            if n.kind().category() != crate::Category::Container {
                continue;
            }
            let (mut sum, mut count) = (Vector::ZERO, 0u32);
            for (m, _, e) in graph.neighbors(id) {
                if e.kind() == EdgeKind::Structural {
                    if let Some(p) = self.place(m) {
                        sum += p;
                        count += 1;
                    }
                }
            }
            let hub = (count > 0).then(|| sum / count as Real);
            match hub.filter(|p| p.is_finite()) {
                Some(p) => self.set_place(id, p),
                None => stats.unplaced_nodes += 1,
            }
        }
    }

    /// Records node `id`'s position.
    fn set_place(&mut self, id: NodeId, p: Vector) {
        let i = id.index() as usize;
        if self.places.len() <= i {
            self.places.resize(i + 1, None);
        }
        self.places[i] = Some((id, p));
    }

    /// Node `id`'s position in this call, if it has one.
    fn place(&self, id: NodeId) -> Option<Vector> {
        match self.places.get(id.index() as usize) {
            Some(Some((n, p))) if *n == id => Some(*p),
            _ => None,
        }
    }

    /// Fills `group_keys`. O(groups + members).
    pub(super) fn key_groups(&mut self, groups: &Groups) {
        self.group_keys.clear();
        for (id, g) in groups.iter() {
            let Some(key) = group_key(g) else { continue };
            let i = id.index() as usize;
            if self.group_keys.len() <= i {
                self.group_keys.resize(i + 1, None);
            }
            self.group_keys[i] = Some((id.generation(), key));
        }
    }

    /// The colour key of group `id` in this call, if it has members.
    pub(super) fn group_key_of(&self, id: crate::GroupId) -> Option<u32> {
        match self.group_keys.get(id.index() as usize) {
            Some(Some((g, key))) if *g == id.generation() => Some(*key),
            _ => None,
        }
    }

    /// A node with its position (`None` if it has none) and its Rapier object (`None`
    /// for containers). `None` if its object is gone from the sets.
    pub(super) fn end<'a>(&self, sets: Sets<'a>, id: NodeId, n: &Node) -> Option<End<'a>> {
        let object = match n.source() {
            NodeSource::Body(h) => Some(DebugRenderObject::RigidBody(h, sets.bodies.get(h)?)),
            NodeSource::StaticCollider(c) | NodeSource::Sensor(c) => {
                Some(DebugRenderObject::Collider(c, sets.colliders.get(c)?))
            }
            NodeSource::Container(_) | NodeSource::Layer(_) => None,
        };
        Some(End {
            object,
            pos: self.place(id),
            simulated: n.kind().is_simulated(),
        })
    }

    /// Whether node `n` is scenery: an insulator not held by the speed-ups.
    fn is_scenery(layer: &ContactLayer, n: &Node) -> bool {
        n.kind().is_insulator()
            && !n
                .body()
                .is_some_and(|h| layer.speedups().is_some_and(|s| s.is_fixated(h)))
    }

    /// The point of scenery node `n`'s colliders nearest to `to`, if finite. O(colliders
    /// of the node).
    fn nearest_on(sets: Sets, n: &Node, to: Vector) -> Option<Vector> {
        let source = n.source();
        let handles = match &source {
            NodeSource::Body(h) => sets.bodies.get(*h)?.colliders(),
            NodeSource::StaticCollider(c) => std::slice::from_ref(c),
            _ => return None,
        };
        let mut best: Option<(Real, Vector)> = None;
        for &c in handles {
            let Some(co) = sets.colliders.get(c) else {
                continue;
            };
            if co.is_sensor() || !co.is_enabled() {
                continue;
            }
            let p = co.shape().project_point(co.position(), to, false).point;
            let d = (p - to).length_squared();
            if p.is_finite() && d.is_finite() && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, p));
            }
        }
        best.map(|(_, p)| p)
    }

    /// Moves the scenery end of a physical edge (one end scenery, the other placed) to
    /// the point of the scenery's colliders nearest the other end. The scenery end needs
    /// no position of its own (a half-space has none). O(colliders of the scenery node).
    pub(super) fn anchor_scenery(
        sets: Sets,
        (na, a): (&Node, &mut End),
        (nb, b): (&Node, &mut End),
    ) {
        match (
            Self::is_scenery(sets.layer, na),
            Self::is_scenery(sets.layer, nb),
            a.pos,
            b.pos,
        ) {
            (true, false, _, Some(to)) => {
                if let Some(p) = Self::nearest_on(sets, na, to) {
                    a.pos = Some(p);
                }
            }
            (false, true, Some(to), _) => {
                if let Some(p) = Self::nearest_on(sets, nb, to) {
                    b.pos = Some(p);
                }
            }
            _ => {}
        }
    }
}
