//! The drawing: the edge layers in order, each edge from its two ends (resolved,
//! anchored, oriented, filtered) to its lines, the state markers, and the line figures
//! (solid, dashed, marker) every backend can draw.

use rapier3d::math::{Real, Vector};
use rapier3d::pipeline::{DebugColor, DebugRenderBackend, DebugRenderObject};

use super::overlay::Sets;
use super::place::End;
use super::{BodyState, GraphOverlay, MarkerShape, OverlayStats};
use crate::graph::{EdgeKind, Node, NodeKind, NodeSource};

/// The edge layers, in drawing order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layer {
    Proximity,
    Structural,
    Trigger,
    Touching,
}

impl Layer {
    fn of(self, kind: EdgeKind, touching: bool, proximate: bool) -> bool {
        match self {
            Layer::Proximity => kind == EdgeKind::Physical && proximate && !touching,
            Layer::Structural => kind == EdgeKind::Structural,
            Layer::Trigger => kind == EdgeKind::Geometric,
            Layer::Touching => kind == EdgeKind::Physical && touching,
        }
    }
}

impl GraphOverlay {
    /// Draws the edge layers the style turns on, in [`Layer`] order. O(layers × edge
    /// slots).
    pub(super) fn draw_edges<B: DebugRenderBackend + ?Sized>(
        &self,
        backend: &mut B,
        sets: Sets,
        stats: &mut OverlayStats,
    ) {
        let style = &self.style;
        let layers = [
            (style.proximity_edges, Layer::Proximity),
            (style.structural_edges, Layer::Structural),
            (style.trigger_edges, Layer::Trigger),
            (style.touching_edges, Layer::Touching),
        ];
        for (on, which) in layers {
            if !on {
                continue;
            }
            for (_, e) in sets.layer.graph().edges() {
                if which.of(e.kind(), e.is_touching(), e.is_proximate()) {
                    self.draw_edge(backend, sets, which, e, stats);
                }
            }
        }
    }

    /// Draws edge `e` of layer `which`, or counts why it is left out. Steps: resolve both
    /// ends, anchor a scenery end, orient, filter, pick the edge's object, stroke.
    fn draw_edge<B: DebugRenderBackend + ?Sized>(
        &self,
        backend: &mut B,
        sets: Sets,
        which: Layer,
        e: &crate::Edge,
        stats: &mut OverlayStats,
    ) {
        let graph = sets.layer.graph();
        let (Some(na), Some(nb)) = (graph.node(e.a()), graph.node(e.b())) else {
            stats.skipped_edges += 1;
            return;
        };
        let (Some(mut a), Some(mut b)) = (self.end(sets, e.a(), na), self.end(sets, e.b(), nb))
        else {
            stats.skipped_edges += 1;
            return;
        };
        if self.style.anchor_on_scenery && e.kind() == EdgeKind::Physical {
            Self::anchor_scenery(sets, (na, &mut a), (nb, &mut b));
        }
        let Some((pa, pb)) = oriented(which, nb, &a, &b) else {
            stats.skipped_edges += 1;
            return;
        };
        // Every end's object must pass the backend's filter.
        for object in [a.object, b.object].into_iter().flatten() {
            if !backend.filter_object(object) {
                stats.filtered += 1;
                return;
            }
        }
        let Some(object) = edge_object(&a, &b) else {
            stats.skipped_edges += 1; // two containers: not a graph the layer builds
            return;
        };
        self.stroke(backend, which, object, (pa, pb), (na, nb), stats);
    }

    /// Draws an edge of layer `which` from `pa` to `pb` in the layer's colour and
    /// figure, counting it.
    fn stroke<B: DebugRenderBackend + ?Sized>(
        &self,
        backend: &mut B,
        which: Layer,
        object: DebugRenderObject,
        (pa, pb): (Vector, Vector),
        (na, nb): (&Node, &Node),
        stats: &mut OverlayStats,
    ) {
        let style = &self.style;
        match which {
            Layer::Proximity => {
                stats.lines += line(backend, object, pa, pb, style.proximity_color);
                stats.proximity += 1;
            }
            Layer::Structural => {
                stats.lines += line(backend, object, pa, pb, style.structural_color);
                stats.structural += 1;
            }
            Layer::Trigger => {
                stats.lines += dashed(
                    backend,
                    object,
                    pa,
                    pb,
                    style.trigger_dashes,
                    style.trigger_color,
                );
                stats.trigger += 1;
            }
            Layer::Touching => {
                let color = self.touching_color(na, nb);
                stats.lines += line(backend, object, pa, pb, color);
                stats.touching += 1;
            }
        }
    }

    /// A touching edge's colour: its group's (the first end's group with a key), or
    /// [`OverlayStyle::touching_color`](super::OverlayStyle::touching_color).
    fn touching_color(&self, na: &Node, nb: &Node) -> DebugColor {
        let style = &self.style;
        let key = style
            .group_colors
            .then(|| {
                [na, nb]
                    .iter()
                    .find_map(|n| n.group())
                    .and_then(|g| self.group_key_of(g))
            })
            .flatten();
        key.map_or(style.touching_color, |k| style.group_color(k))
    }

    /// Draws a state marker at every body and every collider without a body that has a
    /// place and passes the backend's filter. O(node slots).
    pub(super) fn draw_markers<B: DebugRenderBackend + ?Sized>(
        &self,
        backend: &mut B,
        sets: Sets,
        stats: &mut OverlayStats,
    ) {
        let style = &self.style;
        for (id, n) in sets.layer.graph().nodes() {
            let Some(state) = (match n.source() {
                NodeSource::StaticCollider(_) => Some(BodyState::Insulator),
                NodeSource::Body(h) => {
                    BodyState::of_body(sets.layer, sets.bodies, n, h, style.rest_speed)
                }
                _ => continue,
            }) else {
                continue; // a stale body: counted unplaced already
            };
            let Some(End {
                object: Some(object),
                pos: Some(pos),
                ..
            }) = self.end(sets, id, n)
            else {
                continue; // unplaced: counted already
            };
            if !backend.filter_object(object) {
                stats.filtered += 1;
                continue;
            }
            let color = style.states.get(state);
            stats.lines += marker(backend, object, pos, style.marker, style.marker_size, color);
            stats.markers += 1;
        }
    }
}

/// The ends' positions, from the trigger or container to the body for trigger and
/// structural edges; `None` if an end has none.
fn oriented(which: Layer, nb: &Node, a: &End, b: &End) -> Option<(Vector, Vector)> {
    let (Some(pa), Some(pb)) = (a.pos, b.pos) else {
        return None;
    };
    let from_b = match which {
        Layer::Trigger => nb.kind() == NodeKind::Sensor,
        Layer::Structural => nb.kind().category() == crate::Category::Container,
        _ => false,
    };
    Some(if from_b { (pb, pa) } else { (pa, pb) })
}

/// The object an edge's lines carry: the simulated end's body, else a body, else the
/// sensor or collider; end A on ties. `None` when neither end has one.
fn edge_object<'a>(a: &End<'a>, b: &End<'a>) -> Option<DebugRenderObject<'a>> {
    let rank = |end: &End| match end.object {
        Some(DebugRenderObject::RigidBody(..)) if end.simulated => 3,
        Some(DebugRenderObject::RigidBody(..)) => 2,
        Some(_) => 1,
        None => 0,
    };
    if rank(b) > rank(a) {
        b.object
    } else {
        a.object
    }
}

/// Draws `a`–`b` unless a coordinate is not finite (a huge marker size or far-apart
/// ends can overflow); returns the number of lines drawn (0 or 1).
fn line<B: DebugRenderBackend + ?Sized>(
    backend: &mut B,
    object: DebugRenderObject,
    a: Vector,
    b: Vector,
    color: DebugColor,
) -> usize {
    if a.is_finite() && b.is_finite() {
        backend.draw_line(object, a, b, color);
        1
    } else {
        0
    }
}

/// Most dashes a trigger edge is drawn with.
const MAX_DASHES: u32 = 64;

/// Draws `a`–`b` as `dashes` dashes with `dashes − 1` equal gaps (solid for 0 or 1; at
/// most [`MAX_DASHES`]); returns the number of lines.
fn dashed<B: DebugRenderBackend + ?Sized>(
    backend: &mut B,
    object: DebugRenderObject,
    a: Vector,
    b: Vector,
    dashes: u32,
    color: DebugColor,
) -> usize {
    let n = dashes.clamp(1, MAX_DASHES);
    let pieces = (2 * n - 1) as Real;
    let mut drawn = 0;
    for i in 0..n {
        let t0 = (2 * i) as Real / pieces;
        let t1 = (2 * i + 1) as Real / pieces;
        drawn += line(backend, object, a.lerp(b, t0), a.lerp(b, t1), color);
    }
    drawn
}

/// Draws a marker of half size `s` at `p`; returns the number of lines.
fn marker<B: DebugRenderBackend + ?Sized>(
    backend: &mut B,
    object: DebugRenderObject,
    p: Vector,
    shape: MarkerShape,
    s: Real,
    color: DebugColor,
) -> usize {
    let axes = [Vector::X * s, Vector::Y * s, Vector::Z * s];
    let mut drawn = 0;
    match shape {
        MarkerShape::Cross => {
            for d in axes {
                drawn += line(backend, object, p - d, p + d, color);
            }
        }
        MarkerShape::Octahedron => {
            for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                for (si, sj) in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
                    drawn += line(backend, object, p + axes[i] * si, p + axes[j] * sj, color);
                }
            }
        }
    }
    drawn
}
