//! Edges: what relates two nodes (paper Table 2), and the per-edge cache (§3).
//!
//! An edge is keyed by the sorted pair of its nodes ([`crate::PairKey`]); *A* is the
//! node with the smaller slot index. A physical edge aggregates every collider pair of
//! its two bodies: two bodies with three colliders each are one edge, not nine.
//!
//! A physical or geometric edge also names one of its collider pairs (the one its
//! events name, [`Edge::colliders`]): when its bodies start touching, the touching pair
//! with the smallest handles; the same pair while it keeps touching; when it stops
//! while others still touch, the smallest of those; when the bodies stop touching,
//! the pair named last (one of the last to stop). Without a touch (proximity only, or
//! a trigger's overlap), a pair in proximity, kept likewise. The choice depends only on
//! which pairs touch in each step, not on the order the analysis meets them, so
//! proximity tracking and touching tracking, and the per-body walk and the full scan,
//! name the same pair.
//!
//! The cache holds the state of the last update and of the update before (`e_old` in
//! the paper), from which the coherence marks (new / persistent / vanished) are
//! derived. Marks are only reported for edges refreshed in the current step: the pairs
//! of sleeping bodies are not walked (their state is frozen in Rapier, so the cached
//! state stays exact), and a frozen pair has nothing new to say.

use rapier3d::math::{Pose, Real, Vector};
use rapier3d::prelude::ColliderHandle;

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
    /// The contact normal of the deepest contact, pointing from *A* to *B* (the
    /// events' `node1` to `node2`: the crate's one convention, see the `events`
    /// module's "Normals"), in world space (zero when there is no contact point).
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
    /// The collider pair the edge names, *A*'s collider first ([`Edge::colliders`]);
    /// `no_pair()` before any.
    #[cfg_attr(feature = "serde", serde(default = "no_pair"))]
    pub(crate) named: [ColliderHandle; 2],
    /// Scratch of the refresh in progress: how `named` is being chosen.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) naming: Naming,
}

/// Scratch of a refresh's choice of the pair an edge names: set at the start of each
/// refresh, so left out of snapshots and of `Debug`.
#[derive(Clone, Copy)]
pub(crate) struct Naming {
    /// The pair named before the refresh.
    before: [ColliderHandle; 2],
    /// The rank of the pair chosen so far (`RANK_*`).
    rank: u8,
    /// Touching tracking: the pair named before stopped touching, so the one to name is
    /// read from Rapier if others still touch.
    lost: bool,
}

impl Default for Naming {
    fn default() -> Self {
        Self {
            before: no_pair(),
            rank: RANK_NONE,
            lost: false,
        }
    }
}

impl std::fmt::Debug for Naming {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Naming")
    }
}

/// No collider pair named yet.
pub(crate) fn no_pair() -> [ColliderHandle; 2] {
    [ColliderHandle::invalid(), ColliderHandle::invalid()]
}

// The ranks of the pair chosen so far in a refresh: the highest wins, ties go to the
// smaller handles. "Before": the pair named before the refresh.
/// Before, but it was not on (touching, or overlapping for a trigger): any pair met
/// replaces it.
const RANK_NONE: u8 = 0;
/// A pair met in proximity, not touching.
const RANK_NEAR: u8 = 1;
/// Before, met in proximity, not touching.
const RANK_NEAR_KEPT: u8 = 2;
/// Before, it touched and is not (yet) met touching: the last to stop, unless another
/// pair touches.
const RANK_STOPPED: u8 = 3;
/// A pair met touching.
const RANK_TOUCHING: u8 = 4;
/// Before, it touched and still touches.
const RANK_KEPT: u8 = 5;

/// A pair's handles as numbers, for the tie-break.
fn pair_key(p: [ColliderHandle; 2]) -> ((u32, u32), (u32, u32)) {
    (p[0].into_raw_parts(), p[1].into_raw_parts())
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
            named: no_pair(),
            naming: Naming::default(),
        }
    }

    /// The collider pair this edge names, *A*'s collider first: the pair its events
    /// name ([`crate::Event::collider1`] / [`crate::Event::collider2`], oriented
    /// there as the event's nodes). For a physical edge a pair of its two bodies'
    /// colliders (or a static collider itself), for a geometric edge the sensor and
    /// the body's collider inside it. Which pair, when the bodies meet through
    /// several (see [`crate::Event::collider1`]): the touching pair with the smallest
    /// handles when they start touching, kept while it touches, the smallest of those
    /// still touching when it stops, the last to stop when they stop; without a touch,
    /// a pair in proximity, kept likewise. The choice depends only on which pairs touch
    /// in each step, so both trackings and both pair walks name the same pair. `None`
    /// for structural and logical edges, and before an edge's first refresh. O(1).
    #[inline]
    pub fn colliders(&self) -> Option<(ColliderHandle, ColliderHandle)> {
        (self.named != no_pair()).then_some((self.named[0], self.named[1]))
    }

    /// Whether the edge was on at its last refresh before this one (touching, or for
    /// a trigger's edge overlapping): after the cache's `begin_update`.
    fn was_on(&self) -> bool {
        match self.kind {
            EdgeKind::Geometric => self.cache.proximity_old,
            _ => self.cache.touching_old,
        }
    }

    /// Starts this refresh's choice of the pair to name, after the cache's
    /// `begin_update`. `events`: touching tracking, where a pair that keeps touching
    /// is not met (Rapier reports only its start and stop). O(1).
    pub(crate) fn begin_naming(&mut self, events: bool) {
        self.naming.before = self.named;
        self.naming.lost = false;
        self.naming.rank = if self.named == no_pair() || !self.was_on() {
            RANK_NONE
        } else if events {
            RANK_KEPT
        } else {
            RANK_STOPPED
        };
    }

    /// A collider pair of the edge met in this refresh (*A*'s collider first),
    /// touching (`on`; for a trigger's edge, overlapping) or only in proximity.
    /// O(1).
    #[inline]
    pub(crate) fn meet_pair(&mut self, pair: [ColliderHandle; 2], on: bool) {
        let before = pair == self.naming.before;
        let rank = match (on, before) {
            (true, true) if self.was_on() => RANK_KEPT,
            (true, _) => RANK_TOUCHING,
            (false, true) => RANK_NEAR_KEPT,
            (false, false) => RANK_NEAR,
        };
        if rank > self.naming.rank
            || (rank == self.naming.rank && pair_key(pair) < pair_key(self.named))
        {
            self.named = pair;
            self.naming.rank = rank;
        }
    }

    /// A collider pair of the edge stopped touching (touching tracking): if it is the
    /// named one, it stays named unless another pair touches at the end of the
    /// refresh ([`Self::naming_unsettled`]). O(1).
    pub(crate) fn pair_stopped(&mut self, pair: [ColliderHandle; 2]) {
        if pair == self.named && self.naming.rank >= RANK_TOUCHING {
            self.naming.rank = RANK_STOPPED;
            self.naming.lost = true;
        }
    }

    /// Whether the edge touches after this refresh but its named pair may not
    /// (touching tracking): it stopped, or none was named; the caller names the
    /// touching pair with the smallest handles, read from Rapier
    /// ([`Self::set_named`]). O(1).
    pub(crate) fn naming_unsettled(&self) -> bool {
        self.cache.touching && (self.naming.lost || self.naming.rank < RANK_TOUCHING)
    }

    /// Whether `x` is a better pair to name than `y`, both touching now, when the
    /// touching pairs are read from Rapier (a rescan): the pair named already, else
    /// the smaller handles. O(1).
    pub(crate) fn prefers_name(&self, x: [ColliderHandle; 2], y: [ColliderHandle; 2]) -> bool {
        let (kx, ky) = (x == self.named, y == self.named);
        kx > ky || (kx == ky && pair_key(x) < pair_key(y))
    }

    /// Names `pair` (*A*'s collider first), a pair that touches now. O(1).
    pub(crate) fn set_named(&mut self, pair: [ColliderHandle; 2]) {
        self.named = pair;
        self.naming.rank = RANK_TOUCHING;
        self.naming.lost = false;
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
