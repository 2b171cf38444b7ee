//! The state a body's marker shows ([`BodyState`]), read from the layer, its speed-ups
//! and Rapier's body.

use rapier3d::math::Real;
use rapier3d::prelude::{RigidBodyHandle, RigidBodySet};

use crate::graph::{Node, NodeId, NodeSource};
use crate::ContactLayer;

/// The state a body's marker shows (the paper's Fig. 17, refined). [`BodyState::of`]
/// gives it; the rules, first match wins, are in the order of the variants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyState {
    /// Disabled: by [`LayerLogicMut::set_body_disabled`](crate::LayerLogicMut::set_body_disabled) (the paper's *passive* body,
    /// §3.2) or in Rapier.
    Disabled,
    /// Held: fixated by the `hold` speed-up (Fig. 17's "fixed", green).
    Held,
    /// An insulator: a fixed or kinematic body, or a collider without a body. The solver
    /// does not move it.
    Insulator,
    /// Asleep in Rapier.
    Asleep,
    /// Tagged sleepy by the speed-ups but still awake in Rapier (Fig. 17's "sleepy").
    Sleepy,
    /// Awake, with linear and angular speed at most
    /// [`OverlayStyle::rest_speed`](super::OverlayStyle::rest_speed) (Fig. 17's
    /// "absolute rest").
    Resting,
    /// Anything else (Fig. 17's "moving"), non-finite velocities included.
    Moving,
}

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
    /// [`OverlayStyle::rest_speed`](super::OverlayStyle::rest_speed). O(log held bodies).
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

    /// The state of body node `node` with handle `h`; `None` if `bodies` does not hold it.
    pub(super) fn of_body(
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
