//! The switches of the paper's §7 and their parameters (paper §7; the realisations are listed in `docs/ARCHITECTURE.md`).

use std::fmt;

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
/// - `iterations` / `tweak`: the solver's `num_solver_iterations` (`None` and no
///   tweak: the user's own, followed when the user changes it);
/// - `cache` off: Rapier's contact recycling and warm start off (on, the default:
///   the user's own, followed when the user changes them);
/// - `damp`: every dynamic body's linear damping;
/// - `zero`, `reduce`: `ActiveHooks::MODIFY_SOLVER_CONTACTS` on the colliders
///   concerned (that bit only);
/// - `fixate`: a held body's type (fixed while held; dynamic again, with its
///   velocities, when released, unless the user gave it another type meanwhile) and,
///   for one step on its way out of Rapier's active set, its enabled flag.
///
/// The monitor in repair mode sets the solver to full strength while it repairs
/// (twice the iterations, recycling and warm start on) and gives the user's back
/// after. Tested in `tests/solver_settings_kept.rs` and
/// `tests/detach_restores_the_world.rs`.
///
/// # Example
/// ```
/// use rapier_contact_graph::speedups::SpeedUps;
/// let paper_best = SpeedUps { cache: true, zero: true, damp: true, subgroup: true, fixate: true, ..SpeedUps::contact_graph() };
/// paper_best.validate().unwrap();
/// assert_eq!(paper_best.label(), "C--ZDSF");
/// assert!(SpeedUps { tweak_iterations: 0, ..SpeedUps::none() }.validate().is_err());
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
    /// off in the paper's configurations ([`Self::contact_graph`],
    /// [`Self::combination`] without bit 0).
    pub cache: bool,
    /// Solve with `tweak_iterations` solver iterations instead of `iterations`.
    pub tweak: bool,
    /// Keep only the deepest solver contact of pairs penetrating deeper than
    /// `reduce_depth`.
    pub reduce: bool,
    /// Restitution 0 for pairs with a sleepy body.
    pub zero: bool,
    /// Linear viscous damping `damping` on every dynamic body.
    pub damp: bool,
    /// Sleepy bodies insulate groups (the traversal treats them as fixed).
    pub subgroup: bool,
    /// Sleepy bodies are held immovable (inverse mass 0), and restored exactly when
    /// released.
    pub fixate: bool,

    /// Kinetic energy per unit mass below which a body counts as at rest, J/kg.
    /// Default 0.005 (a speed of 0.1 m/s).
    pub sleepy_energy: f32,
    /// Steps at rest before a body is sleepy. Default 20 (0.2 s at dt = 0.01).
    pub sleepy_steps: u32,
    /// Solver iterations without `tweak` (Rapier's `num_solver_iterations`): `None`,
    /// the default, keeps the user's own, as set in the world's
    /// `IntegrationParameters` (before or since the speed-ups started).
    pub iterations: Option<usize>,
    /// Solver iterations with `tweak`. Default 1.
    pub tweak_iterations: usize,
    /// Penetration depth above which `reduce` acts, metres. Default 0.005.
    pub reduce_depth: f32,
    /// Linear damping coefficient of `damp`, 1/s. Default 0.5.
    pub damping: f32,
    /// A fixated body is released when a body that is not sleepy and moves faster
    /// than this, or a moving kinematic body, is about to reach it, m/s. Default 0.5.
    pub release_speed: f32,
    /// A release spreads from a released body through the held bodies it touched
    /// when held, or that touched it, nearest first, as far as the disturbance's
    /// momentum reaches (a kinematic body's and the user's: the whole held group, as
    /// a sleeping Rapier island wakes whole); off, only the bodies reached are
    /// released. Default on.
    pub release_group: bool,
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
            tweak: false,
            reduce: false,
            zero: false,
            damp: false,
            subgroup: false,
            fixate: false,
            sleepy_energy: 0.005,
            sleepy_steps: 20,
            iterations: None,
            tweak_iterations: 1,
            reduce_depth: 0.005,
            damping: 0.5,
            release_speed: 0.5,
            release_group: true,
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

    /// Preset: piles held still once at rest, with Rapier's warm start kept. The
    /// contact graph with `cache`, `subgroup` and `fixate` (`C----SF` in the DIKU
    /// table): a sleepy body is held (a fixed body to Rapier, out of its active set),
    /// sleepy bodies insulate, contacts are recycled and warm-started. A held body is
    /// released before a moving body reaches it, with as much of its held group as
    /// the disturbance can move, and when its support goes (`docs/ARCHITECTURE.md`,
    /// "Releasing held bodies"); on the disturbance scenes (a ball thrown into a
    /// settled pile, its floor taken away, a paddle through it) it answers as Rapier
    /// without sleep does on the bodies moved and the ball's outcome, except that the
    /// paddle moves a few boxes fewer. The gain is on piles at rest; a pile that keeps
    /// being hit (the DIKU scene's rim) runs at about stock Rapier's cost. A held body
    /// keeps its contacts as a sleeping one does (no contact ends because a pile was
    /// held). A pile that comes to rest at once is held over a few steps: each step
    /// holds (and parks) at most 32 bodies or a 16th of those Rapier integrates, the
    /// longest at rest first, so that no step pays Rapier's answer to a whole pile's
    /// change of type; releases are never put off. What it does not do yet: obey an impulse or
    /// velocity the user writes to it (Rapier drops writes to a fixed body). Figures:
    /// `docs/results.md`.
    ///
    /// The other presets: observe only is no speed-ups at all
    /// (`speedups_mut().set(None)`, the layer's default); [`Self::papers_fastest`].
    pub fn reliable_sleep() -> Self {
        Self {
            cache: true,
            subgroup: true,
            fixate: true,
            ..Self::contact_graph()
        }
    }

    /// Preset: the paper's fastest configuration (Table 5's ♠, `C--ZDSF`): cache,
    /// zero, damp, subgroup and fixate. Changes motion: the damping slows rolling, so
    /// it is not equivalent to the reference on the DIKU scene (fewer spheres at the
    /// rim, more in the grooves, a lower and shorter pile). Held bodies as in
    /// [`Self::reliable_sleep`]. Figures: `docs/results.md`.
    pub fn papers_fastest() -> Self {
        Self {
            cache: true,
            zero: true,
            damp: true,
            subgroup: true,
            fixate: true,
            ..Self::contact_graph()
        }
    }

    /// One of the 2^7 combinations of cache, tweak, reduce, zero, damp, subgroup and
    /// fixate (bit 0 = cache … bit 6 = fixate), on top of the contact graph
    /// configuration, as in the paper's Table 5.
    pub fn combination(bits: u8) -> Self {
        let on = |i: u8| bits & (1 << i) != 0;
        Self {
            cache: on(0),
            tweak: on(1),
            reduce: on(2),
            zero: on(3),
            damp: on(4),
            subgroup: on(5),
            fixate: on(6),
            ..Self::contact_graph()
        }
    }

    /// The seven combination switches as "CTRZDSF", with `-` for an off switch.
    pub fn label(&self) -> String {
        let flags = [
            (self.cache, 'C'),
            (self.tweak, 'T'),
            (self.reduce, 'R'),
            (self.zero, 'Z'),
            (self.damp, 'D'),
            (self.subgroup, 'S'),
            (self.fixate, 'F'),
        ];
        flags
            .iter()
            .map(|&(on, c)| if on { c } else { '-' })
            .collect()
    }

    /// The combination bits (see [`Self::combination`]) of a label like `"C-----F"`
    /// (as [`Self::label`] writes it) or of a number 0–127; `None` for anything else.
    /// O(1).
    ///
    /// # Example
    /// ```
    /// use rapier_contact_graph::speedups::SpeedUps;
    /// assert_eq!(SpeedUps::combination_bits("C-----F"), Some(0b100_0001));
    /// assert_eq!(SpeedUps::combination_bits("65"), Some(65));
    /// assert_eq!(SpeedUps::combination_bits("128"), None);
    /// assert_eq!(SpeedUps::combination_bits("CTRZDS"), None);
    /// ```
    pub fn combination_bits(label: &str) -> Option<u8> {
        if let Ok(n) = label.parse::<u8>() {
            return (n < 128).then_some(n);
        }
        let letters = b"CTRZDSF";
        let bytes = label.as_bytes();
        if bytes.len() != letters.len() {
            return None;
        }
        let mut bits = 0u8;
        for (i, (&got, &on)) in bytes.iter().zip(letters).enumerate() {
            match got {
                b'-' => {}
                g if g == on => bits |= 1 << i,
                _ => return None,
            }
        }
        Some(bits)
    }

    /// Whether any switch needs the `modify_solver_contacts` hook.
    pub fn modifies_contacts(&self) -> bool {
        self.reduce || self.zero
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
        nonneg("reduce_depth", self.reduce_depth)?;
        nonneg("damping", self.damping)?;
        nonneg("release_speed", self.release_speed)?;
        if self.sleepy_steps == 0 {
            return bad("sleepy_steps", "must be at least 1".into());
        }
        if self.iterations == Some(0) {
            return bad("iterations", "must be at least 1".into());
        }
        if self.tweak_iterations == 0 {
            return bad("tweak_iterations", "must be at least 1".into());
        }
        Ok(())
    }
}

impl fmt::Display for SpeedUps {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}{}{}",
            if self.groups { "G" } else { "-" },
            if self.sleepy { "S" } else { "-" },
            self.label()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The presets are the DIKU table's rows their docs quote figures of, and keep
    /// Rapier's warm start (`cache`).
    #[test]
    fn presets_are_the_measured_combinations_and_keep_warm_start() {
        for (preset, label) in [
            (SpeedUps::reliable_sleep(), "C----SF"),
            (SpeedUps::papers_fastest(), "C--ZDSF"),
        ] {
            let bits = SpeedUps::combination_bits(label).unwrap();
            assert_eq!(preset, SpeedUps::combination(bits), "{label}");
            assert!(preset.cache, "{label} keeps warm start");
            preset.validate().unwrap();
        }
    }

    #[test]
    fn combination_bits_inverts_the_label() {
        for b in 0..128u8 {
            let label = SpeedUps::combination(b).label();
            assert_eq!(SpeedUps::combination_bits(&label), Some(b), "{label}");
            assert_eq!(SpeedUps::combination_bits(&b.to_string()), Some(b));
        }
        for bad in ["", "CTRZDSFX", "TCRZDSF", "c-----f", "ctrzdsf", "128", "-1"] {
            assert_eq!(SpeedUps::combination_bits(bad), None, "{bad}");
        }
    }

    #[test]
    fn combinations_cover_the_seven_switches() {
        assert_eq!(SpeedUps::combination(0).label(), "-------");
        assert_eq!(SpeedUps::combination(127).label(), "CTRZDSF");
        assert_eq!(SpeedUps::combination(0b100_0001).label(), "C-----F");
        assert!(SpeedUps::combination(5).groups && SpeedUps::combination(5).sleepy);
    }

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
                tweak_iterations: 0,
                ..base.clone()
            },
            SpeedUps {
                reduce_depth: f32::INFINITY,
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
