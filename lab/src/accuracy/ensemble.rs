//! Running the paired seed ensembles of the DIKU scene: the reference on every seed
//! once, then any configuration on the first `k` of the same seeds, each run observed
//! ([`observe`]) against the same-seed reference.
//!
//! The reference's refinements (twice its iterations, half its time step) and the
//! floors of the trajectory deviation (the reference with every coordinate of every
//! sphere nudged by one ulp) are runs of the same kind, prepared by [`Variant`]. Each
//! run is one [`measure::run`]: O(steps · Rapier's step), the observables on top are
//! O(N log N) once and O(contact points) a step (untimed).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;
use rapier_contact_graph::monitor::MonitorConfig;
use rcg_scenes::diku::{diku, is_on_plane, DikuParams};
use rcg_scenes::Scene;

use super::observables::{observe, plausibility, Outcome, Plausibility};
use crate::measure::{self, Mode, RunOptions, RunResult, RunSpec, Trajectory};

/// Positions are sampled every this many steps of 0.01 s (for the trajectory
/// deviation; the observables read the last frame).
pub const SAMPLE_EVERY: u64 = 10;

/// How a run's scene is prepared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The scene as built.
    AsBuilt,
    /// Half the time step and twice the steps: the same simulated time, sampled at the
    /// same times (a refinement of the reference).
    HalfStep,
    /// Every coordinate of every sphere's start moved by one ulp (away from zero):
    /// the chaos floor of the trajectory deviation.
    UlpNudge,
}

/// The reference refined: twice its solver iterations (32).
pub fn reference_double_iterations() -> RunSpec {
    RunSpec {
        name: "reference, 2x iterations".into(),
        mode: Mode::Plain { iterations: 32 },
        repair: false,
    }
}

/// The scene size and length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setup {
    /// Spheres.
    pub spheres: usize,
    /// Steps of 0.01 s.
    pub steps: u64,
}

impl Setup {
    /// The scene's parameters on `seed`.
    pub fn params(&self, seed: u64) -> DikuParams {
        DikuParams {
            spheres: self.spheres,
            seed,
            ..DikuParams::default()
        }
    }
}

/// One observed run.
#[derive(Clone, Debug)]
pub struct SeedRun {
    /// The scene's seed.
    pub seed: u64,
    /// What [`measure::run`] measured (time, deviation against the same-seed
    /// reference, violations, series).
    pub result: RunResult,
    /// The observables.
    pub outcome: Outcome,
    /// Peak and resting penetration, violations.
    pub plausibility: Plausibility,
}

/// The reference on one seed, with what later runs are compared against.
#[derive(Clone, Debug)]
pub struct ReferenceRun {
    /// The reference's own observed run (its deviation and W1 are 0).
    pub run: SeedRun,
    /// Its sampled trajectory.
    pub trajectory: Trajectory,
}

impl ReferenceRun {
    /// The final positions of the spheres.
    pub fn last(&self) -> &[Vector] {
        self.trajectory.frames.last().map_or(&[], Vec::as_slice)
    }
}

/// Moves `x` by one ulp away from zero (to the smallest positive subnormal from 0);
/// non-finite values are kept.
fn ulp_away(x: Real) -> Real {
    if !x.is_finite() {
        x
    } else if x == 0.0 {
        Real::from_bits(1)
    } else {
        Real::from_bits(x.to_bits() + 1)
    }
}

/// Runs `spec` on the scene of `setup` and `seed`, prepared by `variant`, and observes
/// it against `reference` (`None`: this is the reference; it is compared with
/// itself). Errors are [`measure::run`]'s, with the configuration and seed named.
pub fn run_seed(
    setup: Setup,
    spec: &RunSpec,
    seed: u64,
    variant: Variant,
    reference: Option<&ReferenceRun>,
) -> Result<(SeedRun, Trajectory), String> {
    let params = setup.params(seed);
    let mut scene: Scene = diku(&params);
    let spheres: Vec<RigidBodyHandle> = scene.dynamic_bodies();
    let (mut steps, mut sample_every) = (setup.steps, SAMPLE_EVERY);
    match variant {
        Variant::AsBuilt => {}
        Variant::HalfStep => {
            scene.world.integration_parameters.dt /= 2.0;
            steps = steps.saturating_mul(2);
            sample_every *= 2;
        }
        Variant::UlpNudge => {
            for &h in &spheres {
                if let Some(b) = scene.world.bodies.get_mut(h) {
                    let t = b.translation();
                    let nudged = Vector::new(ulp_away(t.x), ulp_away(t.y), ulp_away(t.z));
                    b.set_translation(nudged, true);
                }
            }
        }
    }
    let inside = |p| is_on_plane(&params, p);
    let opts = RunOptions {
        steps,
        sample_every,
        radius: params.radius,
        bodies: &spheres,
        reference: reference.map(|r| &r.trajectory),
        inside: &inside,
        monitor: MonitorConfig::default(),
    };
    let (mut result, trajectory) = measure::run(spec, scene, &opts)
        .map_err(|e| format!("in {} on seed {seed}: {e}", spec.name))?;
    let last: &[Vector] = trajectory.frames.last().map_or(&[], Vec::as_slice);
    let reference_last = reference.map_or(last, ReferenceRun::last);
    if reference.is_none() {
        result.deviation = 0.0;
    }
    let outcome = observe(&params, &result, last, reference_last);
    let plausibility = plausibility(&result);
    Ok((
        SeedRun {
            seed,
            result,
            outcome,
            plausibility,
        },
        trajectory,
    ))
}

/// The reference on `seed`. See [`run_seed`].
pub fn run_reference(setup: Setup, seed: u64) -> Result<ReferenceRun, String> {
    let (run, trajectory) = run_seed(setup, &RunSpec::reference(), seed, Variant::AsBuilt, None)?;
    Ok(ReferenceRun { run, trajectory })
}

/// The outcomes of runs, in order.
pub fn outcomes(runs: &[SeedRun]) -> Vec<Outcome> {
    runs.iter().map(|r| r.outcome).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulps_move_away_from_zero() {
        assert!(ulp_away(1.0) > 1.0 && ulp_away(1.0) - 1.0 < 1e-6);
        assert!(ulp_away(-1.0) < -1.0);
        assert!(ulp_away(0.0) > 0.0);
        assert!(ulp_away(Real::NAN).is_nan());
        assert_eq!(ulp_away(Real::INFINITY), Real::INFINITY);
    }
}
