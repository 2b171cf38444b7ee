//! The disturbance runs' observables and their judgement against the reference.
//!
//! As in the DIKU run ([`crate::accuracy`]): each configuration runs on `K` seeds,
//! paired with the reference on the same seeds; the `K` differences of an observable
//! give a 95 % Student-t interval ([`paired_interval`]); the tolerance is the largest
//! difference the reference's own refinements (twice its solver iterations, half its
//! time step) admit on the same seeds, at least the observable's resolution; a
//! configuration is *equivalent* on an observable when its interval lies inside
//! `±tolerance`. Only the physical observables are judged; the counts of awake and
//! held bodies, the violations and the times are reported with their intervals but
//! not judged (they are meant to differ). O(K · observables).

use rapier3d::math::Vector;
use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle};

use super::MOVED;
use crate::accuracy::stats::{paired_interval, Interval, StatsError};

/// One run's observables, indexed by the constants of this module.
pub type Outcome = [f64; COUNT];

/// An observable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observable {
    /// Short key (table, CSV).
    pub key: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// The smallest tolerance: differences below this are not told apart.
    pub resolution: f64,
    /// Whether it is judged for equivalence.
    pub judged: bool,
}

const fn obs(key: &'static str, unit: &'static str, resolution: f64, judged: bool) -> Observable {
    Observable {
        key,
        unit,
        resolution,
        judged,
    }
}

/// Pile bodies (boxes, or spheres) displaced more than [`MOVED`] between the
/// disturbance and the end (the unit `boxes` reads `spheres` for a pile of spheres).
pub const DISPLACED: usize = 0;
/// The ball's final `x` (the throw runs along `+x`), m.
pub const BALL_X: usize = 1;
/// The ball's final height, m.
pub const BALL_Y: usize = 2;
/// The ball's final speed, m/s.
pub const BALL_SPEED: usize = 3;
/// Mean height of the pile's bodies at the end, m.
pub const CENTRE_Y: usize = 4;
/// RMS horizontal distance of the pile's bodies from their centroid at the end, m.
pub const SPREAD: usize = 5;
/// Kinetic energy of the pile and the ball at the end, J.
pub const KE: usize = 6;
/// Awake dynamic bodies at the end (held bodies are fixed, not counted).
pub const AWAKE: usize = 7;
/// Bodies held by fixation at the end.
pub const HELD: usize = 8;
/// Monitor violations over the run.
pub const VIOLATIONS: usize = 9;
/// Wall time of all steps, s.
pub const TIME: usize = 10;
/// Wall time of the steps from the disturbance on, s.
pub const AFTER: usize = 11;
/// The slowest step, ms.
pub const WORST: usize = 12;
/// The 99th percentile step time (nearest rank, over all steps), ms.
pub const P99: usize = 13;
/// Number of observables.
pub const COUNT: usize = 14;

/// The observables, indexed as above.
pub const OBSERVABLES: [Observable; COUNT] = [
    obs("displaced", "boxes", 1.0, true),
    obs("ball_x", "m", 0.01, true),
    obs("ball_y", "m", 0.01, true),
    obs("ball_speed", "m/s", 0.01, true),
    obs("centre_y", "m", 0.005, true),
    obs("spread", "m", 0.005, true),
    obs("ke", "J", 0.01, true),
    obs("awake", "bodies", 1.0, false),
    obs("held", "bodies", 1.0, false),
    obs("violations", "", 1.0, false),
    obs("time", "s", 0.0, false),
    obs("after", "s", 0.0, false),
    obs("worst_step", "ms", 0.0, false),
    obs("p99_step", "ms", 0.0, false),
];

/// The physical observables and the awake count of a run's end; the others are
/// left 0 for the runner to fill. `before`/`after`: the pile's positions at the
/// disturbance and at the end (a missing box counts as displaced). The ball's are NaN
/// without a projectile. O(pile).
pub fn observe(
    world: &PhysicsWorld,
    pile: &[RigidBodyHandle],
    projectile: Option<RigidBodyHandle>,
    before: &[Vector],
    after: &[Vector],
) -> Outcome {
    let mut o = [0.0; COUNT];
    o[DISPLACED] = before
        .iter()
        .zip(after)
        .filter(|(b, a)| {
            // A missing box (NaN) counts as displaced.
            let d = (**a - **b).length();
            d > MOVED || d.is_nan()
        })
        .count() as f64;
    let ball = projectile.and_then(|h| world.bodies.get(h));
    o[BALL_X] = ball.map_or(f64::NAN, |b| b.translation().x as f64);
    o[BALL_Y] = ball.map_or(f64::NAN, |b| b.translation().y as f64);
    o[BALL_SPEED] = ball.map_or(f64::NAN, |b| b.linvel().length() as f64);
    let n = after.len().max(1) as f64;
    let (mut cx, mut cy, mut cz) = (0.0f64, 0.0f64, 0.0f64);
    for p in after {
        cx += p.x as f64;
        cy += p.y as f64;
        cz += p.z as f64;
    }
    let (cx, cz) = (cx / n, cz / n);
    o[CENTRE_Y] = cy / n;
    let sq: f64 = after
        .iter()
        .map(|p| (p.x as f64 - cx).powi(2) + (p.z as f64 - cz).powi(2))
        .sum();
    o[SPREAD] = (sq / n).sqrt();
    o[KE] = pile
        .iter()
        .chain(projectile.as_ref())
        .filter_map(|&h| world.bodies.get(h))
        .filter(|b| b.is_dynamic())
        .map(|b| b.kinetic_energy() as f64)
        .fold(0.0, |a, e| a + e);
    o[AWAKE] = world
        .islands
        .active_bodies()
        .filter(|h| world.bodies.get(*h).is_some_and(|b| b.is_dynamic()))
        .count() as f64;
    o
}

/// The paired differences `config[s][j] - reference[s][j]`.
fn differences(config: &[Outcome], reference: &[Outcome], j: usize) -> Vec<f64> {
    config
        .iter()
        .zip(reference)
        .map(|(c, r)| c[j] - r[j])
        .collect()
}

/// The tolerance of every judged observable: the largest interval bound of the
/// refinements' paired differences from the reference, at least the resolution; NaN
/// where a refinement's observable is not finite (nothing is then equivalent on it),
/// and for the observables not judged. Errors: ensembles that do not pair or have
/// fewer than two seeds.
pub fn tolerances(
    refinements: &[&[Outcome]],
    reference: &[Outcome],
) -> Result<[f64; COUNT], StatsError> {
    let mut tol = [f64::NAN; COUNT];
    for (j, t) in tol.iter_mut().enumerate() {
        if !OBSERVABLES[j].judged {
            continue;
        }
        *t = OBSERVABLES[j].resolution;
        for r in refinements {
            if r.len() != reference.len() {
                return Err(StatsError::InvalidParameter {
                    reason: "refinement and reference ensembles do not pair".into(),
                });
            }
            crate::accuracy::stats::widen_tolerance(t, &differences(r, reference, j))?;
        }
    }
    Ok(tol)
}

/// The verdict on one observable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The interval lies inside `±tolerance`.
    Equivalent,
    /// Not equivalent, the interval above zero.
    Higher,
    /// Not equivalent, the interval below zero.
    Lower,
    /// The interval contains zero but reaches beyond the tolerance.
    Undecided,
    /// No interval or no finite tolerance (a non-finite value: e.g. no ball).
    NotJudged,
    /// An observable that is reported, not judged.
    Reported,
}

impl Verdict {
    /// `=`, `+`, `-`, `?`, `!`, or a blank.
    pub fn symbol(self) -> &'static str {
        match self {
            Verdict::Equivalent => "=",
            Verdict::Higher => "+",
            Verdict::Lower => "-",
            Verdict::Undecided => "?",
            Verdict::NotJudged => "!",
            Verdict::Reported => " ",
        }
    }
}

/// One observable of one configuration against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The configuration's mean over seeds.
    pub mean: f64,
    /// The 95 % interval of the paired difference, or why there is none.
    pub interval: Result<Interval, StatsError>,
    /// The tolerance (NaN for observables not judged).
    pub tolerance: f64,
    /// The verdict.
    pub verdict: Verdict,
}

/// Compares every observable of `config` with `reference` (same seeds, same order).
/// Errors: fewer than two seeds or ensembles that do not pair.
pub fn judge(
    config: &[Outcome],
    reference: &[Outcome],
    tolerance: &[f64; COUNT],
) -> Result<Vec<Comparison>, StatsError> {
    if config.len() != reference.len() {
        return Err(StatsError::InvalidParameter {
            reason: "configuration and reference ensembles do not pair".into(),
        });
    }
    if config.len() < 2 {
        return Err(StatsError::TooFewSamples { k: config.len() });
    }
    Ok((0..COUNT)
        .map(|j| {
            let mean = config.iter().map(|o| o[j]).sum::<f64>() / config.len() as f64;
            let interval = paired_interval(&differences(config, reference, j));
            let tol = tolerance[j];
            let verdict = match &interval {
                _ if !OBSERVABLES[j].judged => Verdict::Reported,
                Ok(iv) if tol.is_finite() => {
                    if iv.within(tol) {
                        Verdict::Equivalent
                    } else if iv.lo > 0.0 {
                        Verdict::Higher
                    } else if iv.hi < 0.0 {
                        Verdict::Lower
                    } else {
                        Verdict::Undecided
                    }
                }
                _ => Verdict::NotJudged,
            };
            Comparison {
                mean,
                interval,
                tolerance: tol,
                verdict,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ensemble(base: f64, noise: &[f64]) -> Vec<Outcome> {
        noise.iter().map(|&n| [base + n; COUNT]).collect()
    }

    #[test]
    fn verdicts_follow_the_interval_and_the_tolerance() {
        let noise = [0.0, 0.5, -0.5, 0.25, -0.25, 0.1, -0.1, 0.0];
        let reference = ensemble(10.0, &noise);
        let same = judge(&reference, &reference, &[1.0; COUNT]).unwrap();
        assert_eq!(same[DISPLACED].verdict, Verdict::Equivalent);
        assert_eq!(same[TIME].verdict, Verdict::Reported);
        let lower = ensemble(2.0, &noise);
        assert_eq!(
            judge(&lower, &reference, &[1.0; COUNT]).unwrap()[DISPLACED].verdict,
            Verdict::Lower
        );
        let higher = ensemble(15.0, &noise);
        let j = judge(&higher, &reference, &[1.0; COUNT]).unwrap();
        assert_eq!((j[KE].verdict, j[KE].mean), (Verdict::Higher, 15.0));
        let wide: Vec<Outcome> = (0..8)
            .map(|s| [10.0 + if s % 2 == 0 { 5.0 } else { -5.0 }; COUNT])
            .collect();
        let j = judge(&wide, &ensemble(10.0, &[0.0; 8]), &[1.0; COUNT]).unwrap();
        assert_eq!(j[SPREAD].verdict, Verdict::Undecided);
        let mut nan = reference.clone();
        nan[2][BALL_X] = f64::NAN;
        let j = judge(&nan, &reference, &[1.0; COUNT]).unwrap();
        assert_eq!(j[BALL_X].verdict, Verdict::NotJudged);
        assert!(judge(&reference[..1], &reference[..1], &[1.0; COUNT]).is_err());
        assert!(judge(&reference[..3], &reference, &[1.0; COUNT]).is_err());
    }

    #[test]
    fn tolerances_are_the_refinements_bounds_at_least_the_resolution() {
        let reference = ensemble(10.0, &[0.0; 4]);
        let refined = ensemble(13.0, &[0.0, 0.1, -0.1, 0.0]);
        let tol = tolerances(&[&refined, &reference], &reference).unwrap();
        assert!(
            tol[DISPLACED] > 3.0 && tol[DISPLACED] < 3.3,
            "{}",
            tol[DISPLACED]
        );
        let tol = tolerances(&[&reference], &reference).unwrap();
        assert_eq!((tol[DISPLACED], tol[CENTRE_Y]), (1.0, 0.005));
        assert!(tol[TIME].is_nan());
        assert!(tolerances(&[&refined[..2]], &reference).is_err());
    }
}
