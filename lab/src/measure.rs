//! Measuring a configuration for speed *and* accuracy (paper §7,
//! Tables 4–5; definitions in `docs/ARCHITECTURE.md`): the machinery of the DIKU run,
//! shared by the `diku` runner, the benchmarks and the tests.
//!
//! # What is measured
//! - `time_s`: wall time of the steps. For runs with the layer it is the layer's whole
//!   step (pre-step, Rapier, analysis, speed-up decisions); for plain Rapier runs
//!   (reference, brute force, stock) it is Rapier's step alone. The plausibility
//!   monitor and the sampling are not timed, and for plain runs an observe-only layer
//!   feeds the monitor, untimed (it does not change Rapier's results).
//! - `deviation`: against the reference run, for each sampled frame the mean over the
//!   bodies of the position error, in radii; then the RMS over the frames.
//! - `violations`: what the plausibility monitor (`rapier_contact_graph::monitor`) reports.
//! - per-step statistics: groups, largest group's variables, awake bodies; and for
//!   the observables of [`crate::accuracy`], the measured bodies' mean square speed
//!   and the deepest contact penetration of the whole world (from Rapier's narrow
//!   phase: every contact point of every pair, O(contact points) a step, untimed).
//!
//! Only ratios within one process are meaningful on a shared machine: the runner
//! measures every configuration in one run.

use std::time::{Duration, Instant};

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;

use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, MonitorMode, Peaks, RepairConfig, ViolationKind,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes::Scene;

/// How a run drives Rapier.
#[derive(Clone, Debug, PartialEq)]
pub enum Mode {
    /// Plain Rapier with its defaults (auto-sleep, caching): "stock Rapier".
    Stock,
    /// Plain Rapier with sleeping off, recycling and warm start off, and `iterations`
    /// solver iterations: the brute force (4) and the reference (16).
    Plain {
        /// Solver iterations.
        iterations: usize,
    },
    /// The layer with these speed-ups.
    Layer(SpeedUps),
}

/// A configuration to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Short name for tables ("reference", "brute force", "C-R-D-F", ...).
    pub name: String,
    /// How Rapier is driven.
    pub mode: Mode,
    /// Run the layer's monitor in repair mode ([`MonitorMode::Repair`]) instead of
    /// report mode. Only for [`Mode::Layer`]: plain runs are only observed.
    pub repair: bool,
}

impl RunSpec {
    /// The reference: no speed-ups, no sleep, 4× Rapier's default solver iterations.
    pub fn reference() -> Self {
        Self {
            name: "reference".into(),
            mode: Mode::Plain { iterations: 16 },
            repair: false,
        }
    }
    /// Brute force: no groups, no speed-ups, no sleep, Rapier's default iterations.
    pub fn brute_force() -> Self {
        Self {
            name: "brute force".into(),
            mode: Mode::Plain { iterations: 4 },
            repair: false,
        }
    }
    /// Stock Rapier defaults.
    pub fn stock() -> Self {
        Self {
            name: "stock Rapier".into(),
            mode: Mode::Stock,
            repair: false,
        }
    }
    /// The paper's contact graph: groups and sleepy.
    pub fn contact_graph() -> Self {
        Self {
            name: "contact graph".into(),
            mode: Mode::Layer(SpeedUps::contact_graph()),
            repair: false,
        }
    }
    /// The same configuration with the monitor repairing ([`MonitorMode::Repair`]);
    /// the name gets a ` +repair` suffix. Plain modes are not changed (an error at
    /// [`run`]).
    pub fn with_repair(mut self) -> Self {
        self.repair = true;
        self.name.push_str(" +repair");
        self
    }
    /// A combination of the seven switches (see [`combination`](crate::table5::combination)).
    pub fn combination(bits: u8) -> Self {
        let s = crate::table5::combination(bits);
        Self {
            name: crate::table5::label(&s),
            mode: Mode::Layer(s),
            repair: false,
        }
    }
}

/// Sampled positions of the measured bodies.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trajectory {
    /// One frame per sample, one position per measured body (in a fixed order).
    pub frames: Vec<Vec<Vector>>,
}

/// Violation counts by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Violations {
    /// Hanging sleepers.
    pub hanging: u64,
    /// Launches.
    pub launch: u64,
    /// Deep penetrations.
    pub penetration: u64,
    /// Escapes (non-finite state).
    pub escape: u64,
    /// Unresponsive held bodies (pushed into, not moved).
    pub unresponsive: u64,
}

impl Violations {
    /// All kinds together.
    pub fn total(&self) -> u64 {
        self.hanging + self.launch + self.penetration + self.escape + self.unresponsive
    }

    /// The count of one kind.
    pub fn get(&self, kind: ViolationKind) -> u64 {
        match kind {
            ViolationKind::HangingSleeper => self.hanging,
            ViolationKind::Launch => self.launch,
            ViolationKind::DeepPenetration => self.penetration,
            ViolationKind::Escape => self.escape,
            ViolationKind::Unresponsive => self.unresponsive,
        }
    }
}

/// What one run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// The configuration's name.
    pub name: String,
    /// Wall time of the timed part of the steps, seconds.
    pub time_s: f64,
    /// The timed part of the last 100 steps (the last simulated second at dt = 0.01),
    /// seconds: what a settled scene costs.
    pub tail_time_s: f64,
    /// RMS over sampled frames of the mean position error, in radii (0 for the
    /// reference itself; NaN without a reference).
    pub deviation: f64,
    /// Plausibility violations.
    pub violations: Violations,
    /// How close each detector came to firing ([`Monitor::peaks`]): below 1, never.
    pub peaks: Peaks,
    /// Mean number of contact groups per step (0 where groups are not computed).
    pub mean_groups: f64,
    /// Largest contact-variable count of a group, over the run.
    pub max_largest_variables: u32,
    /// Mean awake (simulated, not fixated) bodies per step.
    pub mean_awake: f64,
    /// Awake bodies after the last step.
    pub final_awake: usize,
    /// Measured bodies that ended outside the region `inside` accepts.
    pub left_region: usize,
    /// Per-step awake bodies (for plots like the paper's Figs. 13–14).
    pub awake_series: Vec<u32>,
    /// Per-step timed duration, microseconds.
    pub step_us: Vec<u32>,
    /// The step length of the run, seconds (the scene's `dt`).
    pub dt: f64,
    /// Per-step mean over the measured bodies of the squared linear speed, m²/s²
    /// (NaN once a body's velocity is not finite or a body is missing).
    pub ms_speed_series: Vec<f32>,
    /// Per-step deepest penetration of any contact point in the world, metres (0 when
    /// nothing penetrates).
    pub penetration_series: Vec<f32>,
}

/// Options of a run.
pub struct RunOptions<'a> {
    /// Steps to run.
    pub steps: u64,
    /// Sample positions every this many steps (and at the last step).
    pub sample_every: u64,
    /// The length unit of deviations (the sphere radius).
    pub radius: Real,
    /// The bodies measured (in order); other bodies are ignored.
    pub bodies: &'a [RigidBodyHandle],
    /// The reference trajectory, if measured already.
    pub reference: Option<&'a Trajectory>,
    /// Whether a final position is acceptable (e.g. still on the plane).
    pub inside: &'a dyn Fn(Vector) -> bool,
    /// Monitor thresholds.
    pub monitor: MonitorConfig,
}

/// Every body's position (NaN for a body the scene lacks), in the given order: one
/// frame of a [`Trajectory`]. O(bodies).
pub fn sample(scene: &Scene, bodies: &[RigidBodyHandle]) -> Vec<Vector> {
    per_body(scene, bodies, Vector::splat(Real::NAN), |b| b.translation()).collect()
}

/// `f` of each of `bodies` in order, `missing` for a body the scene lacks. O(1) per
/// item.
fn per_body<'a, T: Copy + 'a>(
    scene: &'a Scene,
    bodies: &'a [RigidBodyHandle],
    missing: T,
    f: impl Fn(&rapier3d::prelude::RigidBody) -> T + 'a,
) -> impl Iterator<Item = T> + 'a {
    bodies
        .iter()
        .map(move |&h| scene.world.bodies.get(h).map_or(missing, &f))
}

/// The deviation of a trajectory from a reference: RMS over frames of the mean
/// position error, in units of `radius`. Frames or bodies missing on either side are
/// skipped; NaN if nothing is comparable.
pub fn deviation(run: &Trajectory, reference: &Trajectory, radius: Real) -> f64 {
    let mut sum_sq = 0.0f64;
    let mut frames = 0usize;
    for (f, r) in run.frames.iter().zip(reference.frames.iter()) {
        let mut err = 0.0f64;
        let mut n = 0usize;
        for (p, q) in f.iter().zip(r.iter()) {
            let d = (*p - *q).length() as f64;
            if d.is_finite() {
                err += d / radius as f64;
                n += 1;
            }
        }
        if n > 0 {
            let mean = err / n as f64;
            sum_sq += mean * mean;
            frames += 1;
        }
    }
    if frames == 0 {
        f64::NAN
    } else {
        (sum_sq / frames as f64).sqrt()
    }
}

/// The measured bodies' mean squared linear speed, m²/s²: NaN if a body is missing or
/// its velocity is not finite. O(bodies).
pub fn mean_square_speed(scene: &Scene, bodies: &[RigidBodyHandle]) -> f64 {
    if bodies.is_empty() {
        return 0.0;
    }
    let sum: f64 = per_body(scene, bodies, f64::NAN, |b| {
        b.linvel().length_squared() as f64
    })
    .sum();
    sum / bodies.len() as f64
}

/// The deepest penetration of any contact point of Rapier's narrow phase, metres (0
/// when none penetrates; speculative contacts have positive distances). Reads every
/// contact pair's manifolds: O(contact points).
pub fn deepest_penetration(scene: &Scene) -> f64 {
    let mut deepest = 0.0f64;
    for pair in scene.world.narrow_phase.contact_pairs() {
        for m in pair.manifolds() {
            for p in &m.points {
                deepest = deepest.max(-(p.dist as f64));
            }
        }
    }
    deepest
}

/// Runs one configuration on a freshly built scene. Returns the result and the
/// sampled trajectory.
// Long: the step loop samples, times and judges in one pass over the steps (phases commented).
pub fn run(
    spec: &RunSpec,
    mut scene: Scene,
    opts: &RunOptions,
) -> rapier_contact_graph::Result<(RunResult, Trajectory)> {
    if opts.sample_every == 0 {
        return Err(rapier_contact_graph::Error::InvalidParameter {
            name: "sample_every",
            reason: "must be at least 1".into(),
        });
    }
    if !(opts.radius.is_finite() && opts.radius > 0.0) {
        return Err(rapier_contact_graph::Error::InvalidParameter {
            name: "radius",
            reason: format!("must be finite and positive, got {}", opts.radius),
        });
    }
    if let Mode::Plain { iterations: 0 } = spec.mode {
        return Err(rapier_contact_graph::Error::InvalidParameter {
            name: "iterations",
            reason: "must be at least 1".into(),
        });
    }
    // The layer's default tracking (touching): the speed-ups, the layer's own monitor
    // and the standalone monitor below read what they need from Rapier, and decide
    // and judge the same as under proximity tracking (the plugin's
    // `speedups_under_touching` and `monitor_under_touching` tests).
    let mut layer = ContactLayer::new();
    match &spec.mode {
        Mode::Stock => {}
        Mode::Plain { iterations } => rcg_scenes::plain_solver(&mut scene.world, *iterations),
        Mode::Layer(s) => layer.speedups_mut().set(Some(s.clone()))?,
    }
    let layered = matches!(spec.mode, Mode::Layer(_));
    if spec.repair && !layered {
        return Err(rapier_contact_graph::Error::InvalidParameter {
            name: "repair",
            reason: format!(
                "`{}` runs plain Rapier: only layer runs can repair",
                spec.name
            ),
        });
    }
    // Repair runs use the layer's own monitor: its checks and repairs are part of the
    // configuration's cost, so they are timed. Every other run is only observed: an
    // untimed monitor outside the step.
    let mut monitor = Monitor::new(opts.monitor)?;
    if spec.repair {
        layer
            .monitor_mut()
            .set(MonitorMode::Repair, opts.monitor, RepairConfig::default())?;
        layer.monitor_mut().prime(&WorldView::from(&scene.world));
    } else {
        monitor.prime(&WorldView::from(&scene.world));
    }
    let mut traj = Trajectory::default();
    let mut timed = Duration::ZERO;
    let (mut groups_sum, mut awake_sum) = (0.0f64, 0.0f64);
    let mut max_vars = 0u32;
    let reserve = opts.steps.min(1 << 20) as usize;
    let mut awake_series = Vec::with_capacity(reserve);
    let mut step_us = Vec::with_capacity(reserve);
    let mut ms_speed_series = Vec::with_capacity(reserve);
    let mut penetration_series = Vec::with_capacity(reserve);
    let mut final_awake = 0usize;
    for step in 0..opts.steps {
        scene.before_step(step);
        let t0 = Instant::now();
        let stats = if layered {
            let s = layer.step(&mut scene.world);
            let dt = t0.elapsed();
            timed += dt;
            step_us.push(dt.as_micros().min(u32::MAX as u128) as u32);
            s
        } else {
            scene.world.step();
            let dt = t0.elapsed();
            timed += dt;
            step_us.push(dt.as_micros().min(u32::MAX as u128) as u32);
            layer.analyze(WorldView::from(&scene.world))
        };
        if !spec.repair {
            let held = |h: RigidBodyHandle| layer.analysis().holds(&scene.world.bodies, h);
            monitor.check(&layer, &WorldView::from(&scene.world), &held, &|_| false);
        }
        let awake = scene
            .world
            .islands
            .active_bodies()
            .filter(|h| scene.world.bodies.get(*h).is_some_and(|b| b.is_dynamic()))
            .count();
        final_awake = awake;
        awake_sum += awake as f64;
        awake_series.push(awake as u32);
        let want_groups = !matches!(&spec.mode, Mode::Layer(s) if !s.groups) && layered;
        if want_groups {
            groups_sum += stats.groups.count as f64;
            max_vars = max_vars.max(stats.groups.largest_variables);
        }
        ms_speed_series.push(mean_square_speed(&scene, opts.bodies) as f32);
        penetration_series.push(deepest_penetration(&scene) as f32);
        if (step + 1) % opts.sample_every == 0 || step + 1 == opts.steps {
            traj.frames.push(sample(&scene, opts.bodies));
        }
    }
    let (totals, peaks) = match layer.monitor() {
        Some(m) => (m.monitor().totals(), m.monitor().peaks()),
        None => (monitor.totals(), monitor.peaks()),
    };
    let violations = Violations {
        hanging: totals.get(ViolationKind::HangingSleeper),
        launch: totals.get(ViolationKind::Launch),
        penetration: totals.get(ViolationKind::DeepPenetration),
        escape: totals.get(ViolationKind::Escape),
        unresponsive: totals.get(ViolationKind::Unresponsive),
    };
    let left_region = opts
        .bodies
        .iter()
        .filter(|&&h| {
            scene
                .world
                .bodies
                .get(h)
                .is_none_or(|b| !(opts.inside)(b.translation()))
        })
        .count();
    let deviation = opts
        .reference
        .map_or(f64::NAN, |r| deviation(&traj, r, opts.radius));
    let n = opts.steps.max(1) as f64;
    let tail: u64 = step_us.iter().rev().take(100).map(|&u| u as u64).sum();
    Ok((
        RunResult {
            name: spec.name.clone(),
            time_s: timed.as_secs_f64(),
            tail_time_s: tail as f64 * 1e-6,
            deviation,
            violations,
            peaks,
            mean_groups: groups_sum / n,
            max_largest_variables: max_vars,
            mean_awake: awake_sum / n,
            final_awake,
            left_region,
            awake_series,
            step_us,
            dt: scene.world.integration_parameters.dt as f64,
            ms_speed_series,
            penetration_series,
        },
        traj,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deviation_is_rms_over_frames_of_mean_error_in_radii() {
        let r = Trajectory {
            frames: vec![
                vec![Vector::ZERO, Vector::ZERO],
                vec![Vector::ZERO, Vector::ZERO],
            ],
        };
        let t = Trajectory {
            frames: vec![
                vec![Vector::new(1.0, 0.0, 0.0), Vector::new(3.0, 0.0, 0.0)], // mean 2
                vec![Vector::ZERO, Vector::ZERO],                             // mean 0
            ],
        };
        // radius 0.5: errors 4 and 0 radii; RMS = sqrt((16 + 0) / 2).
        let d = deviation(&t, &r, 0.5);
        assert!((d - 8f64.sqrt()).abs() < 1e-9, "{d}");
        assert_eq!(deviation(&r, &r, 0.5), 0.0);
        assert!(deviation(&Trajectory::default(), &r, 0.5).is_nan());
    }
}
