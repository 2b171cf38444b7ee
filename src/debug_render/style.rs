//! What the overlay draws and in which colours: [`OverlayStyle`], the state colours and
//! marker figures, and the stable colour of a contact group.

use rapier3d::math::Real;
use rapier3d::pipeline::DebugColor;

use super::BodyState;
use crate::groups::Group;

/// Default [`OverlayStyle::rest_speed`]: 1 mm/s (and 1 mrad/s), well above the residual
/// speeds of bodies Rapier keeps awake on a support and well below visible motion.
pub const DEFAULT_REST_SPEED: Real = 1e-3;

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

/// The stable colour key of a group: its smallest member slot index
/// ([`NodeId::index`](crate::graph::NodeId::index)), which survives the group's rebuilds
/// as long as that body stays in it (`None` for a group without members). O(members).
pub fn group_key(group: &Group) -> Option<u32> {
    group.bodies.iter().map(|n| n.index()).min()
}
