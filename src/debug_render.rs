//! The contact graph as a debug-render overlay: draws the graph, its contact groups and
//! the state of every body into any Rapier [`DebugRenderBackend`] (bevy_rapier's debug
//! render, Rapier's testbed, a headless recorder of one's own), on top of what Rapier's
//! own [`DebugRenderPipeline`](rapier3d::pipeline::DebugRenderPipeline) draws.
//!
//! Needs the cargo feature `debug-render` (on by default), which turns on Rapier's own
//! `debug-render` feature (the backend trait lives behind it); it adds no dependency.
//!
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::debug_render::GraphOverlay;
//! use rapier_contact_graph::ContactLayer;
//!
//! /// A backend that only counts lines (any `DebugRenderBackend` will do).
//! #[derive(Default)]
//! struct Count(usize);
//! impl DebugRenderBackend for Count {
//!     fn draw_line(&mut self, _: DebugRenderObject, _: Vector, _: Vector, _: DebugColor) {
//!         self.0 += 1;
//!     }
//! }
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.99, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! layer.step(&mut world);
//!
//! let mut backend = Count::default();
//! // Rapier's own picture first, the graph on top, into the same backend.
//! // (`world.debug_render` calls `DebugRenderPipeline::render` with the world's sets.)
//! let mut pipeline = DebugRenderPipeline::default();
//! world.debug_render(&mut pipeline, &mut backend);
//! let rapier_lines = backend.0;
//! let mut overlay = GraphOverlay::default();
//! let stats = overlay.render(&mut backend, &layer, &world.bodies, &world.colliders);
//! assert_eq!(stats.touching, 1); // ball – ground
//! assert_eq!(stats.markers, 2); // one state marker per body
//! assert_eq!(backend.0 - rapier_lines, stats.lines);
//! ```
//!
//! # What it draws
//! Lines only, in this order (later ones on top in a painter's backend), each layer in
//! the graph's slot order:
//! 1. **Proximity edges** (off by default, [`OverlayStyle::proximity_edges`]): physical
//!    edges whose bodies are in Rapier's narrow phase but do not touch; one faint line.
//! 2. **Structural edges** (container ↔ member: composites, articulations, multibodies):
//!    one line from the container's hub to each member, in
//!    [`OverlayStyle::structural_color`]. A container has no place of its own; its hub is
//!    the mean of its members' positions, so a container is drawn as a star.
//! 3. **Trigger edges** (sensor ↔ body inside it): a *dashed* line from the sensor's
//!    centre to the body, in [`OverlayStyle::trigger_color`]. Dashes make them tell apart
//!    from every other line whatever the hues.
//! 4. **Touching edges** (physical edges with an active contact): one solid line per
//!    edge, whatever the number of collider pairs and contact points it aggregates, in
//!    the colour of the edge's contact group ([`OverlayStyle::group_color`]).
//! 5. **State markers**: a small octahedron (or 3-axis cross) at the centre of mass of
//!    every body, and at the centre of every collider without a body, coloured by its
//!    [`BodyState`] in the spirit of the paper's Fig. 17 ("purple means sleepy, red
//!    moving, blue absolute rest, green fixed"): green is *held* (fixated by the
//!    speed-ups), and this overlay tells Rapier's own sleep (dark purple) from the
//!    speed-ups' sleepy tag (purple), and shows insulators (grey) and disabled bodies.
//!
//! Logical edges (rule ↔ body) and rule and timer nodes are not drawn: they have no
//! place in space.
//!
//! # Design
//! - **Edges run between the bodies' centres of mass, not between contact points.** The
//!   overlay is a picture of the *graph*: one node per body, one line per edge, which is
//!   what "who touches whom" and "which bodies form a group" are about. Contact points
//!   are Rapier's business and Rapier already draws them
//!   ([`DebugRenderMode::CONTACTS`](rapier3d::pipeline::DebugRenderMode::CONTACTS));
//!   drawing them again would need the narrow phase, give k lines for an edge of k
//!   points instead of one, and mean nothing for trigger and structural edges.
//!   *Except on scenery*: the end of a physical edge on an insulator that is not held
//!   (a fixed ground, a wall, a kinematic platform; [`NodeKind::is_insulator`]) is drawn
//!   at the point of its colliders nearest to the other body's centre (parry's point
//!   projection), not at its centre of mass. A ground slab's centre says nothing about
//!   where a ball rests on it, and a pile of n balls would draw an n-pointed star through
//!   the scene to the middle of the floor; anchored on the surface, each ball gets a
//!   short line down to where it rests, and unbounded scenery (a half-space, whose centre
//!   does not exist) still gets its edges. [`OverlayStyle::anchor_on_scenery`] turns it
//!   off.
//! - **Rejected: reusing `DebugRenderPipeline`'s contact drawing**, e.g. recolouring its
//!   contact lines by group in a wrapping backend. It walks the narrow phase's collider
//!   pairs, so it cannot show what the graph adds: the aggregation per body pair,
//!   trigger and structural edges, groups (a group spans pairs the pipeline draws
//!   separately) and the bodies' states. The overlay complements it instead and takes
//!   the same kind of backend, so the two compose: call
//!   [`DebugRenderPipeline::render`](rapier3d::pipeline::DebugRenderPipeline::render),
//!   then [`GraphOverlay::render`], on the same backend.
//! - **Lines only.** `draw_line` is the one primitive every [`DebugRenderBackend`] must
//!   provide (Rapier's polylines and line strips are defaults built on it). Text labels
//!   or filled discs would need what only some backends have, so markers are small line
//!   figures and styles are colours and dashes.
//! - **Which [`DebugRenderObject`] a line carries.** Rapier 0.36 has no variant for a
//!   body pair, so every line carries the object of the Rapier entity it is about, in
//!   the variant Rapier itself uses for it: a body's marker
//!   [`DebugRenderObject::RigidBody`], the marker of a collider without a body
//!   [`DebugRenderObject::Collider`]; an edge the `RigidBody` of one of its bodies, a
//!   dynamic one first and end *A* on ties (so: the body inside a trigger, the member
//!   of a container, the ball on a fixed ground), or the `Collider` when neither end is
//!   a body (a collider without a body inside a trigger). Each primitive is
//!   drawn only if [`DebugRenderBackend::filter_object`] accepts the objects of *all*
//!   its ends (a sensor's `Collider`, the bodies), so a backend hiding a body hides its
//!   marker and its edges, and one hiding a sensor hides its trigger lines. Rejected:
//!   [`DebugRenderObject::ContactPair`] for touching edges. It needs the narrow phase and
//!   one particular collider pair, when the edge stands for all of them, and a backend
//!   hiding Rapier's contacts would then hide the graph as well. Consequence: a backend
//!   that filters out *every* `RigidBody` to hide Rapier's body axes hides the overlay
//!   too; hide the axes with `DebugRenderMode` (drop `RIGID_BODY_AXES`) instead. Backends
//!   that recolour by object (bevy_rapier's `ColliderDebugColor`) recolour only the
//!   markers of colliders without a body, which carry no state.
//! - **Group colours are stable.** A group keeps its [`GroupId`](crate::GroupId) while
//!   smaller groups merge into it and parts split off it, but the smaller group of a
//!   merge ends, and a group is rebuilt under a new id when a member is removed, made
//!   passive or changes kind, so a colour hashed from the id would jump whenever a
//!   group merges into a larger one or a body of a pile is fixated. The colour is keyed instead by the
//!   group's smallest member slot index ([`group_key`]), which stays while that body is
//!   in the group; when two groups merge, the result keeps the colour of one of them. The
//!   hue is the golden-ratio sequence `360° · frac(key · 0.618…)`: distinct keys get
//!   distinct hues, and neighbouring keys (bodies created one after another) get hues far
//!   apart.
//! - **Deterministic.** No hashing, clocks or threads: the same layer and sets give the
//!   same lines in the same order, bit for bit.
//! - **Forgiving.** Stale handles (a body or collider removed since the layer's last
//!   analysis, or sets that are not the layer's), non-finite poses and unbounded shapes
//!   never panic. A node without a finite position gets no marker and its edges are left
//!   out, except that scenery needs no position of its own (its end of a physical edge
//!   is the nearest point of its surface, which a half-space has); an edge with an end
//!   whose object is gone from the sets is left out. Both are counted in
//!   [`OverlayStats`], and no line with a non-finite coordinate is ever drawn.
//!
//! # Cost
//! [`GraphOverlay::render`]: O(node slots + edge slots) of the graph (its live nodes and
//! edges plus free slots), with O(log held bodies) per body for the speed-ups' state,
//! plus one point projection per collider of the scenery end of each drawn physical edge
//! (O(1) for primitive shapes, logarithmic for meshes). Nothing is allocated once the
//! overlay's buffers have grown to the graph's size (they are kept from call to call).

use rapier3d::math::{Real, Vector};
use rapier3d::pipeline::{DebugColor, DebugRenderBackend, DebugRenderObject};
use rapier3d::prelude::{ColliderSet, RigidBodyHandle, RigidBodySet};

use crate::graph::{EdgeKind, Node, NodeId, NodeKind, NodeSource};
use crate::groups::{Group, Groups};
use crate::{ContactLayer, WorldView};

/// Default [`OverlayStyle::rest_speed`]: 1 mm/s (and 1 mrad/s), well above the residual
/// speeds of bodies Rapier keeps awake on a support and well below visible motion.
pub const DEFAULT_REST_SPEED: Real = 1e-3;

/// The state a body's marker shows (the paper's Fig. 17, refined). [`BodyState::of`]
/// gives it; the rules, first match wins, are in the order of the variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyState {
    /// Disabled: by [`ContactLayer::set_body_disabled`] (the paper's *passive* body,
    /// §3.2) or in Rapier.
    Disabled,
    /// Held: fixated by the `fixate` speed-up (Fig. 17's "fixed", green).
    Held,
    /// An insulator: a fixed or kinematic body, or a collider without a body. The solver
    /// does not move it.
    Insulator,
    /// Asleep in Rapier.
    Asleep,
    /// Tagged sleepy by the speed-ups but still awake in Rapier (Fig. 17's "sleepy").
    Sleepy,
    /// Awake, with linear and angular speed at most [`OverlayStyle::rest_speed`]
    /// (Fig. 17's "absolute rest").
    Resting,
    /// Anything else (Fig. 17's "moving"), non-finite velocities included.
    Moving,
}

renamed_consts!(BodyState:
    Passive => Disabled, "renamed to BodyState::Disabled, Rapier's word";
);

impl BodyState {
    /// Every state, in rule order.
    pub const ALL: [BodyState; 7] = [
        BodyState::Disabled,
        BodyState::Held,
        BodyState::Insulator,
        BodyState::Asleep,
        BodyState::Sleepy,
        BodyState::Resting,
        BodyState::Moving,
    ];

    /// A short name, for legends.
    pub const fn name(self) -> &'static str {
        match self {
            BodyState::Disabled => "disabled",
            BodyState::Held => "held",
            BodyState::Insulator => "insulator",
            BodyState::Asleep => "asleep",
            BodyState::Sleepy => "sleepy",
            BodyState::Resting => "resting",
            BodyState::Moving => "moving",
        }
    }

    /// The state of node `node`: `Some` for a body node whose body `bodies` holds and
    /// for a collider without a body (always [`BodyState::Insulator`]); `None` for a
    /// stale node, a body `bodies` does not hold, and nodes that are not bodies
    /// (containers, triggers, rules, timers). `rest_speed` as
    /// [`OverlayStyle::rest_speed`]. O(log held bodies).
    pub fn of(
        layer: &ContactLayer,
        bodies: &RigidBodySet,
        node: NodeId,
        rest_speed: Real,
    ) -> Option<BodyState> {
        let n = layer.graph().node(node)?;
        match n.source() {
            NodeSource::StaticCollider(_) => Some(BodyState::Insulator),
            NodeSource::Body(h) => Some(Self::of_body(layer, bodies, n, h, rest_speed)?),
            _ => None,
        }
    }

    fn of_body(
        layer: &ContactLayer,
        bodies: &RigidBodySet,
        node: &Node,
        h: RigidBodyHandle,
        rest_speed: Real,
    ) -> Option<BodyState> {
        let rb = bodies.get(h)?;
        let speedups = layer.speedups();
        Some(if node.is_body_disabled() || !rb.is_enabled() {
            BodyState::Disabled
        } else if speedups.is_some_and(|s| s.is_fixated(h)) {
            BodyState::Held
        } else if !rb.is_dynamic() {
            BodyState::Insulator
        } else if rb.is_sleeping() {
            BodyState::Asleep
        } else if speedups.is_some_and(|s| s.is_sleepy(h)) {
            BodyState::Sleepy
        } else if rb.linvel().length() <= rest_speed && rb.angvel().length() <= rest_speed {
            BodyState::Resting
        } else {
            BodyState::Moving
        })
    }
}

/// The marker colour of each [`BodyState`], as Rapier [`DebugColor`]s (`[hue 0..=360,
/// saturation, lightness, alpha]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateColors {
    /// [`BodyState::Disabled`]: pale, half transparent grey.
    pub disabled: DebugColor,
    /// [`BodyState::Held`]: green (Fig. 17's "fixed").
    pub held: DebugColor,
    /// [`BodyState::Insulator`]: mid grey.
    pub insulator: DebugColor,
    /// [`BodyState::Asleep`]: dark purple (Rapier's own debug render darkens sleepers
    /// too).
    pub asleep: DebugColor,
    /// [`BodyState::Sleepy`]: purple (Fig. 17).
    pub sleepy: DebugColor,
    /// [`BodyState::Resting`]: blue (Fig. 17's "absolute rest").
    pub resting: DebugColor,
    /// [`BodyState::Moving`]: red (Fig. 17).
    pub moving: DebugColor,
}

impl Default for StateColors {
    fn default() -> Self {
        StateColors {
            disabled: [0.0, 0.0, 0.8, 0.5],
            held: [130.0, 0.75, 0.4, 1.0],
            insulator: [0.0, 0.0, 0.5, 1.0],
            asleep: [280.0, 0.55, 0.3, 1.0],
            sleepy: [280.0, 0.7, 0.55, 1.0],
            resting: [215.0, 0.85, 0.5, 1.0],
            moving: [0.0, 0.85, 0.5, 1.0],
        }
    }
}

impl StateColors {
    /// The colour of `state`.
    pub const fn get(&self, state: BodyState) -> DebugColor {
        match state {
            BodyState::Disabled => self.disabled,
            BodyState::Held => self.held,
            BodyState::Insulator => self.insulator,
            BodyState::Asleep => self.asleep,
            BodyState::Sleepy => self.sleepy,
            BodyState::Resting => self.resting,
            BodyState::Moving => self.moving,
        }
    }
}

/// The figure drawn at a body's centre for its state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MarkerShape {
    /// An octahedron's 12 edges (a diamond from any side, unlike Rapier's body axes,
    /// which start at the centre of mass and go one way).
    #[default]
    Octahedron,
    /// Three lines along the world axes, centred on the body: 3 lines instead of 12, for
    /// dense scenes.
    Cross,
}

impl MarkerShape {
    /// The number of lines one marker takes.
    pub const fn lines(self) -> usize {
        match self {
            MarkerShape::Octahedron => 12,
            MarkerShape::Cross => 3,
        }
    }
}

/// What the overlay draws and how. Colours are Rapier [`DebugColor`]s: `[hue 0..=360,
/// saturation 0..=1, lightness 0..=1, alpha 0..=1]`, as the backend expects them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayStyle {
    /// Draw touching edges (physical edges with an active contact), one line each, in
    /// their group's colour. Default on.
    pub touching_edges: bool,
    /// Draw proximity-only physical edges (in Rapier's narrow phase, not touching), one
    /// faint line each. Default off: a dense pile has many and they constrain nothing.
    pub proximity_edges: bool,
    /// Draw trigger edges (sensor ↔ body inside it), dashed. Default on.
    pub trigger_edges: bool,
    /// Draw structural edges (container ↔ member). Default on.
    pub structural_edges: bool,
    /// Draw a state marker at every body and every collider without a body. Default on.
    pub state_markers: bool,
    /// Colour touching edges by contact group; off, they all take
    /// [`Self::touching_color`]. Default on.
    pub group_colors: bool,
    /// Draw the scenery end of a physical edge (an insulator that is not held) at the
    /// point of its colliders nearest to the other end, not at its centre of mass (see
    /// the module docs). Default on.
    pub anchor_on_scenery: bool,
    /// Saturation of the group colours. Default 0.9 (no state colour has it, so a group
    /// colour never equals a marker's).
    pub group_saturation: f32,
    /// Lightness of the group colours. Default 0.5.
    pub group_lightness: f32,
    /// Alpha of the group colours. Default 1.
    pub group_alpha: f32,
    /// Colour of touching edges outside every group (between two insulators, groups
    /// switched off by the speed-ups, or [`Self::group_colors`] off). Default light grey.
    pub touching_color: DebugColor,
    /// Colour of proximity-only edges. Default grey at alpha 0.35.
    pub proximity_color: DebugColor,
    /// Colour of trigger edges. Default yellow.
    pub trigger_color: DebugColor,
    /// Number of dashes of a trigger edge; 0 or 1 draws it solid, at most 64. Default 5.
    pub trigger_dashes: u32,
    /// Colour of structural edges. Default a dull brown, unlike any group colour.
    pub structural_color: DebugColor,
    /// Marker colour of each body state.
    pub states: StateColors,
    /// The marker figure. Default [`MarkerShape::Octahedron`].
    pub marker: MarkerShape,
    /// Half size of a marker, in world units (metres). Default 0.1. A non-finite or
    /// non-positive size draws no markers.
    pub marker_size: Real,
    /// Speed (m/s, and rad/s) at or below which an awake body is
    /// [`BodyState::Resting`]. Default [`DEFAULT_REST_SPEED`]; 0 means exactly still.
    pub rest_speed: Real,
}

impl Default for OverlayStyle {
    fn default() -> Self {
        OverlayStyle {
            touching_edges: true,
            proximity_edges: false,
            trigger_edges: true,
            structural_edges: true,
            state_markers: true,
            group_colors: true,
            anchor_on_scenery: true,
            group_saturation: 0.9,
            group_lightness: 0.5,
            group_alpha: 1.0,
            touching_color: [0.0, 0.0, 0.65, 1.0],
            proximity_color: [0.0, 0.0, 0.6, 0.35],
            trigger_color: [55.0, 1.0, 0.5, 1.0],
            trigger_dashes: 5,
            structural_color: [30.0, 0.35, 0.4, 1.0],
            states: StateColors::default(),
            marker: MarkerShape::Octahedron,
            marker_size: 0.1,
            rest_speed: DEFAULT_REST_SPEED,
        }
    }
}

impl OverlayStyle {
    /// The colour of the group with key `key` ([`group_key`]): hue
    /// `360 · frac(key · (√5 − 1)/2)`, with [`Self::group_saturation`],
    /// [`Self::group_lightness`] and [`Self::group_alpha`]. Distinct keys give distinct
    /// hues. O(1).
    pub fn group_color(&self, key: u32) -> DebugColor {
        const INV_PHI: f64 = 0.618_033_988_749_894_9;
        let hue = (f64::from(key) * INV_PHI).fract() * 360.0;
        [
            hue as f32,
            self.group_saturation,
            self.group_lightness,
            self.group_alpha,
        ]
    }
}

/// The stable colour key of a group: its smallest member slot index ([`NodeId::index`]),
/// which survives the group's rebuilds as long as that body stays in it (`None` for a
/// group without members). O(members).
pub fn group_key(group: &Group) -> Option<u32> {
    group.bodies.iter().map(|n| n.index()).min()
}

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
    /// State markers drawn ([`MarkerShape::lines`] lines each).
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

/// Draws a [`ContactLayer`]'s graph into a [`DebugRenderBackend`] (see the module docs).
/// Holds the style and buffers reused from call to call.
#[derive(Clone, Debug, Default)]
pub struct GraphOverlay {
    /// What to draw and how; change it between calls at will.
    pub style: OverlayStyle,
    /// Node slot → its position in this call (generation checked).
    places: Vec<Option<(NodeId, Vector)>>,
    /// Group slot → (generation, colour key).
    group_keys: Vec<Option<(u32, u32)>>,
}

/// Boxes wider than this (metres) are unbounded shapes (half-spaces): they have no centre.
const UNBOUNDED: Real = 1.0e30;

/// A node's end of an edge: its Rapier object and its position.
struct End<'a> {
    object: Option<DebugRenderObject<'a>>,
    pos: Option<Vector>,
    /// A body the solver moves (Dynamic or Link): preferred as the edge's object.
    simulated: bool,
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
        let mut stats = OverlayStats::default();
        self.place_nodes(layer, bodies, colliders, &mut stats);
        self.key_groups(layer.groups());
        let style = self.style;
        let graph = layer.graph();

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
            for (_, e) in graph.edges() {
                if which.of(e.kind(), e.is_touching(), e.is_proximate()) {
                    self.draw_edge(backend, layer, bodies, colliders, which, e, &mut stats);
                }
            }
        }

        if style.state_markers && style.marker_size.is_finite() && style.marker_size > 0.0 {
            for (id, n) in graph.nodes() {
                let Some(state) = (match n.source() {
                    NodeSource::StaticCollider(_) => Some(BodyState::Insulator),
                    NodeSource::Body(h) => {
                        BodyState::of_body(layer, bodies, n, h, style.rest_speed)
                    }
                    _ => continue,
                }) else {
                    continue; // a stale body: counted unplaced already
                };
                let Some(End {
                    object: Some(object),
                    pos: Some(pos),
                    ..
                }) = self.end(bodies, colliders, id, n)
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

    /// Fills `places`: bodies at their centre of mass, colliders without a body and
    /// sensors at their bounding box's centre, then containers at the mean of their
    /// members. O(node slots + structural edges).
    fn place_nodes(
        &mut self,
        layer: &ContactLayer,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        stats: &mut OverlayStats,
    ) {
        let graph = layer.graph();
        self.places.clear();
        let mut containers = false;
        for (id, n) in graph.nodes() {
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
        if !containers {
            return;
        }
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

    fn set_place(&mut self, id: NodeId, p: Vector) {
        let i = id.index() as usize;
        if self.places.len() <= i {
            self.places.resize(i + 1, None);
        }
        self.places[i] = Some((id, p));
    }

    fn place(&self, id: NodeId) -> Option<Vector> {
        match self.places.get(id.index() as usize) {
            Some(Some((n, p))) if *n == id => Some(*p),
            _ => None,
        }
    }

    /// Fills `group_keys`. O(groups + members).
    fn key_groups(&mut self, groups: &Groups) {
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

    fn group_key_of(&self, id: crate::GroupId) -> Option<u32> {
        match self.group_keys.get(id.index() as usize) {
            Some(Some((g, key))) if *g == id.generation() => Some(*key),
            _ => None,
        }
    }

    /// A node with its position (`None` if it has none) and its Rapier object (`None`
    /// for containers). `None` if its object is gone from the sets.
    fn end<'a>(
        &self,
        bodies: &'a RigidBodySet,
        colliders: &'a ColliderSet,
        id: NodeId,
        n: &Node,
    ) -> Option<End<'a>> {
        let object = match n.source() {
            NodeSource::Body(h) => Some(DebugRenderObject::RigidBody(h, bodies.get(h)?)),
            NodeSource::StaticCollider(c) | NodeSource::Sensor(c) => {
                Some(DebugRenderObject::Collider(c, colliders.get(c)?))
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
    fn nearest_on(
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        n: &Node,
        to: Vector,
    ) -> Option<Vector> {
        let source = n.source();
        let handles = match &source {
            NodeSource::Body(h) => bodies.get(*h)?.colliders(),
            NodeSource::StaticCollider(c) => std::slice::from_ref(c),
            _ => return None,
        };
        let mut best: Option<(Real, Vector)> = None;
        for &c in handles {
            let Some(co) = colliders.get(c) else { continue };
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

    #[allow(clippy::too_many_arguments)]
    fn draw_edge<B: DebugRenderBackend + ?Sized>(
        &self,
        backend: &mut B,
        layer: &ContactLayer,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        which: Layer,
        e: &crate::Edge,
        stats: &mut OverlayStats,
    ) {
        let graph = layer.graph();
        let style = &self.style;
        let (Some(na), Some(nb)) = (graph.node(e.a()), graph.node(e.b())) else {
            stats.skipped_edges += 1;
            return;
        };
        let (Some(mut a), Some(mut b)) = (
            self.end(bodies, colliders, e.a(), na),
            self.end(bodies, colliders, e.b(), nb),
        ) else {
            stats.skipped_edges += 1;
            return;
        };
        if style.anchor_on_scenery && e.kind() == EdgeKind::Physical {
            // The scenery end needs no position of its own (a half-space has none).
            match (
                Self::is_scenery(layer, na),
                Self::is_scenery(layer, nb),
                a.pos,
                b.pos,
            ) {
                (true, false, _, Some(to)) => {
                    if let Some(p) = Self::nearest_on(bodies, colliders, na, to) {
                        a.pos = Some(p);
                    }
                }
                (false, true, Some(to), _) => {
                    if let Some(p) = Self::nearest_on(bodies, colliders, nb, to) {
                        b.pos = Some(p);
                    }
                }
                _ => {}
            }
        }
        let (Some(mut pa), Some(mut pb)) = (a.pos, b.pos) else {
            stats.skipped_edges += 1;
            return;
        };
        // Trigger and structural edges run from the trigger or container to the body.
        let from_b = match which {
            Layer::Trigger => nb.kind() == NodeKind::Sensor,
            Layer::Structural => nb.kind().category() == crate::Category::Container,
            _ => false,
        };
        if from_b {
            std::mem::swap(&mut pa, &mut pb);
        }
        // Every end's object must pass the backend's filter.
        for object in [a.object, b.object].into_iter().flatten() {
            if !backend.filter_object(object) {
                stats.filtered += 1;
                return;
            }
        }
        // The simulated end's body, else a body, else the sensor or collider; A on ties.
        let rank = |end: &End| match end.object {
            Some(DebugRenderObject::RigidBody(..)) if end.simulated => 3,
            Some(DebugRenderObject::RigidBody(..)) => 2,
            Some(_) => 1,
            None => 0,
        };
        let object = if rank(&b) > rank(&a) {
            b.object
        } else {
            a.object
        };
        let Some(object) = object else {
            stats.skipped_edges += 1; // two containers: not a graph the layer builds
            return;
        };
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
                let key = style
                    .group_colors
                    .then(|| {
                        [na, nb]
                            .iter()
                            .find_map(|n| n.group())
                            .and_then(|g| self.group_key_of(g))
                    })
                    .flatten();
                let color = key.map_or(style.touching_color, |k| style.group_color(k));
                stats.lines += line(backend, object, pa, pb, color);
                stats.touching += 1;
            }
        }
    }
}

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
