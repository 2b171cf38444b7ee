//! Disturbing a settled pile: does a configuration let a pile be moved as much as a
//! simulation without sleep does? (paper §7, fixation; Erleben 2004, §5 on waking.)
//!
//! Each scene of `rcg_scenes::disturb` settles a pile and then disturbs it (a
//! thrown ball, a removed floor segment, a sweeping paddle in a box pile; a heavy
//! sphere thrown into the DIKU scene's pile of spheres; a heavy ball thrown into the
//! held-bodies benchmark's bin of mixed balls and boxes). A run steps one scene on
//! one seed under one [`Config`] and reads its [`Outcome`]: how many pile bodies moved
//! more than [`MOVED`] between the disturbance and the end, where the ball ended and
//! how fast, the pile's centre height and horizontal spread, the kinetic energy left,
//! the awake and held bodies, the monitor's violations and the step times. [`judge`]
//! pairs runs with the reference on the same seeds, as the DIKU run does
//! ([`crate::accuracy`]); definitions in `docs/disturb.md`.
//!
//! Cost: one run is O(steps · Rapier's step); the observables on top are O(pile)
//! twice, and the untimed monitor O(awake bodies) a step.

pub mod judge;

use std::time::Instant;

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle};
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, MonitorMode, RepairConfig, ViolationKind,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes::disturb::{DisturbParams, Disturbance};

pub use judge::{Outcome, COUNT, OBSERVABLES};

/// A pile box counts as displaced when it moved farther than this between the
/// disturbance and the end, m.
pub const MOVED: Real = 0.01;

/// How a run drives Rapier.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    /// Rapier's defaults with sleep off for every body (the ball included), observed
    /// only: the reference.
    NoSleep {
        /// Solver iterations (Rapier's default 4; 8 for the refinement).
        iterations: usize,
        /// Divide the time step by this (1; 2 for the refinement).
        dt_divisor: u64,
    },
    /// Stock Rapier: its defaults, its own sleep.
    Stock,
    /// The layer with these speed-ups; `repair`: its monitor repairing.
    Layer {
        /// The speed-ups.
        speedups: SpeedUps,
        /// Whether the layer's monitor repairs ([`MonitorMode::Repair`]).
        repair: bool,
    },
}

/// A configuration to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Long name (CSV, report).
    pub name: &'static str,
    /// Short name (table column).
    pub short: &'static str,
    /// How Rapier is driven.
    pub setting: Setting,
}

/// The reference: Rapier's defaults with sleep off.
pub fn reference() -> Config {
    Config {
        name: "reference (no sleep)",
        short: "reference",
        setting: Setting::NoSleep {
            iterations: 4,
            dt_divisor: 1,
        },
    }
}

/// The reference's refinements: twice its solver iterations, half its time step.
/// Their change against it is the tolerance ([`judge::tolerances`]).
pub fn refinements() -> [Config; 2] {
    [
        Config {
            name: "reference, 2x iterations",
            short: "ref 2x it",
            setting: Setting::NoSleep {
                iterations: 8,
                dt_divisor: 1,
            },
        },
        Config {
            name: "reference, dt/2",
            short: "ref dt/2",
            setting: Setting::NoSleep {
                iterations: 4,
                dt_divisor: 2,
            },
        },
    ]
}

/// Steps at rest before `rel-rest50` holds a body (0.5 s at dt = 0.01; the preset's
/// `sleepy_steps` is 20).
pub const LATE_HOLD_STEPS: u32 = 50;

/// Configurations run only when named (`--configs`): `reliable_sleep()` holding a body
/// only after [`LATE_HOLD_STEPS`] steps at rest, to measure what holding later trades
/// (`docs/results.md`, "One spread per disturbance": with one spread, the bin hit's
/// count no longer depends on it).
pub fn named_only() -> Vec<Config> {
    vec![Config {
        name: "reliable_sleep, held after 0.5 s at rest",
        short: "rel-rest50",
        setting: Setting::Layer {
            speedups: SpeedUps {
                sleepy_steps: LATE_HOLD_STEPS,
                ..SpeedUps::reliable_sleep()
            },
            repair: false,
        },
    }]
}

/// The configurations judged against the reference: stock Rapier, the layer's sleep
/// (`SpeedUps::default()`), `reliable_sleep()` without and with the monitor repairing,
/// `reliable_sleep()` with the release confined to the bodies reached (the
/// alternative to waking the held group whole), and `papers_fastest()`.
pub fn configs() -> Vec<Config> {
    let layer = |name, short, speedups, repair| Config {
        name,
        short,
        setting: Setting::Layer { speedups, repair },
    };
    vec![
        Config {
            name: "stock Rapier",
            short: "stock",
            setting: Setting::Stock,
        },
        layer("layer sleep (default)", "sleep", SpeedUps::default(), false),
        layer(
            "reliable_sleep",
            "reliable",
            SpeedUps::reliable_sleep(),
            false,
        ),
        layer(
            "reliable_sleep, release_group off",
            "rel-nogroup",
            SpeedUps {
                release_group: false,
                ..SpeedUps::reliable_sleep()
            },
            false,
        ),
        layer(
            "reliable_sleep +repair",
            "reliable+rep",
            SpeedUps::reliable_sleep(),
            true,
        ),
        layer(
            "papers_fastest",
            "fastest",
            SpeedUps::papers_fastest(),
            false,
        ),
    ]
}

/// A disturbance scene's builder.
pub type Builder = fn(&DisturbParams) -> Disturbance;

/// A scene of the runner: its builder, its default sizes and what its pile is made of.
#[derive(Clone, Copy, Debug)]
pub struct SceneSpec {
    /// Its name (`--scenes`, tables, CSV).
    pub name: &'static str,
    /// Its builder.
    pub build: Builder,
    /// Its pile's bodies, disturbance step and steps after when not given (the seed is
    /// the run's).
    pub defaults: DisturbParams,
    /// Its pile's bodies under `--quick`.
    pub quick_bodies: usize,
    /// What the pile is made of, plural (`boxes`, `spheres`): the tables' unit of
    /// `displaced`.
    pub bodies: &'static str,
}

/// The box scenes' defaults: 250 boxes, 3 s of settling, 2 s after.
const BOX_PILE: DisturbParams = DisturbParams {
    boxes: 250,
    seed: 0,
    at: 300,
    after: 200,
};

const fn boxes(name: &'static str, build: Builder) -> SceneSpec {
    SceneSpec {
        name,
        build,
        defaults: BOX_PILE,
        quick_bodies: 150,
        bodies: "boxes",
    }
}

/// The scenes, in report order: the three box piles, then the DIKU scene with a
/// sphere thrown in (its own sizes: the DIKU run's 120 spheres, the throw at 10 s),
/// then the held-bodies benchmark's bin of mixed balls and boxes hit by a heavy ball
/// (its own sizes: 1,000 bodies, the hit at 10 s, 6 s after; a smaller bin under
/// `--quick`).
pub const SCENES: [SceneSpec; 5] = [
    boxes("thrown_ball", rcg_scenes::disturb::thrown_ball),
    boxes("support_removed", rcg_scenes::disturb::support_removed),
    boxes("paddle", rcg_scenes::disturb::paddle),
    SceneSpec {
        name: "diku_throw",
        build: rcg_scenes::disturb::diku_throw,
        defaults: rcg_scenes::disturb::diku_throw::params(),
        quick_bodies: QUICK_SPHERES,
        bodies: "spheres",
    },
    SceneSpec {
        name: "bin_hit",
        build: rcg_scenes::disturb::bin_hit,
        defaults: rcg_scenes::disturb::bin_hit::params(),
        quick_bodies: QUICK_BIN,
        bodies: "bodies",
    },
];

/// The mixed bin under `--quick`: 120 bodies in a bin of their size (6 m across),
/// hit by the same ball at the same time (about a tenth of the default run's cost).
pub const QUICK_BIN: usize = 120;

/// The DIKU pile under `--quick`.
pub const QUICK_SPHERES: usize = 120;

/// Sleep off for every body of the world: Rapier's activation thresholds below zero
/// (as `rcg_scenes::plain_solver` does). O(bodies).
fn no_sleep(world: &mut PhysicsWorld) {
    for (_, rb) in world.bodies.iter_mut() {
        let a = rb.activation_mut();
        a.normalized_linear_threshold = -1.0;
        a.angular_threshold = -1.0;
    }
}

/// What one run measured, besides its [`Outcome`]: the per-step times.
#[derive(Clone, Debug)]
pub struct Run {
    /// The observables ([`OBSERVABLES`]).
    pub outcome: Outcome,
    /// Bodies held by fixation at the disturbance step (0 without the layer).
    pub held_at_disturbance: usize,
}

/// Runs `config` on the scene `build` builds from `params`. Errors: a configuration
/// the layer refuses. O(steps · Rapier's step).
// Long: the step loop measures and judges in one pass over the steps.
pub fn run(config: &Config, build: Builder, params: &DisturbParams) -> Result<Run, String> {
    let mut d = build(params);
    let fail =
        |e: rapier_contact_graph::Error| format!("{} on seed {}: {e}", config.name, params.seed);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).map_err(fail)?;
    let (layered, repair, plain_no_sleep) = match &config.setting {
        Setting::NoSleep {
            iterations,
            dt_divisor,
        } => {
            d.scene.world.integration_parameters.num_solver_iterations = *iterations;
            d.refine_time_step(*dt_divisor)?;
            (false, false, true)
        }
        Setting::Stock => (false, false, false),
        Setting::Layer { speedups, repair } => {
            layer
                .speedups_mut()
                .set(Some(speedups.clone()))
                .map_err(fail)?;
            (true, *repair, false)
        }
    };
    if repair {
        layer
            .monitor_mut()
            .set(
                MonitorMode::Repair,
                MonitorConfig::default(),
                RepairConfig::default(),
            )
            .map_err(fail)?;
        layer.monitor_mut().prime(&WorldView::from(&d.scene.world));
    } else {
        monitor.prime(&WorldView::from(&d.scene.world));
    }
    let mut step_us: Vec<f64> = Vec::with_capacity(d.steps as usize);
    let mut before: Vec<Vector> = Vec::new();
    let mut held_at_disturbance = 0;
    let mut after_s = 0.0;
    for step in 0..d.steps {
        if step == d.at {
            before = positions(&d.scene.world, &d.pile);
            held_at_disturbance = held(&layer);
        }
        d.before_step(step);
        if plain_no_sleep && (step == 0 || step == d.at) {
            no_sleep(&mut d.scene.world);
        }
        let t0 = Instant::now();
        if layered {
            layer.step(&mut d.scene.world);
        } else {
            d.scene.world.step();
        }
        let dt = t0.elapsed().as_secs_f64();
        step_us.push(dt * 1e6);
        if step >= d.at {
            after_s += dt;
        }
        if !layered {
            layer.analyze(WorldView::from(&d.scene.world));
        }
        if !repair {
            let world = &d.scene.world;
            let held = |h: RigidBodyHandle| layer.analysis().holds(&world.bodies, h);
            monitor.check(&layer, &WorldView::from(world), &held, &|_| false);
        }
    }
    let total_s = step_us.iter().sum::<f64>() * 1e-6;
    let totals = match layer.monitor() {
        Some(m) => m.monitor().totals(),
        None => monitor.totals(),
    };
    let violations = [
        ViolationKind::HangingSleeper,
        ViolationKind::Launch,
        ViolationKind::DeepPenetration,
        ViolationKind::Escape,
    ]
    .iter()
    .map(|&k| totals.get(k))
    .sum::<u64>();
    let world = &d.scene.world;
    let after = positions(world, &d.pile);
    let mut o = judge::observe(world, &d.pile, d.projectile, &before, &after);
    o[judge::HELD] = held(&layer) as f64;
    o[judge::VIOLATIONS] = violations as f64;
    o[judge::TIME] = total_s;
    o[judge::AFTER] = after_s;
    let mut sorted = step_us;
    sorted.sort_by(f64::total_cmp);
    o[judge::WORST] = sorted.last().copied().unwrap_or(0.0) * 1e-3;
    o[judge::P99] = percentile(&sorted, 0.99) * 1e-3;
    Ok(Run {
        outcome: o,
        held_at_disturbance,
    })
}

/// Bodies held by the layer's fixation now.
fn held(layer: &ContactLayer) -> usize {
    layer.speedups().map_or(0, |s| s.stats().fixated)
}

/// The positions of `bodies` (NaN for a missing one). O(bodies).
pub fn positions(world: &PhysicsWorld, bodies: &[RigidBodyHandle]) -> Vec<Vector> {
    bodies
        .iter()
        .map(|&h| {
            world
                .bodies
                .get(h)
                .map_or(Vector::splat(Real::NAN), |b| b.translation())
        })
        .collect()
}

/// The `q` quantile of an ascending sample (nearest rank); 0 for an empty one.
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.99), 99.0);
        assert_eq!(percentile(&v, 1.0), 100.0);
        assert_eq!(percentile(&[3.0], 0.99), 3.0);
        assert_eq!(percentile(&[], 0.5), 0.0);
    }
}
