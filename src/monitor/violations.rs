//! What the monitor reports: violations, their counts per kind, and the peaks.

use rapier3d::math::Real;
use rapier3d::prelude::RigidBodyHandle;

use crate::events::ViolationKind;
use crate::graph::NodeId;

/// One reported violation.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Violation {
    /// The layer's step it was found in ([`LayerAnalysis::current_step`](crate::LayerAnalysis::current_step)).
    pub step: u64,
    /// What went wrong.
    pub kind: ViolationKind,
    /// The body it is reported on: the hanging body; the group's body with the largest
    /// kinetic energy gain; the smaller body of a deep contact (the other one if the
    /// smaller is static geometry); the escaped body; the held body an awake body
    /// pressed.
    pub body: RigidBodyHandle,
    /// The body's node, if the graph has one.
    pub node: Option<NodeId>,
    /// The measure: seconds without support; excess energy of the group in joules;
    /// penetration depth in metres; for an escape, the number of non-finite scalars in
    /// the pose (7) and velocities (6) — 0 for a body Rapier's quarantine already reset;
    /// for an unresponsive body, the largest push across gravity on it in units of the
    /// pusher's weight over the step plus its push along gravity.
    pub value: Real,
}

/// Violations per kind.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViolationCounts {
    /// Hanging sleepers.
    pub hanging_sleeper: u64,
    /// Launches.
    pub launch: u64,
    /// Deep penetrations.
    pub deep_penetration: u64,
    /// Escapes.
    pub escape: u64,
    /// Unresponsive held bodies.
    #[cfg_attr(feature = "serde", serde(default))]
    pub unresponsive: u64,
}

impl ViolationCounts {
    /// The count of one kind.
    pub fn get(&self, kind: ViolationKind) -> u64 {
        match kind {
            ViolationKind::HangingSleeper => self.hanging_sleeper,
            ViolationKind::Launch => self.launch,
            ViolationKind::DeepPenetration => self.deep_penetration,
            ViolationKind::Escape => self.escape,
            ViolationKind::Unresponsive => self.unresponsive,
        }
    }

    /// The sum over all kinds.
    pub fn total(&self) -> u64 {
        self.hanging_sleeper + self.launch + self.deep_penetration + self.escape + self.unresponsive
    }

    pub(super) fn add(&mut self, kind: ViolationKind) {
        match kind {
            ViolationKind::HangingSleeper => self.hanging_sleeper += 1,
            ViolationKind::Launch => self.launch += 1,
            ViolationKind::DeepPenetration => self.deep_penetration += 1,
            ViolationKind::Escape => self.escape += 1,
            ViolationKind::Unresponsive => self.unresponsive += 1,
        }
    }
}

/// The largest values each detector measured since the monitor was created, as a
/// fraction of its threshold (below 1: never fired). For tuning thresholds and for
/// reporting how close a run came to a violation.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Peaks {
    /// Longest time a held body went unsupported, over `hang_time` (0 when
    /// `hang_time` is 0).
    pub hang: Real,
    /// Largest excess energy of a checked group, over its tolerance.
    pub launch: Real,
    /// Largest excess energy of a checked group, in joules.
    pub launch_excess: Real,
    /// Deepest penetration, over `penetration_fraction ×` the smaller body's size.
    pub penetration: Real,
    /// Largest push on a held body across gravity, over `unresponsive_push` (0 when
    /// `unresponsive_push` is 0, and while nothing is held).
    #[cfg_attr(feature = "serde", serde(default))]
    pub unresponsive: Real,
}
