//! The detectors' thresholds.

use rapier3d::math::Real;

use crate::{Error, Result};

/// Thresholds of the detectors (defaults as defined in `docs/ARCHITECTURE.md` §6).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MonitorConfig {
    /// Seconds a held body may stay without support before it is a hanging sleeper
    /// (strictly longer than this). Default 0.1 s (paper §8, Figs. 15 and 17).
    pub hang_time: Real,
    /// Deepest allowed penetration as a fraction of the smaller body's size. Default 0.1.
    pub penetration_fraction: Real,
    /// Launch tolerance, relative part. Default 0.05.
    ///
    /// A contact group's excess energy in a step (its kinetic energy gain minus the work
    /// gravity did on it) is a launch when it exceeds
    /// `launch_relative · KE_before + launch_per_kg · m`, where `KE_before` and `m` are
    /// the kinetic energy before the step and the mass of the group's *gainers* (the
    /// members whose energy rose by more than gravity's work on them), so that one body
    /// thrown out of a large pile is not diluted by the pile's mass. The relative part
    /// absorbs the integration error of fast groups (a swinging multibody), the
    /// absolute part the solver's slop in slow ones.
    ///
    /// Tuned with Rapier's default parameters on the quiet scenes of
    /// `tests/monitor_detect_hanging.rs`: the largest excess over tolerance seen was 0.35 in
    /// a settling 300-sphere pile (columns of spheres landing on each other; 0.19 J/kg),
    /// 0.22 for the pendulum multibody, 0.12 for the DIKU scene, below 0.001 for bounces
    /// with restitution 0.8 and 1, colliding balls and the toppling stack. A launch by
    /// position correction (two 0.5 m boxes created 0.3 m into each other, Rapier's
    /// stabilisation pass off) measures 2 with Rapier's soft contacts and 130 with
    /// stiff ones (300 Hz, 100 m/s correction cap); releasing a box fixated with
    /// `set_additional_mass(1e6)` measures 33,000. With Rapier's defaults the same
    /// overlap is resolved at 0.2 m/s and measures 0.04: not a launch.
    pub launch_relative: Real,
    /// Launch tolerance, absolute part, in joules per kilogram of the gainers' mass.
    /// Default 0.5 J/kg: the gainers as a whole thrown at 1 m/s from rest. See
    /// [`Self::launch_relative`].
    pub launch_per_kg: Real,
    /// The smallest cosine between a contact's push and `-gravity` that still counts as
    /// support. Default 0.0: any upward component supports (a body on a fixed slope is
    /// supported). Must be in `[0, 1)`.
    pub min_support_cos: Real,
    /// The largest unexplained push an awake body may put on a held (fixated) body
    /// across gravity or up, in three steps in a row: the push its weight and its other
    /// contacts do not explain (its momentum lost, a user's force), in units of its
    /// weight over the step or its load if larger (see the module docs). Default 2.0:
    /// a box driven at 0.3 m/s into a held box (`dt` = 0.01) measures about 3, a box
    /// pushed with a constant force `F` measures `F` over its weight; bodies settling
    /// on a held pile under [`crate::speedups::SpeedUps::reliable_sleep`] stay below
    /// it for three steps in a row.
    #[cfg_attr(feature = "serde", serde(default = "default_unresponsive_push"))]
    pub unresponsive_push: Real,
}

#[cfg(feature = "serde")]
fn default_unresponsive_push() -> Real {
    MonitorConfig::default().unresponsive_push
}

impl Default for MonitorConfig {
    fn default() -> Self {
        Self {
            hang_time: 0.1,
            penetration_fraction: 0.1,
            launch_relative: 0.05,
            launch_per_kg: 0.5,
            min_support_cos: 0.0,
            unresponsive_push: 2.0,
        }
    }
}

impl MonitorConfig {
    /// Checks every field: all must be finite and non-negative, and
    /// `min_support_cos < 1`. An [`Error::InvalidParameter`] names the first bad one.
    pub fn validate(&self) -> Result<()> {
        let fields = [
            ("hang_time", self.hang_time),
            ("penetration_fraction", self.penetration_fraction),
            ("launch_relative", self.launch_relative),
            ("launch_per_kg", self.launch_per_kg),
            ("min_support_cos", self.min_support_cos),
            ("unresponsive_push", self.unresponsive_push),
        ];
        for (name, value) in fields {
            if !value.is_finite() || value < 0.0 {
                return Err(Error::InvalidParameter {
                    name,
                    reason: format!("must be finite and non-negative, got {value}"),
                });
            }
        }
        if self.min_support_cos >= 1.0 {
            return Err(Error::InvalidParameter {
                name: "min_support_cos",
                reason: format!(
                    "must be below 1 (no contact could support), got {}",
                    self.min_support_cos
                ),
            });
        }
        Ok(())
    }
}
