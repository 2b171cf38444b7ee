//! The obsolete test of §3.1: when may an edge whose proximity vanished be removed?
//!
//! The paper keeps an edge after its bodies separate (so a quick return finds the
//! cache warm) and removes it when "the orthogonal distance along the axes between the
//! AABBs of the corresponding nodes [is] twice the maximum edge size of the AABBs":
//! a few subtractions and comparisons. Edges are only tested once their vanishing
//! was reported (§4: "only allowing edges to become obsolete if they were at least
//! marked as vanishing close proximities last time"), so no End event is ever lost.
//!
//! A body's AABB is the union of its enabled, non-sensor colliders' AABBs. A node
//! without such geometry (all colliders removed or disabled) cannot touch anything:
//! its dead physical edges are obsolete at once. A non-finite AABB never is: a
//! body that exploded keeps its edges until its pose is finite again.

use rapier3d::math::Real;
use rapier3d::parry::bounding_volume::{Aabb, BoundingVolume};

use crate::graph::NodeSource;
use crate::WorldView;

/// The AABB of a node's geometry, `None` when it has none.
pub(crate) fn node_aabb(view: &WorldView, source: NodeSource) -> Option<Aabb> {
    match source {
        NodeSource::Body(h) => {
            let rb = view.bodies.get(h)?;
            let mut acc: Option<Aabb> = None;
            for &ch in rb.colliders() {
                let Some(c) = view.colliders.get(ch) else {
                    continue;
                };
                if !c.is_enabled() || c.is_sensor() {
                    continue;
                }
                let a = c.compute_aabb();
                acc = Some(match acc {
                    Some(x) => x.merged(&a),
                    None => a,
                });
            }
            acc
        }
        NodeSource::StaticCollider(h) | NodeSource::Sensor(h) => {
            view.colliders.get(h).map(|c| c.compute_aabb())
        }
        NodeSource::Container(_) | NodeSource::Layer(_) => None,
    }
}

/// The §3.1 test on two AABBs: some axis gap exceeds twice the largest AABB edge.
/// Any non-finite input answers `false`.
pub fn aabbs_obsolete(a: &Aabb, b: &Aabb) -> bool {
    if !(a.mins.is_finite() && a.maxs.is_finite() && b.mins.is_finite() && b.maxs.is_finite()) {
        // An exploded body never makes its edges obsolete.
        return false;
    }
    let edge = (a.maxs - a.mins)
        .max_element()
        .max((b.maxs - b.mins).max_element());
    let gap_lo = a.mins - b.maxs;
    let gap_hi = b.mins - a.maxs;
    let gap: Real = gap_lo.max(gap_hi).max_element();
    gap > 2.0 * edge
}

/// The §3.1 test on two nodes.
pub(crate) fn is_obsolete(view: &WorldView, a: NodeSource, b: NodeSource) -> bool {
    match (node_aabb(view, a), node_aabb(view, b)) {
        (Some(x), Some(y)) => aabbs_obsolete(&x, &y),
        // No geometry on one side: nothing can bring the pair back into contact
        // until a collider is attached again, which re-creates the edge.
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::math::Vector;

    fn cube(x: Real) -> Aabb {
        Aabb::new(Vector::new(x, 0.0, 0.0), Vector::new(x + 1.0, 1.0, 1.0))
    }

    #[test]
    fn obsolete_needs_a_gap_of_twice_the_largest_edge() {
        assert!(!aabbs_obsolete(&cube(0.0), &cube(1.5)));
        assert!(
            !aabbs_obsolete(&cube(0.0), &cube(3.0)),
            "gap 2.0 is not more than 2.0"
        );
        assert!(aabbs_obsolete(&cube(0.0), &cube(3.01)));
        assert!(aabbs_obsolete(&cube(3.01), &cube(0.0)), "symmetric");
        let big = Aabb::new(Vector::new(-10.0, 0.0, 0.0), Vector::new(-5.0, 5.0, 5.0));
        assert!(
            !aabbs_obsolete(&big, &cube(4.0)),
            "largest edge of either counts"
        );
    }

    #[test]
    fn nan_is_never_obsolete() {
        let nan = Aabb::new(Vector::splat(Real::NAN), Vector::splat(Real::NAN));
        assert!(!aabbs_obsolete(&nan, &cube(100.0)));
    }
}
