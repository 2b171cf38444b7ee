//! The switches of the paper's §7 and their parameters (the realisations, and the
//! paper's name for each switch, are listed in `docs/ARCHITECTURE.md` §7).

use crate::{Error, Result};

/// The speed-up switches and their parameters. Every switch is independent.
///
/// Units: energies per unit mass in J/kg (m²/s²), depths in metres, damping in 1/s,
/// times in steps.
///
/// # What the speed-ups change in your world
/// Only what the switch asked for is the speed-up; each is given back at `detach`
/// (or `speedups_mut().set(None)`, at the next pre-step) as the user last set it:
/// - any configuration: every dynamic body's sleep thresholds (the layer decides
///   when bodies sleep; with `sleepy` off nothing sleeps);
/// - `iterations` / `fewer_iterations`: the solver's `num_solver_iterations` (`None`
///   and `fewer_iterations` off: the user's own, followed when the user changes it);
/// - `cache` off: Rapier's contact recycling and warm start off (on, the default:
///   the user's own, followed when the user changes them);
/// - `viscous_damping`: every dynamic body's linear damping;
/// - `no_restitution_at_rest`, `deepest_contact_only`:
///   `ActiveHooks::MODIFY_SOLVER_CONTACTS` on the colliders concerned (that bit only);
/// - `hold`: a held body's type (fixed while held; dynamic again, with its
///   velocities, when released, unless the user gave it another type meanwhile) and,
///   for one step on its way out of Rapier's active set, its enabled flag.
///
/// The monitor in repair mode sets the solver to full strength while it repairs
/// (twice the iterations, recycling and warm start on) and gives the user's back
/// after. Tested in `tests/solver_settings_kept.rs` and
/// `tests/detach_restores_the_world.rs`.
///
/// The paper's names for the switches (Table 5's letters) are listed in
/// `docs/ARCHITECTURE.md` §7.
///
/// # Example
/// ```
/// use rapier_contact_graph::speedups::SpeedUps;
/// let held_piles = SpeedUps { cache: true, insulate_sleepy: true, hold: true, ..SpeedUps::contact_graph() };
/// held_piles.validate().unwrap();
/// assert_eq!(held_piles, SpeedUps::reliable_sleep());
/// assert!(SpeedUps { fewer_iterations_count: 0, ..SpeedUps::none() }.validate().is_err());
/// ```
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedUps {
    /// Contact groups by the paper's traversal drive sleeping and the statistics.
    /// Motion: unchanged.
    pub groups: bool,
    /// The layer owns sleeping: a body is sleepy once its kinetic energy per unit
    /// mass stayed below `sleepy_energy` for `sleepy_steps` steps; a group (a Rapier
    /// island) sleeps when all its bodies are sleepy. Off: nothing ever sleeps.
    pub sleepy: bool,
    /// Rapier's contact recycling and warm start (the paper's cached contact points
    /// and forces), as the user set them. Off: both off. On in [`Self::default`],
    /// off in the paper's contact graph configuration ([`Self::contact_graph`]).
    pub cache: bool,
    /// Solve with `fewer_iterations_count` solver iterations instead of `iterations`.
    pub fewer_iterations: bool,
    /// Keep only the deepest solver contact of pairs penetrating deeper than
    /// `deepest_contact_depth`.
    pub deepest_contact_only: bool,
    /// Restitution 0 for pairs with a sleepy body.
    pub no_restitution_at_rest: bool,
    /// Linear viscous damping `damping` on every dynamic body.
    pub viscous_damping: bool,
    /// Sleepy bodies insulate groups (the traversal treats them as fixed).
    pub insulate_sleepy: bool,
    /// Sleepy bodies are held immovable (inverse mass 0), and restored exactly when
    /// released.
    pub hold: bool,

    /// Kinetic energy per unit mass below which a body counts as at rest, J/kg.
    /// Default 0.005 (a speed of 0.1 m/s).
    pub sleepy_energy: f32,
    /// Steps at rest before a body is sleepy. Default 20 (0.2 s at dt = 0.01).
    pub sleepy_steps: u32,
    /// Solver iterations without `fewer_iterations` (Rapier's `num_solver_iterations`): `None`,
    /// the default, keeps the user's own, as set in the world's
    /// `IntegrationParameters` (before or since the speed-ups started).
    pub iterations: Option<usize>,
    /// Solver iterations with `fewer_iterations`. Default 1.
    pub fewer_iterations_count: usize,
    /// Penetration depth above which `deepest_contact_only` acts, metres. Default 0.005.
    pub deepest_contact_depth: f32,
    /// Linear damping coefficient of `viscous_damping`, 1/s. Default 0.5.
    pub damping: f32,
    /// A held body is released when a body that is not sleepy and moves faster
    /// than this, or a moving kinematic body, is about to reach it; what it released
    /// is not held again until it is slower than this (or stopped, if kinematic),
    /// m/s. Default 0.5.
    pub release_speed: f32,
    /// A release spreads from the bodies a disturbance released through the held
    /// bodies they touched when held, or that touched them, nearest first, in one
    /// walk per disturbance, as far as its momentum reaches (a kinematic body's and
    /// the user's: the whole held group, as a sleeping Rapier island wakes whole);
    /// off, only the bodies reached are released. Default on.
    pub release_group: bool,
    /// A held body the user wrote to since the last step (Rapier flags every body
    /// reached through `get_mut`, `bodies[h]` as `&mut` or `iter_mut`) is given back
    /// at the next pre-step, so that the user's writes from then on reach a dynamic
    /// body (Rapier drops the first, on a fixed body). Costs O(held) a step: off, a
    /// settled held pile costs less where nothing writes to the bodies the layer may
    /// hold. Default on.
    pub release_written: bool,
}

impl Default for SpeedUps {
    /// The contact graph configuration (groups + sleepy) with `cache` on: Rapier's
    /// contact recycling and warm start stay as the user had them. (The paper's
    /// contact-graph configuration, [`Self::contact_graph`], has `cache` off; a
    /// default must not turn off a Rapier feature, and warm start is what keeps
    /// stacks standing in the stability suite.)
    fn default() -> Self {
        Self {
            cache: true,
            ..Self::contact_graph()
        }
    }
}

impl SpeedUps {
    /// Brute force: no groups, no sleep, no caching; Rapier's default iterations.
    pub fn none() -> Self {
        Self {
            groups: false,
            sleepy: false,
            cache: false,
            fewer_iterations: false,
            deepest_contact_only: false,
            no_restitution_at_rest: false,
            viscous_damping: false,
            insulate_sleepy: false,
            hold: false,
            sleepy_energy: 0.005,
            sleepy_steps: 20,
            iterations: None,
            fewer_iterations_count: 1,
            deepest_contact_depth: 0.005,
            damping: 0.5,
            release_speed: 0.5,
            release_group: true,
            release_written: true,
        }
    }

    /// The paper's "contact graph" configuration: groups and sleepy objects.
    pub fn contact_graph() -> Self {
        Self {
            groups: true,
            sleepy: true,
            ..Self::none()
        }
    }

    /// Preset: piles held still once at rest, with Rapier's warm start kept: the
    /// contact graph with `cache`, `insulate_sleepy` and `hold` (the paper's
    /// `C----SF`). A sleepy body is held (a fixed body to Rapier, out of its active
    /// set) and keeps its contacts as a sleeping one does, once no body of a contact
    /// group it touches still moves fast; it is released before a
    /// moving body reaches it, with as much of its held group as the disturbance can
    /// move, and not held again while that body still moves; and when its support
    /// goes, with its held group when a support was removed or moved under it
    /// (`docs/ARCHITECTURE.md`, "Releasing held bodies"). A pile that comes to
    /// rest at once is held over a few steps, so that no step pays Rapier's answer to
    /// a whole pile's change of type; likewise a release that spreads through a
    /// large held pile is given back over a few steps, nearest first, while what a
    /// moving body reaches, a lost support and the user's own bodies are released at
    /// once. The gain is on
    /// piles at rest; a pile that keeps being hit runs at about stock Rapier's cost
    /// (`docs/results.md`). Not done yet: obeying an impulse or velocity the user
    /// writes to a held body (Rapier drops writes to a fixed body).
    ///
    /// The other presets: observe only is no speed-ups at all
    /// (`speedups_mut().set(None)`, the layer's default); [`Self::papers_fastest`].
    pub fn reliable_sleep() -> Self {
        Self {
            cache: true,
            insulate_sleepy: true,
            hold: true,
            ..Self::contact_graph()
        }
    }

    /// Preset: the paper's fastest configuration (Table 5's ♠, `C--ZDSF`): `cache`,
    /// `no_restitution_at_rest`, `viscous_damping`, `insulate_sleepy` and `hold`. Changes motion: the damping slows rolling, so
    /// it is not equivalent to the reference on the DIKU scene (fewer spheres at the
    /// rim, more in the grooves, a lower and shorter pile). Held bodies as in
    /// [`Self::reliable_sleep`]. Figures: `docs/results.md`.
    pub fn papers_fastest() -> Self {
        Self {
            cache: true,
            no_restitution_at_rest: true,
            viscous_damping: true,
            insulate_sleepy: true,
            hold: true,
            ..Self::contact_graph()
        }
    }

    /// Checks the parameters: finite, and in range. Called by the layer when the
    /// configuration is set.
    pub fn validate(&self) -> Result<()> {
        fn bad(name: &'static str, reason: String) -> Result<()> {
            Err(Error::InvalidParameter { name, reason })
        }
        let nonneg = |name: &'static str, v: f32| {
            if !v.is_finite() || v < 0.0 {
                bad(name, format!("must be finite and >= 0, got {v}"))
            } else {
                Ok(())
            }
        };
        nonneg("sleepy_energy", self.sleepy_energy)?;
        nonneg("deepest_contact_depth", self.deepest_contact_depth)?;
        nonneg("damping", self.damping)?;
        nonneg("release_speed", self.release_speed)?;
        if self.sleepy_steps == 0 {
            return bad("sleepy_steps", "must be at least 1".into());
        }
        if self.iterations == Some(0) {
            return bad("iterations", "must be at least 1".into());
        }
        if self.fewer_iterations_count == 0 {
            return bad("fewer_iterations_count", "must be at least 1".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_parameters_are_refused() {
        let base = SpeedUps::contact_graph();
        for bad in [
            SpeedUps {
                sleepy_energy: -1.0,
                ..base.clone()
            },
            SpeedUps {
                sleepy_energy: f32::NAN,
                ..base.clone()
            },
            SpeedUps {
                sleepy_steps: 0,
                ..base.clone()
            },
            SpeedUps {
                iterations: Some(0),
                ..base.clone()
            },
            SpeedUps {
                fewer_iterations_count: 0,
                ..base.clone()
            },
            SpeedUps {
                deepest_contact_depth: f32::INFINITY,
                ..base.clone()
            },
            SpeedUps {
                damping: -0.1,
                ..base.clone()
            },
        ] {
            assert!(
                matches!(bad.validate(), Err(Error::InvalidParameter { .. })),
                "{bad:?}"
            );
        }
        base.validate().unwrap();
    }
}
