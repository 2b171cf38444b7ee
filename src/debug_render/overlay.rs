//! The overlay itself: [`GraphOverlay`] with its buffers, one [`GraphOverlay::render`]
//! call as its steps (place the nodes, key the groups, draw the edges, draw the markers)
//! and what a call drew ([`OverlayStats`]).

use rapier3d::math::Vector;
use rapier3d::pipeline::DebugRenderBackend;
use rapier3d::prelude::{ColliderSet, RigidBodySet};

use super::OverlayStyle;
use crate::graph::NodeId;
use crate::{ContactLayer, WorldView};

/// What one [`GraphOverlay::render`] drew and left out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OverlayStats {
    /// Lines passed to the backend.
    pub lines: usize,
    /// Touching edges drawn (one line each).
    pub touching: usize,
    /// Proximity-only edges drawn (one line each).
    pub proximity: usize,
    /// Trigger edges drawn (`trigger_dashes` lines each, at least 1 and at most 64).
    pub trigger: usize,
    /// Structural edges drawn (one line each).
    pub structural: usize,
    /// State markers drawn ([`MarkerShape::lines`](super::MarkerShape::lines) lines each).
    pub markers: usize,
    /// Primitives (markers, edges) the backend's
    /// [`filter_object`](DebugRenderBackend::filter_object) refused.
    pub filtered: usize,
    /// Body, collider, trigger and container nodes without a finite position: a body or
    /// collider the sets do not hold (stale handle), a non-finite pose, an unbounded
    /// shape (a half-space has no centre), a container without a placed member.
    pub unplaced_nodes: usize,
    /// Edges of a drawn layer left out because an end has no position (or its object
    /// is gone from the sets).
    pub skipped_edges: usize,
}

/// Draws a [`ContactLayer`]'s graph into a [`DebugRenderBackend`] (what and how: the
/// [module docs](super)). Holds the style and buffers reused from call to call.
///
/// ```
/// use rapier3d::prelude::*;
/// use rapier_contact_graph::debug_render::GraphOverlay;
/// use rapier_contact_graph::ContactLayer;
///
/// /// A backend that only counts lines (any `DebugRenderBackend` will do).
/// #[derive(Default)]
/// struct Count(usize);
/// impl DebugRenderBackend for Count {
///     fn draw_line(&mut self, _: DebugRenderObject, _: Vector, _: Vector, _: DebugColor) {
///         self.0 += 1;
///     }
/// }
///
/// let mut world = PhysicsWorld::new();
/// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
/// world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.99, 0.0)),
///     ColliderBuilder::ball(0.5),
/// );
/// let mut layer = ContactLayer::new();
/// layer.step(&mut world);
///
/// let mut backend = Count::default();
/// // Rapier's own picture first, the graph on top, into the same backend.
/// // (`world.debug_render` calls `DebugRenderPipeline::render` with the world's sets.)
/// let mut pipeline = DebugRenderPipeline::default();
/// world.debug_render(&mut pipeline, &mut backend);
/// let rapier_lines = backend.0;
/// let mut overlay = GraphOverlay::default();
/// let stats = overlay.render(&mut backend, &layer, &world.bodies, &world.colliders);
/// assert_eq!(stats.touching, 1); // ball – ground
/// assert_eq!(stats.markers, 2); // one state marker per body
/// assert_eq!(backend.0 - rapier_lines, stats.lines);
/// ```
#[derive(Clone, Debug, Default)]
pub struct GraphOverlay {
    /// What to draw and how; change it between calls at will.
    pub style: OverlayStyle,
    /// Node slot → its position in this call (generation checked).
    pub(super) places: Vec<Option<(NodeId, Vector)>>,
    /// Group slot → (generation, colour key).
    pub(super) group_keys: Vec<Option<(u32, u32)>>,
}

/// What one [`GraphOverlay::render`] reads: the layer and the sets it analysed.
#[derive(Clone, Copy)]
pub(super) struct Sets<'a> {
    pub(super) layer: &'a ContactLayer,
    pub(super) bodies: &'a RigidBodySet,
    pub(super) colliders: &'a ColliderSet,
}

impl GraphOverlay {
    /// An overlay drawing with `style`. O(1).
    pub fn new(style: OverlayStyle) -> Self {
        GraphOverlay {
            style,
            places: Vec::new(),
            group_keys: Vec::new(),
        }
    }

    /// Draws `layer`'s graph into `backend`, reading positions and states from `bodies`
    /// and `colliders` (the sets the layer analysed; stale handles are skipped). Composes
    /// with Rapier's `DebugRenderPipeline::render` on the same backend, before or after
    /// it. Deterministic; cost in the module docs.
    pub fn render<B: DebugRenderBackend + ?Sized>(
        &mut self,
        backend: &mut B,
        layer: &ContactLayer,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> OverlayStats {
        let sets = Sets {
            layer,
            bodies,
            colliders,
        };
        let mut stats = OverlayStats::default();
        self.place_nodes(sets, &mut stats);
        self.key_groups(layer.groups());
        self.draw_edges(backend, sets, &mut stats);
        let size = self.style.marker_size;
        if self.style.state_markers && size.is_finite() && size > 0.0 {
            self.draw_markers(backend, sets, &mut stats);
        }
        stats
    }

    /// [`Self::render`] with the sets of a [`WorldView`].
    pub fn render_view<B: DebugRenderBackend + ?Sized>(
        &mut self,
        backend: &mut B,
        layer: &ContactLayer,
        view: &WorldView,
    ) -> OverlayStats {
        self.render(backend, layer, view.bodies, view.colliders)
    }
}
