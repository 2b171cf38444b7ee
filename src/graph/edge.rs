//! Edges: what relates two nodes (paper Table 2), and the per-edge cache (§3).
//!
//! An edge is keyed by the sorted pair of its nodes ([`crate::PairKey`]); *A* is the
//! node with the smaller slot index. A physical edge aggregates every collider pair of
//! its two bodies: two bodies with three colliders each are one edge, not nine.
//!
//! The cache holds the state of the last update and of the update before (`e_old` in
//! the paper), from which the coherence marks (new / persistent / vanished) are
//! derived. Marks are only reported for edges refreshed in the current step: the pairs
//! of sleeping bodies are not walked (their state is frozen in Rapier, so the cached
//! state stays exact), and a frozen pair has nothing new to say.

use rapier3d::math::{Pose, Real, Vector};

use super::NodeId;

/// The four edge categories of Table 2.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EdgeKind {
    /// Rule – body: the rule applies to the body (static, user-defined).
    Logical,
    /// Body – container: the body is part of the container (static).
    Structural,
    /// Trigger – body: the body is inside the trigger volume (dynamic).
    Geometric,
    /// Body – body: the bodies are in close proximity or touch (dynamic).
    Physical,
}

/// A coherence mark: how a boolean state of an edge changed between the last two
/// updates (paper Figs. 3 and 5).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Transition {
    /// Off before, on now.
    New,
    /// On before and now.
    Persistent,
    /// On before, off now.
    Vanished,
}

impl Transition {
    /// The transition from `old` to `now`; `None` when the state is off in both.
    #[inline]
    pub const fn between(old: bool, now: bool) -> Option<Transition> {
        match (old, now) {
            (false, true) => Some(Transition::New),
            (true, true) => Some(Transition::Persistent),
            (true, false) => Some(Transition::Vanished),
            (false, false) => None,
        }
    }
}

/// The per-edge cache of a physical edge (paper §2, Tables 1–2).
///
/// Distances follow Rapier's sign convention: negative is penetration.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactCache {
    /// A Rapier narrow-phase pair exists between the bodies (fat AABBs overlap) now.
    pub proximity: bool,
    /// `proximity` at the previous update (`e_old`).
    pub proximity_old: bool,
    /// Some collider pair of the two bodies has an active contact now.
    pub touching: bool,
    /// `touching` at the previous update.
    pub touching_old: bool,
    /// Pose of *B* in the frame of *A* at the last update.
    pub relative_pose: Pose,
    /// Whether `relative_pose` differs (bitwise) from the update before.
    pub relative_pose_changed: bool,
    /// Smallest contact distance over all contact points (the paper's min PC);
    /// `Real::INFINITY` when there are no contact points.
    pub min_distance: Real,
    /// The number of active solver contacts (in touching tracking, of touching
    /// collider pairs: see `coherence::Tracking`).
    pub contact_count: u32,
    /// `contact_count` at the previous update.
    pub contact_count_old: u32,
    /// The deepest penetration (≥ 0).
    pub max_penetration: Real,
    /// The sum of the normal impulses the solver applied at the last step.
    pub normal_impulse: Real,
    /// The contact normal of the deepest contact, pointing from *A* to *B*, in world
    /// space (zero when there is no contact point).
    pub normal: Vector,
    /// The number of collider pairs aggregated in this edge.
    pub collider_pairs: u32,
    /// The resultant of the normal impulses of the last step, Σ impulse · normal
    /// (pointing from *A* to *B*): the direction the contact as a whole pushes *B*.
    /// A body in a corner touches a wall deepest but rests on the floor; this says
    /// so where the deepest `normal` cannot. Zero without impulses.
    pub push: Vector,
}

impl Default for ContactCache {
    fn default() -> Self {
        Self {
            proximity: false,
            proximity_old: false,
            touching: false,
            touching_old: false,
            relative_pose: Pose::IDENTITY,
            relative_pose_changed: false,
            min_distance: Real::INFINITY,
            contact_count: 0,
            contact_count_old: 0,
            max_penetration: 0.0,
            normal_impulse: 0.0,
            normal: Vector::ZERO,
            collider_pairs: 0,
            push: Vector::ZERO,
        }
    }
}

impl ContactCache {
    /// Number of contact variables the solver sees for this edge: one normal and two
    /// friction impulses per active contact in 3-D (the measure of the paper's
    /// Figs. 13–14).
    #[inline]
    pub fn variables(&self) -> u32 {
        3 * self.contact_count
    }

    /// Whether this contact holds its *B* end (with `b` false, its *A* end) up along
    /// `up`: it touches or lies within `gap`, and the resultant of its impulses where
    /// there is one (a body in a corner rests on the floor, though a wall may be
    /// deeper), else its deepest normal, pushes that end by more than `min_cos` along
    /// `up`. The one support test of the graph's cached edges and of the contacts read
    /// from Rapier on demand. O(1).
    pub(crate) fn holds_up(&self, b: bool, up: Vector, min_cos: Real, gap: Real) -> bool {
        if !(self.touching || self.min_distance <= gap) {
            return false;
        }
        let dir = if self.push != Vector::ZERO {
            self.push.normalize()
        } else {
            self.normal
        };
        let push = if b { dir } else { -dir };
        push.dot(up) > min_cos
    }

    /// Shifts the current state into `*_old` and clears the per-update aggregates,
    /// keeping the relative pose for the change test. Without `details` the detail
    /// fields keep their values (they are not maintained).
    pub(crate) fn begin_update(&mut self, details: bool) {
        self.proximity_old = self.proximity;
        self.touching_old = self.touching;
        self.proximity = false;
        self.touching = false;
        self.contact_count_old = self.contact_count;
        self.contact_count = 0;
        self.collider_pairs = 0;
        if details {
            self.min_distance = Real::INFINITY;
            self.max_penetration = 0.0;
            self.normal_impulse = 0.0;
            self.normal = Vector::ZERO;
            self.push = Vector::ZERO;
        }
    }
}

/// An edge of the contact graph.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Edge {
    pub(crate) a: NodeId,
    pub(crate) b: NodeId,
    pub(crate) kind: EdgeKind,
    pub(crate) cache: ContactCache,
    /// The step of the last refresh; marks are reported only when it is the current step.
    pub(crate) updated_step: u64,
    /// The step the edge was created in.
    pub(crate) created_step: u64,
    /// Traversal colour: "white" unless it equals the current traversal stamp.
    pub(crate) colour_stamp: u64,
    /// Per-step scratch: the collider-pair walk reached this edge in this step.
    pub(crate) walk_stamp: u64,
    /// The edge's position in its group's edge list, [`NO_SLOT`] when it is in none
    /// (the edge is in group `g` exactly when `g.edges[group_slot]` is this edge).
    /// Not saved: a restore rebuilds it from the groups.
    #[cfg_attr(feature = "serde", serde(skip, default = "no_slot"))]
    pub(crate) group_slot: u32,
    /// The contact count the edge's group has counted for it (the group follows the
    /// edge's count by differences).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) group_counted: u32,
}

/// `Edge::group_slot` of an edge in no group.
pub(crate) const NO_SLOT: u32 = u32::MAX;

#[cfg(feature = "serde")]
fn no_slot() -> u32 {
    NO_SLOT
}

/// A joining edge (physical or structural) removed from the graph, waiting for the
/// groups to take it out of the group that held it (see [`crate::Groups`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LeftEdge {
    pub(crate) id: crate::graph::EdgeId,
    pub(crate) a: NodeId,
    pub(crate) b: NodeId,
    pub(crate) slot: u32,
    pub(crate) counted: u32,
}

impl Edge {
    pub(crate) fn new(a: NodeId, b: NodeId, kind: EdgeKind, step: u64) -> Self {
        debug_assert!(a.index() < b.index());
        Self {
            a,
            b,
            kind,
            cache: ContactCache::default(),
            updated_step: step,
            created_step: step,
            colour_stamp: 0,
            walk_stamp: 0,
            group_slot: NO_SLOT,
            group_counted: 0,
        }
    }

    /// The node with the smaller slot index (the paper's *A*).
    #[inline]
    pub fn a(&self) -> NodeId {
        self.a
    }
    /// The node with the larger slot index (the paper's *B*).
    #[inline]
    pub fn b(&self) -> NodeId {
        self.b
    }
    /// Both end nodes, *A* first.
    #[inline]
    pub fn nodes(&self) -> (NodeId, NodeId) {
        (self.a, self.b)
    }
    /// The end that is not `n` (`None` if `n` is not an end of this edge).
    #[inline]
    pub fn other(&self, n: NodeId) -> Option<NodeId> {
        if n == self.a {
            Some(self.b)
        } else if n == self.b {
            Some(self.a)
        } else {
            None
        }
    }
    /// The edge's category.
    #[inline]
    pub fn kind(&self) -> EdgeKind {
        self.kind
    }
    /// The cached contact state (meaningful for physical and geometric edges).
    #[inline]
    pub fn cache(&self) -> &ContactCache {
        &self.cache
    }
    /// Whether the two bodies touch (an active contact). Exact for sleeping pairs too:
    /// Rapier freezes their state and so does the graph.
    #[inline]
    pub fn is_touching(&self) -> bool {
        self.cache.touching
    }
    /// Whether the two bodies are in close proximity (a Rapier narrow-phase pair).
    #[inline]
    pub fn is_proximate(&self) -> bool {
        self.cache.proximity
    }
    /// The step of the edge's last refresh.
    #[inline]
    pub fn updated_step(&self) -> u64 {
        self.updated_step
    }
    /// The step the edge was created in.
    #[inline]
    pub fn created_step(&self) -> u64 {
        self.created_step
    }
    /// The proximity mark of the step `step`: `Some` only if the edge was refreshed in
    /// that step and was or is proximate.
    #[inline]
    pub fn proximity_mark(&self, step: u64) -> Option<Transition> {
        (self.updated_step == step)
            .then(|| Transition::between(self.cache.proximity_old, self.cache.proximity))
            .flatten()
    }
    /// The touching mark of the step `step` (see [`Edge::proximity_mark`]).
    #[inline]
    pub fn touching_mark(&self, step: u64) -> Option<Transition> {
        (self.updated_step == step)
            .then(|| Transition::between(self.cache.touching_old, self.cache.touching))
            .flatten()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transitions() {
        assert_eq!(Transition::between(false, true), Some(Transition::New));
        assert_eq!(
            Transition::between(true, true),
            Some(Transition::Persistent)
        );
        assert_eq!(Transition::between(true, false), Some(Transition::Vanished));
        assert_eq!(Transition::between(false, false), None);
    }

    #[test]
    fn marks_only_for_the_step_of_the_update() {
        let a = NodeId::from_raw_parts(0, 0);
        let b = NodeId::from_raw_parts(1, 0);
        let mut e = Edge::new(a, b, EdgeKind::Physical, 3);
        e.cache.begin_update(true);
        e.cache.proximity = true;
        assert_eq!(e.proximity_mark(3), Some(Transition::New));
        assert_eq!(e.proximity_mark(4), None);
        e.updated_step = 4;
        e.cache.begin_update(true);
        assert_eq!(e.proximity_mark(4), Some(Transition::Vanished));
        assert_eq!(e.touching_mark(4), None);
        assert_eq!(e.other(a), Some(b));
        assert_eq!(e.other(NodeId::from_raw_parts(9, 0)), None);
    }
}
