//! Deep penetration: touching edges deeper than a fraction of the smaller body's size.
//!
//! Only the edges refreshed in the step are looked at: a sleeping pair is frozen, and
//! if it was deep it was reported when it was last refreshed. A body's size is the
//! smallest extent of the union of its non-sensor colliders' AABBs in its own frame
//! (a static collider's: its shape's local AABB); it is cached per node and recomputed
//! when the body's collider count changes (a shape replaced in place with `set_shape`
//! is not noticed). The depths: under proximity tracking with the details kept
//! (`Coherence::details_kept`), the touched edges' caches; otherwise (touching
//! tracking, the default) the touching edges of the refreshed bodies, read from
//! Rapier's narrow phase (the same figures: the same accumulation of the same pairs).
//! O(touching pairs of the awake bodies) per step either way.

use std::collections::{HashMap, HashSet};

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::ColliderHandle;

use super::{Ctx, MonitorConfig, Peaks, Violation, ViolationKind};
use crate::coherence::details::touching_depths;
use crate::graph::{EdgeId, EdgeKind, NodeId, NodeSource};
use crate::WorldView;

#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Penetration {
    /// Edges in a reported deep episode.
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_set"))]
    deep: HashSet<EdgeId>,
    /// Node → (collider count when measured, size).
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    sizes: HashMap<NodeId, (usize, Real)>,
    /// The deepest contact of the last check relative to its limit, with the node of
    /// one of its bodies (for the repair's early warning).
    pub(crate) last_deepest: Option<(Real, NodeId)>,
}

/// The smallest extent of an AABB given by its corners.
fn smallest_extent(mins: Vector, maxs: Vector) -> Real {
    let e = maxs - mins;
    e.x.min(e.y).min(e.z)
}

fn collider_count(view: &WorldView, source: NodeSource) -> usize {
    match source {
        NodeSource::Body(h) => view.bodies.get(h).map_or(0, |rb| rb.colliders().len()),
        _ => 1,
    }
}

/// The size of a body or static collider (see the module docs); `None` without solid
/// colliders.
fn measure(view: &WorldView, source: NodeSource) -> Option<Real> {
    let local = |c: ColliderHandle| {
        let co = view.colliders.get(c).filter(|co| !co.is_sensor())?;
        Some(match co.position_wrt_parent() {
            Some(p) => co.shape().compute_aabb(p),
            None => co.shape().compute_local_aabb(),
        })
    };
    let mut union: Option<(Vector, Vector)> = None;
    let mut add = |c: ColliderHandle| {
        if let Some(a) = local(c) {
            union = Some(match union {
                Some((lo, hi)) => (lo.min(a.mins), hi.max(a.maxs)),
                None => (a.mins, a.maxs),
            });
        }
    };
    match source {
        NodeSource::Body(h) => {
            for &c in view.bodies.get(h)?.colliders() {
                add(c);
            }
        }
        NodeSource::StaticCollider(c) => add(c),
        _ => return None,
    }
    let (lo, hi) = union?;
    Some(smallest_extent(lo, hi)).filter(|s| s.is_finite())
}

impl Penetration {
    pub(crate) fn forget_node(&mut self, n: NodeId) {
        self.sizes.remove(&n);
    }

    fn size(&mut self, view: &WorldView, n: NodeId, source: NodeSource) -> Option<Real> {
        let count = collider_count(view, source);
        if let Some(&(c, s)) = self.sizes.get(&n) {
            if c == count {
                return Some(s);
            }
        }
        let s = measure(view, source)?;
        self.sizes.insert(n, (count, s));
        Some(s)
    }

    // Long: one pass over the refreshed bodies' edges under either tracking, with its episode upkeep.
    pub(crate) fn check(
        &mut self,
        ctx: &Ctx,
        config: &MonitorConfig,
        out: &mut Vec<Violation>,
        peaks: &mut Peaks,
    ) {
        let layer = ctx.layer;
        let graph = layer.graph();
        if ctx.fresh {
            self.deep.retain(|&e| graph.edge(e).is_some());
            if self.sizes.len() > 2 * graph.node_count() + 64 {
                self.sizes.retain(|&n, _| graph.contains_node(n));
            }
        }
        self.last_deepest = None;
        // Under proximity tracking with the details kept, the touched edges (every
        // edge of a refreshed body) and their caches; under touching tracking, whose
        // touched edges are only those whose touching began or ended, the refreshed
        // bodies' touching edges with their depths read from Rapier in one pass over
        // each body's pairs.
        let mut edges: Vec<(EdgeId, Real)> = Vec::new();
        if layer.coherence().details_kept() {
            for &eid in layer.coherence().touched_edges() {
                let Some(e) = graph.edge(eid) else { continue };
                if e.kind() != EdgeKind::Physical || !e.is_touching() {
                    self.deep.remove(&eid);
                    continue;
                }
                edges.push((eid, e.cache().max_penetration));
            }
        } else {
            touching_depths(
                graph,
                ctx.view,
                layer.coherence().refreshed_nodes(),
                &mut edges,
            );
        }
        for (eid, depth) in edges {
            let Some(e) = graph.edge(eid) else { continue };
            let (a, b) = e.nodes();
            let (Some(na), Some(nb)) = (graph.node(a), graph.node(b)) else {
                continue;
            };
            let (sa, sb) = (na.source(), nb.source());
            let size_a = self.size(ctx.view, a, sa);
            let size_b = self.size(ctx.view, b, sb);
            let size = match (size_a, size_b) {
                (Some(x), Some(y)) => x.min(y),
                (Some(x), None) | (None, Some(x)) => x,
                (None, None) => continue,
            };
            let limit = config.penetration_fraction * size;
            if limit > 0.0 {
                let ratio = depth / limit;
                peaks.penetration = peaks.penetration.max(ratio);
                let simulated = if na.kind().is_simulated() { a } else { b };
                // Ties to the smaller node: the same whatever order the edges come in.
                let deeper = match self.last_deepest {
                    None => ratio > 0.0,
                    Some((r, n)) => ratio > r || (ratio == r && simulated < n),
                };
                if deeper {
                    self.last_deepest = Some((ratio, simulated));
                }
            }
            if depth.is_nan() || depth <= limit {
                self.deep.remove(&eid);
                continue;
            }
            if !self.deep.insert(eid) {
                continue; // the episode was reported already
            }
            // Report on a simulated body if there is one (the smaller of two), else on
            // the body end (a fixed or scripted body against static geometry).
            let rank = |n: &crate::graph::Node, size: Option<Real>| {
                (!n.kind().is_simulated(), size.unwrap_or(Real::INFINITY))
            };
            let a_first = rank(na, size_a) <= rank(nb, size_b);
            let order = if a_first {
                [(a, na), (b, nb)]
            } else {
                [(b, nb), (a, na)]
            };
            let Some((node, body)) = order.iter().find_map(|(id, n)| n.body().map(|h| (*id, h)))
            else {
                continue;
            };
            out.push(Violation {
                step: ctx.step,
                kind: ViolationKind::DeepPenetration,
                body,
                node: Some(node),
                value: depth,
            });
        }
    }
}
