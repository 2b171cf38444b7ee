//! Accuracy that a physicist would trust: paired seed ensembles,
//! chaos-robust observables, and equivalence against the reference's own
//! discretisation error. Definitions with units: `docs/accuracy.md`.
//!
//! # Why not the trajectory deviation
//! The DIKU scene is chaotic: brute force against itself with every sphere moved by
//! one ulp ends about 0.3 radii (mean position error, RMS over the run) away, the
//! reference at twice its iterations about 0.8 radii, another jitter seed 2.4 radii.
//! A per-body trajectory error therefore measures chaos, not accuracy, and differences
//! of a few tenths of a radius between configurations say nothing. What a physicist
//! compares instead is the *outcome in distribution*: how many spheres end where, the
//! pile's shape, how fast they rolled, when they settled ([`observables`]).
//!
//! # The procedure
//! 1. **Paired seeds.** Each configuration runs on `K` jitter seeds of the scene
//!    (`DikuParams::seed`), and each run is paired with the reference on the same
//!    seed: the difference of an observable on a seed removes what the seed alone
//!    decides (where the spheres started), and the `K` differences give a 95 %
//!    Student-t interval of the mean difference ([`stats::paired_interval`]).
//! 2. **Tolerance from the reference's own error.** The reference (16 iterations, dt
//!    0.01) is itself a discretisation. The same run measures it against two
//!    refinements on the same seeds: twice its iterations, and half its time step. The
//!    tolerance of an observable is the largest difference either refinement's 95 %
//!    interval admits ([`stats::Interval::bound`]), at least the observable's
//!    resolution ([`observables::Observable::resolution`]). The interval bound rather
//!    than the mean: with `K = 8` a mean difference can come out near zero by chance,
//!    and a tolerance the reference's own refinement could not pass would judge
//!    discretisation noise as a difference.
//! 3. **Equivalence.** A configuration is equivalent to the reference on an
//!    observable when the 95 % interval of its paired difference lies inside
//!    `±tolerance` (two one-sided tests at 2.5 % each); equivalent when it is on every
//!    observable. Otherwise [`Judgement::differs`] names the observables, each with
//!    the sign of the difference when the interval excludes zero (`+`/`-`) and `?`
//!    when it only is too wide to decide. The Wasserstein distance is a distance, 0
//!    only for the reference itself: it is `+` only when its whole interval lies
//!    beyond the tolerance (farther than the refinements), else `?`.
//! 4. **One number.** The chart's accuracy number is the worst observable's
//!    `|mean difference| / tolerance`: 1.0 is the edge of what the reference itself can
//!    tell apart; it does not include the interval's width, so a configuration can be
//!    below 1 and still not proven equivalent with few seeds.
//!
//! # Bad input
//! Fewer than two seeds is a usage error ([`stats::StatsError::TooFewSamples`]); a
//! non-finite observable on any seed (an escaped sphere, no sphere at the rim) makes
//! the configuration *not equivalent* with the reason, and its accuracy number
//! infinite: never a panic, never a dropped row.

pub mod ensemble;
pub mod observables;
pub mod stats;

use observables::{Outcome, COUNT, OBSERVABLES};
use stats::{paired_interval, Interval, StatsError};

/// Per observable, the paired differences of `config` against `reference` (same
/// seeds, same order): `config[s][j] - reference[s][j]`. O(K).
fn differences(config: &[Outcome], reference: &[Outcome], j: usize) -> Vec<f64> {
    config
        .iter()
        .zip(reference)
        .map(|(c, r)| c[j] - r[j])
        .collect()
}

/// Checks that two ensembles pair up: the same number of seeds, at least two.
fn check_pairs(config: &[Outcome], reference: &[Outcome]) -> Result<(), StatsError> {
    if config.len() != reference.len() {
        return Err(StatsError::InvalidParameter {
            reason: format!(
                "{} configuration runs cannot pair with {} reference runs",
                config.len(),
                reference.len()
            ),
        });
    }
    if config.len() < 2 {
        return Err(StatsError::TooFewSamples { k: config.len() });
    }
    Ok(())
}

/// The tolerance of every observable from the reference's refinements (each an
/// ensemble on the reference's seeds): the largest [`Interval::bound`] over the
/// refinements, at least the observable's resolution. NaN where a refinement's
/// observable is not finite on some seed (nothing is then judged equivalent on it).
/// O(refinements · K · observables).
///
/// Errors: no refinement, fewer than two seeds, or ensembles that do not pair.
pub fn tolerances(
    refinements: &[&[Outcome]],
    reference: &[Outcome],
) -> Result<[f64; COUNT], StatsError> {
    if refinements.is_empty() {
        return Err(StatsError::InvalidParameter {
            reason: "a tolerance needs at least one refinement of the reference".into(),
        });
    }
    let mut tol = [0.0f64; COUNT];
    for (j, t) in tol.iter_mut().enumerate() {
        *t = OBSERVABLES[j].resolution;
    }
    for r in refinements {
        check_pairs(r, reference)?;
        for (j, t) in tol.iter_mut().enumerate() {
            stats::widen_tolerance(t, &differences(r, reference, j))?;
        }
    }
    Ok(tol)
}

/// The direction of a difference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// The interval lies above zero: the configuration's value is larger.
    Higher,
    /// The interval lies below zero.
    Lower,
    /// The interval contains zero but reaches beyond the tolerance: undecided.
    Undecided,
}

impl Sign {
    /// `+`, `-` or `?`.
    pub fn symbol(self) -> char {
        match self {
            Sign::Higher => '+',
            Sign::Lower => '-',
            Sign::Undecided => '?',
        }
    }
}

/// One observable's comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The 95 % interval of the paired difference, or why there is none.
    pub interval: Result<Interval, StatsError>,
    /// The tolerance it is judged against.
    pub tolerance: f64,
    /// Whether the observable is a distance to the reference
    /// ([`observables::Observable::distance`]).
    pub distance: bool,
}

impl Comparison {
    /// `|mean difference| / tolerance`; infinite without an interval or with a
    /// non-finite tolerance; 0 for a zero difference at a zero tolerance.
    pub fn ratio(&self) -> f64 {
        match &self.interval {
            Ok(iv) if self.tolerance.is_finite() => {
                if iv.mean == 0.0 {
                    0.0
                } else {
                    iv.mean.abs() / self.tolerance
                }
            }
            _ => f64::INFINITY,
        }
    }

    /// Whether the interval lies inside `±tolerance`.
    pub fn equivalent(&self) -> bool {
        self.interval
            .as_ref()
            .is_ok_and(|iv| iv.within(self.tolerance))
    }

    /// The sign of a difference that is not equivalent; `None` when equivalent or
    /// without an interval. A difference is [`Sign::Higher`] when its interval lies
    /// above 0, [`Sign::Lower`] below 0, else [`Sign::Undecided`]. A distance is 0 only
    /// for the reference itself and positive for any other run, so for a distance the
    /// line is the tolerance instead: `Higher` when the whole interval lies beyond it
    /// (farther from the reference than its refinements can be), else `Undecided`.
    pub fn sign(&self) -> Option<Sign> {
        let iv = self.interval.as_ref().ok()?;
        let zero = if self.distance { self.tolerance } else { 0.0 };
        if iv.within(self.tolerance) {
            None
        } else if iv.lo > zero {
            Some(Sign::Higher)
        } else if iv.hi < 0.0 {
            Some(Sign::Lower)
        } else {
            Some(Sign::Undecided)
        }
    }
}

/// A configuration judged against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Judgement {
    /// Number of paired seeds.
    pub k: usize,
    /// One comparison per observable, in the order of [`OBSERVABLES`].
    pub comparisons: Vec<Comparison>,
}

impl Judgement {
    /// Equivalent on every observable.
    pub fn equivalent(&self) -> bool {
        self.comparisons.iter().all(Comparison::equivalent)
    }

    /// The accuracy number: the worst observable's [`Comparison::ratio`] (1.0 = at the
    /// edge of what the reference itself can tell; infinite when an observable is not
    /// finite).
    pub fn accuracy(&self) -> f64 {
        self.comparisons
            .iter()
            .map(Comparison::ratio)
            .fold(0.0, f64::max)
    }

    /// The observables that are not equivalent: `key` and sign, e.g. `rim-
    /// groove_K+ settling?`, and for those without an interval `key!` with the reason
    /// in [`Judgement::reasons`]. Empty when equivalent.
    pub fn differs(&self) -> String {
        let mut out = Vec::new();
        for (c, o) in self.comparisons.iter().zip(OBSERVABLES.iter()) {
            if c.equivalent() {
                continue;
            }
            let mark = match c.sign() {
                Some(s) => s.symbol(),
                None => '!',
            };
            out.push(format!("{}{mark}", o.key));
        }
        out.join(" ")
    }

    /// Why observables could not be judged (a non-finite value, a non-finite
    /// tolerance), one sentence each; empty when every one was.
    pub fn reasons(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (c, o) in self.comparisons.iter().zip(OBSERVABLES.iter()) {
            match &c.interval {
                Err(StatsError::NonFinite { index }) => {
                    out.push(format!("{} is not finite on seed #{index}", o.key))
                }
                Err(e) => out.push(format!("{}: {e}", o.key)),
                Ok(_) if !c.tolerance.is_finite() => out.push(format!(
                    "{}: the reference's refinements give no finite tolerance",
                    o.key
                )),
                Ok(_) => {}
            }
        }
        out
    }
}

/// Judges a configuration's ensemble against the reference's on the same seeds, with
/// the given tolerances. O(K · observables).
///
/// Errors (usage errors): fewer than two seeds, or ensembles that do not pair. A
/// non-finite observable is not an error: its comparison carries
/// [`StatsError::NonFinite`] and the configuration is not equivalent.
pub fn judge(
    config: &[Outcome],
    reference: &[Outcome],
    tolerance: &[f64; COUNT],
) -> Result<Judgement, StatsError> {
    check_pairs(config, reference)?;
    let comparisons = (0..COUNT)
        .map(|j| Comparison {
            interval: paired_interval(&differences(config, reference, j)),
            tolerance: tolerance[j],
            distance: OBSERVABLES[j].distance,
        })
        .collect();
    Ok(Judgement {
        k: config.len(),
        comparisons,
    })
}

#[cfg(test)]
mod tests {
    use super::observables::{RIM, W1};
    use super::*;

    /// A synthetic outcome: every observable `base + j`, with `bump` added to one.
    fn outcome(base: f64, bump: Option<(usize, f64)>) -> Outcome {
        let mut o = [0.0; COUNT];
        for (j, v) in o.iter_mut().enumerate() {
            *v = base + j as f64;
        }
        o[W1] = 0.0;
        if let Some((j, d)) = bump {
            o[j] += d;
        }
        o
    }

    fn ensemble(noise: &[f64], bump: Option<(usize, f64)>) -> Vec<Outcome> {
        noise.iter().map(|&n| outcome(100.0 + n, bump)).collect()
    }

    const NOISE: [f64; 8] = [0.0, 1.0, -2.0, 3.0, 0.5, -1.5, 2.0, -0.5];

    #[test]
    fn the_reference_against_itself_is_equivalent_at_accuracy_zero() {
        let reference = ensemble(&NOISE, None);
        let tol = [1.0; COUNT];
        let j = judge(&reference, &reference, &tol).unwrap();
        assert!(j.equivalent());
        assert_eq!(j.accuracy(), 0.0);
        assert_eq!(j.differs(), "");
        assert!(j.reasons().is_empty());
        // Even with the smallest tolerances the refinements can give.
        let floor: [f64; COUNT] = std::array::from_fn(|j| OBSERVABLES[j].resolution);
        assert!(judge(&reference, &reference, &floor).unwrap().equivalent());
    }

    #[test]
    fn tolerances_come_from_the_refinements_interval_bounds() {
        let reference = ensemble(&NOISE, None);
        // Refinement 1: every count 0.5 higher on average, with noise ±1.
        let r1: Vec<Outcome> = reference
            .iter()
            .enumerate()
            .map(|(s, o)| {
                let mut o = *o;
                o[RIM] += 0.5 + if s % 2 == 0 { 1.0 } else { -1.0 };
                o
            })
            .collect();
        // Refinement 2: identical to the reference.
        let r2 = reference.clone();
        let tol = tolerances(&[&r1, &r2], &reference).unwrap();
        let iv = paired_interval(&differences(&r1, &reference, RIM)).unwrap();
        assert_eq!(tol[RIM], iv.bound().max(1.0));
        assert!(tol[RIM] > 1.0);
        // Elsewhere the resolution floor.
        assert_eq!(tol[W1], OBSERVABLES[W1].resolution);
        // The refinement itself is equivalent to the reference under this tolerance.
        assert!(judge(&r1, &reference, &tol).unwrap().comparisons[RIM].equivalent());
        // Bad input.
        assert!(tolerances(&[], &reference).is_err());
        assert_eq!(
            tolerances(&[&r1[..1]], &reference[..1]).unwrap_err(),
            StatsError::TooFewSamples { k: 1 }
        );
        assert!(tolerances(&[&r1[..3]], &reference).is_err());
        let mut nan = r1.clone();
        nan[3][RIM] = f64::NAN;
        let t = tolerances(&[&nan], &reference).unwrap();
        assert!(t[RIM].is_nan());
        let j = judge(&r1, &reference, &t).unwrap();
        assert!(!j.equivalent());
        assert!(
            j.reasons()[0].contains("no finite tolerance"),
            "{:?}",
            j.reasons()
        );
    }

    #[test]
    fn a_shift_is_named_with_its_sign() {
        let reference = ensemble(&NOISE, None);
        let tol = [1.0; COUNT];
        let fewer = ensemble(&NOISE, Some((RIM, -15.0)));
        let j = judge(&fewer, &reference, &tol).unwrap();
        assert!(!j.equivalent());
        assert_eq!(j.differs(), "rim-");
        assert_eq!(j.accuracy(), 15.0);
        let more = ensemble(&NOISE, Some((W1, 4.0)));
        assert_eq!(judge(&more, &reference, &tol).unwrap().differs(), "w1+");
        // A distance whose interval straddles the tolerance is undecided, although it
        // lies above 0 (every run but the reference's own is at a positive distance).
        let near: Vec<Outcome> = reference
            .iter()
            .enumerate()
            .map(|(s, o)| {
                let mut o = *o;
                o[W1] = 1.0 + 0.2 * NOISE[s];
                o
            })
            .collect();
        assert_eq!(judge(&near, &reference, &tol).unwrap().differs(), "w1?");
        // Noisy but centred: too wide to decide.
        let noisy: Vec<Outcome> = reference
            .iter()
            .enumerate()
            .map(|(s, o)| {
                let mut o = *o;
                o[RIM] += if s % 2 == 0 { 5.0 } else { -5.0 };
                o
            })
            .collect();
        let j = judge(&noisy, &reference, &tol).unwrap();
        assert_eq!(j.differs(), "rim?");
        assert_eq!(j.accuracy(), 0.0);
    }

    #[test]
    fn non_finite_observables_are_not_equivalent_with_the_reason() {
        let reference = ensemble(&NOISE, None);
        let mut escaped = reference.clone();
        escaped[5][W1] = f64::NAN;
        let j = judge(&escaped, &reference, &[1.0; COUNT]).unwrap();
        assert!(!j.equivalent());
        assert_eq!(j.accuracy(), f64::INFINITY);
        assert_eq!(j.differs(), "w1!");
        assert_eq!(j.reasons(), vec!["w1 is not finite on seed #5".to_string()]);
    }

    #[test]
    fn fewer_than_two_seeds_is_a_usage_error() {
        let one = ensemble(&[0.0], None);
        assert_eq!(
            judge(&one, &one, &[1.0; COUNT]).unwrap_err(),
            StatsError::TooFewSamples { k: 1 }
        );
        assert_eq!(
            judge(&[], &[], &[1.0; COUNT]).unwrap_err(),
            StatsError::TooFewSamples { k: 0 }
        );
        let two = ensemble(&[0.0, 1.0], None);
        assert!(judge(&two, &one, &[1.0; COUNT]).is_err());
    }
}
