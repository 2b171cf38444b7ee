//! Edge insertion and the proximity / touching marks (paper Figs. 3 and 5).
//!
//! Rapier's narrow phase already holds every broad-phase overlap as a contact pair
//! (touching or not), so the paper's list `O` of overlaps is read from it, body by
//! body, through `NarrowPhase::contact_pairs_with` on the colliders of the bodies that
//! moved. Walking `contact_pairs()` instead would cost in proportion to *all* pairs,
//! resting ones included: far more than Rapier's own sleeping step costs on a settled
//! pile (measured: `docs/rapier-notes.md`).
//!
//! A collider pair seen from both of its bodies (both awake) is aggregated once: from
//! the body with the smaller node index.

use rapier3d::geometry::ContactPair;
use rapier3d::math::{Pose, Real};
use rapier3d::prelude::ColliderHandle;

use crate::graph::validate::edge_allowed;
use crate::graph::{ContactCache, ContactGraph, EdgeId, EdgeKind, NodeId};
use crate::util::rapier::pose_is_finite;

/// Bitwise equality of two poses: "unchanged" in the paper's sense means the narrow
/// phase would return exactly the same result.
fn same_pose(p: &Pose, q: &Pose) -> bool {
    let a = [
        p.translation.x,
        p.translation.y,
        p.translation.z,
        p.rotation.x,
        p.rotation.y,
        p.rotation.z,
        p.rotation.w,
    ];
    let b = [
        q.translation.x,
        q.translation.y,
        q.translation.z,
        q.rotation.x,
        q.rotation.y,
        q.rotation.z,
        q.rotation.w,
    ];
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Starts this step's update of an edge: shifts the state to `e_old`, clears the
/// aggregates and refreshes the relative transform (unless a pose is not finite, in
/// which case the last finite one is kept and marked changed).
#[inline]
pub(crate) fn begin_edge_update(
    cache: &mut ContactCache,
    pose_a: Option<&Pose>,
    pose_b: Option<&Pose>,
    details: bool,
) {
    cache.begin_update(details);
    if !details {
        return;
    }
    match (pose_a, pose_b) {
        (Some(pa), Some(pb)) if pose_is_finite(pa) && pose_is_finite(pb) => {
            let rel = pa.inv_mul(pb);
            cache.relative_pose_changed = !same_pose(&rel, &cache.relative_pose);
            cache.relative_pose = rel;
        }
        _ => cache.relative_pose_changed = true,
    }
}

/// A penetration raised to what the deepest contact point's distance `deepest` says
/// (left as it is while no point was found: `deepest` infinite). O(1).
#[inline]
pub(crate) fn penetration_with(penetration: Real, deepest: Real) -> Real {
    if deepest.is_finite() {
        penetration.max(-deepest).max(0.0)
    } else {
        penetration
    }
}

/// Adds one Rapier collider pair to an edge's aggregates. `flip` is true when the
/// pair's `collider1` belongs to the edge's *B* node (Rapier's normals point from
/// collider 1 to collider 2; the edge's from *A* to *B*). Without `details`, only
/// proximity, touching and the contact count are gathered.
#[inline]
pub(crate) fn accumulate_pair(
    cache: &mut ContactCache,
    pair: &ContactPair,
    flip: bool,
    details: bool,
) {
    cache.collider_pairs += 1;
    cache.proximity = true;
    if !details {
        let mut count = 0;
        for m in pair.solver_manifolds() {
            count += m.data.solver_contacts.len() as u32;
        }
        cache.contact_count += count;
        cache.touching |= count > 0 || pair.has_any_active_contact();
        return;
    }
    let mut deepest = cache.min_distance;
    for m in pair.manifolds() {
        let n = if flip { -m.data.normal } else { m.data.normal };
        for p in &m.points {
            // Ties (a body in a corner touching two walls equally deep) are broken by
            // the normal itself, so the result does not depend on the order in which
            // the collider pairs are visited.
            let deeper =
                p.dist < deepest || (p.dist == deepest && normal_order(n, cache.normal).is_gt());
            if p.dist.is_finite() && deeper {
                deepest = p.dist;
                cache.normal = n;
            }
        }
    }
    cache.min_distance = deepest;
    cache.max_penetration = penetration_with(cache.max_penetration, deepest);
    if pair.has_any_active_contact() {
        cache.touching = true;
    }
    let mut impulse: Real = 0.0;
    let mut push = cache.push;
    for m in pair.solver_manifolds() {
        cache.contact_count += m.data.solver_contacts.len() as u32;
        let n = if flip { -m.data.normal } else { m.data.normal };
        for p in &m.points {
            impulse += p.data.impulse;
            push += n * p.data.impulse;
        }
    }
    if push.is_finite() {
        cache.push = push;
    }
    if impulse.is_finite() {
        cache.normal_impulse += impulse;
    }
}

/// A total order on normals, for tie-breaking.
fn normal_order(a: rapier3d::math::Vector, b: rapier3d::math::Vector) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x)
        .then(a.y.total_cmp(&b.y))
        .then(a.z.total_cmp(&b.z))
}

/// Per-step counters of the pair walk.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WalkCounters {
    /// Bodies whose collider pairs were walked.
    pub bodies: usize,
    /// Rapier collider pairs read.
    pub collider_pairs: usize,
    /// Edges refreshed from a collider pair.
    pub edges: usize,
    /// Whether Rapier stepped since the last analysis without the layer (the user's
    /// own `world.step()`, or another layer's step) and this analysis therefore read
    /// the world in full (see
    /// [`ContactLayer::pre_step`](crate::ContactLayer::pre_step)).
    #[cfg_attr(feature = "serde", serde(default))]
    pub unseen_step: bool,
}

/// The edge a collider pair belongs to, or `None` if the pair makes no edge (Table 2
/// excludes it, or an owner is unknown).
pub(crate) fn physical_edge_for(
    graph: &mut ContactGraph,
    me: NodeId,
    other: NodeId,
    step: u64,
) -> Option<EdgeId> {
    let (k1, k2) = (graph.node(me)?.kind(), graph.node(other)?.kind());
    if !edge_allowed(EdgeKind::Physical, k1, k2) {
        return None;
    }
    let id = graph.ensure_edge(me, other, EdgeKind::Physical, step)?;
    (graph.edge(id)?.kind() == EdgeKind::Physical).then_some(id)
}

/// The collider of a pair that is not `mine`.
pub(crate) fn other_collider(pair: &ContactPair, mine: ColliderHandle) -> ColliderHandle {
    if pair.collider1 == mine {
        pair.collider2
    } else {
        pair.collider1
    }
}
