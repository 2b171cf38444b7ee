//! Chaos-robust observables of one DIKU run: what a physicist would compare between
//! two simulations of a chaotic pile (definitions and units also in
//! `docs/accuracy.md`).
//!
//! A single sphere's trajectory is chaotic (one ulp at the start moves it by a third
//! of a radius), so no observable here follows a body. Each is a property of the whole
//! ensemble of spheres that a different but equally good simulation reproduces *in
//! distribution*: where the spheres end (regions, the pile's centre and spread, mean
//! height, the distribution of along-slope positions), and how they got there (RMS
//! speed while rolling, settling time). Plausibility (penetration, the monitor's
//! violations) needs no reference and is kept apart ([`Plausibility`]).
//!
//! Every observable is computed in O(spheres) from the final frame of
//! [`Trajectory`](crate::measure::Trajectory) and the per-step series of
//! [`RunResult`], except the Wasserstein distance (O(N log N)).

use rapier3d::math::Vector;
use rcg_scenes::diku::{groove_letter, is_on_plane, to_plane_frame, DikuParams, RUNOUT};

use super::stats::wasserstein1;
use crate::measure::{RunResult, Violations};

/// One observable: its names and unit, and the smallest tolerance it is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observable {
    /// Short column name (`results.csv`, the printed table).
    pub key: &'static str,
    /// What it is, in a few words.
    pub name: &'static str,
    /// Unit of its values and differences.
    pub unit: &'static str,
    /// The floor of its tolerance: a difference this small is below what the
    /// observable resolves (one sphere for counts, 1 mm, 1 mm/s, one step of 0.01 s).
    pub resolution: f64,
    /// A distance to the same-seed reference (0 for the reference itself, positive
    /// for any other run, chaos included) rather than a value compared by difference:
    /// its difference is only shown larger when it exceeds the tolerance, the
    /// refinements' own distance ([`crate::accuracy::Comparison::sign`]).
    pub distance: bool,
}

/// Number of observables.
pub const COUNT: usize = 12;

/// Index of the at-the-rim count in [`OBSERVABLES`].
pub const RIM: usize = 0;
/// Index of the first of the four per-letter groove counts (D, I, K, U).
pub const GROOVE_D: usize = 1;
/// Index of the count of spheres elsewhere.
pub const ELSEWHERE: usize = 5;
/// Index of the pile's centre.
pub const PILE_CENTRE: usize = 6;
/// Index of the pile's spread.
pub const PILE_SPREAD: usize = 7;
/// Index of the mean height.
pub const MEAN_HEIGHT: usize = 8;
/// Index of the Wasserstein-1 distance to the same-seed reference.
pub const W1: usize = 9;
/// Index of the RMS speed over the first seconds.
pub const RMS_SPEED: usize = 10;
/// Index of the settling time.
pub const SETTLING: usize = 11;

/// The observables, in the order of an [`Outcome`].
pub const OBSERVABLES: [Observable; COUNT] = [
    Observable {
        key: "rim",
        name: "spheres at the rim (in the run-out, x < 4.5 m)",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "groove_D",
        name: "spheres in the D's grooves",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "groove_I",
        name: "spheres in the I's grooves",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "groove_K",
        name: "spheres in the K's grooves",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "groove_U",
        name: "spheres in the U's grooves",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "elsewhere",
        name: "spheres elsewhere (on the land above the run-out, or off the plane)",
        unit: "spheres",
        resolution: 1.0,
        distance: false,
    },
    Observable {
        key: "pile_centre",
        name: "pile centre: mean along-slope position of the spheres at the rim",
        unit: "m",
        resolution: 0.001,
        distance: false,
    },
    Observable {
        key: "pile_spread",
        name: "pile spread: standard deviation of their along-slope positions",
        unit: "m",
        resolution: 0.001,
        distance: false,
    },
    Observable {
        key: "mean_height",
        name:
            "mean height of the centres above the flat surface (potential energy across the slope)",
        unit: "m",
        resolution: 0.001,
        distance: false,
    },
    Observable {
        key: "w1",
        name:
            "Wasserstein-1 distance of the final along-slope positions to the same-seed reference's",
        unit: "m",
        resolution: 0.001,
        distance: true,
    },
    Observable {
        key: "rms_speed",
        name: "RMS speed of the spheres over 0-3 s",
        unit: "m/s",
        resolution: 0.001,
        distance: false,
    },
    Observable {
        key: "settling",
        name: "settling time: end of the last step with RMS speed >= 0.05 m/s",
        unit: "s",
        resolution: 0.01,
        distance: false,
    },
];

/// The window of [`RMS_SPEED`]: the first 3 simulated seconds (falling and rolling).
pub const SPEED_WINDOW_S: f64 = 3.0;
/// The RMS speed below which the spheres count as settled ([`SETTLING`]).
pub const SETTLED_RMS_SPEED: f64 = 0.05;

/// One run's observables, indexed as [`OBSERVABLES`]. A value is NaN when it cannot
/// be computed (a body escaped, no sphere reached the rim).
pub type Outcome = [f64; COUNT];

/// Plausibility of one run, which needs no reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Plausibility {
    /// Deepest contact penetration over the run, millimetres.
    pub peak_penetration_mm: f64,
    /// Deepest contact penetration, averaged over the steps of the last simulated
    /// second, millimetres: how deep the settled pile rests.
    pub resting_penetration_mm: f64,
    /// The monitor's violations by kind.
    pub violations: Violations,
}

/// The plausibility figures of a run. O(steps).
pub fn plausibility(result: &RunResult) -> Plausibility {
    let series = &result.penetration_series;
    let peak = series.iter().fold(0.0f64, |m, &p| m.max(p as f64));
    let last = steps_in(1.0, result.dt).clamp(1, series.len().max(1));
    let tail = &series[series.len().saturating_sub(last)..];
    let resting = if tail.is_empty() {
        0.0
    } else {
        tail.iter().map(|&p| p as f64).sum::<f64>() / tail.len() as f64
    };
    Plausibility {
        peak_penetration_mm: peak * 1e3,
        resting_penetration_mm: resting * 1e3,
        violations: result.violations,
    }
}

/// Steps of length `dt` in `seconds` (rounded; 0 for a non-positive `dt`).
fn steps_in(seconds: f64, dt: f64) -> usize {
    if dt > 0.0 && dt.is_finite() {
        (seconds / dt).round() as usize
    } else {
        0
    }
}

/// The observables of a DIKU run from its result, its final positions (world frame,
/// one per sphere) and the same-seed reference's final positions (for [`W1`]; the
/// run's own for the reference itself, giving 0). O(N log N).
pub fn observe(
    params: &DikuParams,
    result: &RunResult,
    last: &[Vector],
    reference_last: &[Vector],
) -> Outcome {
    let mut out = [0.0; COUNT];
    let mut pile = Vec::new();
    let mut height_sum = 0.0f64;
    let mut finite = true;
    for &p in last {
        let q = to_plane_frame(params, p);
        if !(q.x.is_finite() && q.y.is_finite() && q.z.is_finite()) {
            finite = false;
            out[ELSEWHERE] += 1.0;
            continue;
        }
        height_sum += q.y as f64;
        if let Some(letter) = groove_letter(params, p) {
            out[GROOVE_D + letter] += 1.0;
        } else if q.x < RUNOUT && is_on_plane(params, p) {
            out[RIM] += 1.0;
            pile.push(q.x as f64);
        } else {
            out[ELSEWHERE] += 1.0;
        }
    }
    let nan_unless = |ok: bool, v: f64| if ok { v } else { f64::NAN };
    let n = last.len() as f64;
    out[MEAN_HEIGHT] = nan_unless(finite && n > 0.0, height_sum / n);
    if pile.is_empty() {
        out[PILE_CENTRE] = f64::NAN;
        out[PILE_SPREAD] = f64::NAN;
    } else {
        let m = pile.len() as f64;
        let mean = pile.iter().sum::<f64>() / m;
        let var = pile.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / m;
        out[PILE_CENTRE] = mean;
        out[PILE_SPREAD] = var.sqrt();
    }
    let along = |ps: &[Vector]| -> Vec<f64> {
        ps.iter()
            .map(|&p| to_plane_frame(params, p).x as f64)
            .collect()
    };
    out[W1] = wasserstein1(&along(last), &along(reference_last)).unwrap_or(f64::NAN);
    let window = steps_in(SPEED_WINDOW_S, result.dt).min(result.ms_speed_series.len());
    out[RMS_SPEED] = if window == 0 {
        f64::NAN
    } else {
        let s: f64 = result.ms_speed_series[..window]
            .iter()
            .map(|&v| v as f64)
            .sum();
        (s / window as f64).sqrt()
    };
    out[SETTLING] = settling_time(&result.ms_speed_series, result.dt);
    out
}

/// The end time of the last step whose RMS speed (√ of the mean square speed) is at
/// least [`SETTLED_RMS_SPEED`]; 0 if none is; NaN if a value is not finite. When the
/// spheres never settle this is the run's duration (censored). O(steps).
pub fn settling_time(ms_speed_series: &[f32], dt: f64) -> f64 {
    let threshold = SETTLED_RMS_SPEED * SETTLED_RMS_SPEED;
    if ms_speed_series.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    ms_speed_series
        .iter()
        .rposition(|&v| v as f64 >= threshold)
        .map_or(0.0, |i| (i + 1) as f64 * dt)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rcg_scenes::diku::plane_pose;

    fn result(ms: Vec<f32>, pen: Vec<f32>, dt: f64) -> RunResult {
        RunResult {
            name: "t".into(),
            time_s: 0.0,
            tail_time_s: 0.0,
            deviation: 0.0,
            violations: Violations::default(),
            peaks: Default::default(),
            mean_groups: 0.0,
            max_largest_variables: 0,
            mean_awake: 0.0,
            final_awake: 0,
            left_region: 0,
            awake_series: vec![],
            step_us: vec![],
            dt,
            ms_speed_series: ms,
            penetration_series: pen,
        }
    }

    #[test]
    fn regions_pile_and_distances_of_placed_spheres() {
        let params = DikuParams::default();
        let pose = plane_pose(&params);
        let world = |x: f32, y: f32, z: f32| pose.transform_point(Vector::new(x, y, z));
        // Two at the rim (x = 0.5, 1.5), one in the D's stem (row 2, column 1), one on
        // the top strip.
        let w = rcg_scenes::diku::plane_width(120);
        let d_stem = world(4.5 + 2.5 * 1.2, 0.3, -w / 2.0 + 1.5 * 1.2);
        let last = vec![
            world(0.5, 0.5, 0.0),
            world(1.5, 0.5, 1.0),
            d_stem,
            world(12.0, 0.5, 0.0),
        ];
        // 400 steps at 0.01 s: RMS speed 2 m/s for 3 s, then 0.1 m/s until 3.5 s,
        // then 0.
        let mut ms = vec![4.0f32; 300];
        ms.extend([0.01f32; 50]);
        ms.extend([0.0f32; 50]);
        let mut pen = vec![0.002f32; 300];
        pen.extend([0.0005f32; 100]);
        let r = result(ms, pen, 0.01);
        let o = observe(&params, &r, &last, &last);
        assert_eq!(o[RIM], 2.0);
        assert_eq!(o[GROOVE_D..GROOVE_D + 4], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(o[ELSEWHERE], 1.0);
        assert!((o[PILE_CENTRE] - 1.0).abs() < 1e-5);
        assert!((o[PILE_SPREAD] - 0.5).abs() < 1e-5);
        assert!((o[MEAN_HEIGHT] - (0.5 * 3.0 + 0.3) / 4.0).abs() < 1e-5);
        assert_eq!(o[W1], 0.0);
        assert!((o[RMS_SPEED] - 2.0).abs() < 1e-9);
        assert!((o[SETTLING] - 3.5).abs() < 1e-9);
        let p = plausibility(&r);
        assert!((p.peak_penetration_mm - 2.0).abs() < 1e-4);
        assert!((p.resting_penetration_mm - 0.5).abs() < 1e-4);
        // Every sphere 0.25 m further down: W1 0.25 against the original.
        let lower: Vec<Vector> = last
            .iter()
            .map(|&p| {
                let q = to_plane_frame(&params, p);
                world(q.x - 0.25, q.y, q.z)
            })
            .collect();
        let o2 = observe(&params, &r, &lower, &last);
        assert!((o2[W1] - 0.25).abs() < 1e-5, "{}", o2[W1]);
    }

    #[test]
    fn escaped_or_empty_runs_give_nan_never_a_panic() {
        let params = DikuParams::default();
        let r = result(vec![f32::NAN; 10], vec![], 0.01);
        let bad = vec![Vector::splat(f32::NAN), Vector::ZERO];
        let o = observe(&params, &r, &bad, &bad);
        assert!(o[MEAN_HEIGHT].is_nan() && o[W1].is_nan() && o[SETTLING].is_nan());
        assert!(o[RMS_SPEED].is_nan());
        assert_eq!(o[ELSEWHERE] + o[RIM], 2.0);
        let empty = observe(&params, &result(vec![], vec![], 0.0), &[], &[]);
        assert!(empty[PILE_CENTRE].is_nan() && empty[W1].is_nan());
        assert_eq!(
            plausibility(&result(vec![], vec![], 0.0)),
            Plausibility::default()
        );
        assert_eq!(settling_time(&[0.0, 0.0], 0.01), 0.0);
    }
}
