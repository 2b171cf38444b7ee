//! The statistics of the paired seed ensembles: Student-t intervals of paired
//! differences, the equivalence decision against a tolerance, and the Wasserstein-1
//! distance of two one-dimensional samples.
//!
//! # Design
//! - **No statistics crate.** What is needed is one distribution's quantile (Student
//!   t, two-sided 95 %, 1–30 degrees of freedom in practice) and a sorted-merge
//!   distance. The quantile is computed from the regularised incomplete beta function
//!   (Lentz's continued fraction, as in *Numerical Recipes* §6.4) and inverted by
//!   bisection: exact to ~1e-10 for every degree of freedom, checked against tabled
//!   values in the tests. A crate (`statrs`) would bring `nalgebra` and `rand` for
//!   these thirty lines.
//! - **Errors, not panics.** Fewer than two paired samples cannot give an interval
//!   ([`StatsError::TooFewSamples`]: a usage error of the runner); a non-finite
//!   sample ([`StatsError::NonFinite`], e.g. an escaped body's position) is named with
//!   its index so that the caller can report the configuration as *not equivalent,
//!   because* rather than drop it.
//! - **Deterministic.** Plain `f64` arithmetic in a fixed order: the same samples give
//!   the same bits.

use std::fmt;

/// Why a statistic could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum StatsError {
    /// An interval needs at least two paired samples (seeds); `k` were given.
    TooFewSamples {
        /// The number of samples given.
        k: usize,
    },
    /// Sample `index` is NaN or infinite.
    NonFinite {
        /// Position of the first non-finite sample.
        index: usize,
    },
    /// A parameter out of its range (a probability outside (0, 1), zero degrees of
    /// freedom, an empty sample).
    InvalidParameter {
        /// What was wrong.
        reason: String,
    },
}

impl fmt::Display for StatsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StatsError::TooFewSamples { k } => {
                write!(f, "a paired interval needs at least 2 seeds, got {k}")
            }
            StatsError::NonFinite { index } => write!(f, "sample {index} is not finite"),
            StatsError::InvalidParameter { reason } => f.write_str(reason),
        }
    }
}

impl std::error::Error for StatsError {}

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, 9 terms; relative error ~1e-15).
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1 - x) = π / sin(πx).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The continued fraction of the incomplete beta function (modified Lentz).
fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let nonzero = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 / nonzero(1.0 - qab * x / qap);
    let mut h = d;
    // One Lentz step with coefficient `aa`: the factor it multiplies `h` by.
    let lentz = |aa: f64, c: &mut f64, d: &mut f64| {
        *d = 1.0 / nonzero(1.0 + aa * *d);
        *c = nonzero(1.0 + aa / *c);
        *d * *c
    };
    for m in 1..=300 {
        let m = m as f64;
        let m2 = 2.0 * m;
        h *= lentz(m * (b - m) * x / ((qam + m2) * (a + m2)), &mut c, &mut d);
        let del = lentz(
            -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2)),
            &mut c,
            &mut d,
        );
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// The regularised incomplete beta function `I_x(a, b)`, `0 <= x <= 1`.
fn inc_beta(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    let front = ln_front.exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_cf(a, b, x) / a
    } else {
        1.0 - front * beta_cf(b, a, 1.0 - x) / b
    }
}

/// The cumulative distribution function of Student's t with `df` degrees of freedom.
/// O(1) (a continued fraction of at most 300 terms).
pub fn t_cdf(t: f64, df: f64) -> f64 {
    if t.is_nan() || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    let tail = 0.5 * inc_beta(df / 2.0, 0.5, df / (df + t * t));
    if t >= 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The `p` quantile of Student's t with `df` degrees of freedom (e.g. `p = 0.975`,
/// `df = 7`: 2.3646). Bisection on [`t_cdf`] to 1e-12: about 100 evaluations.
///
/// Errors for `p` outside (0, 1) or `df` not finite and positive.
pub fn t_quantile(p: f64, df: f64) -> Result<f64, StatsError> {
    if !(p > 0.0 && p < 1.0) {
        return Err(StatsError::InvalidParameter {
            reason: format!("a quantile needs 0 < p < 1, got {p}"),
        });
    }
    if !(df.is_finite() && df > 0.0) {
        return Err(StatsError::InvalidParameter {
            reason: format!("degrees of freedom must be finite and positive, got {df}"),
        });
    }
    if p < 0.5 {
        return t_quantile(1.0 - p, df).map(|q| -q);
    }
    let mut hi = 1.0;
    while t_cdf(hi, df) < p && hi < 1e12 {
        hi *= 2.0;
    }
    let mut lo = 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if t_cdf(mid, df) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-12 * hi.max(1.0) {
            break;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// A two-sided confidence interval of a mean from `k` paired differences.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Number of paired samples (seeds).
    pub k: usize,
    /// Mean of the differences.
    pub mean: f64,
    /// Sample standard deviation of the differences (`k - 1` in the denominator).
    pub sd: f64,
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
}

impl Interval {
    /// The larger of `|lo|` and `|hi|`: the largest difference the interval admits.
    pub fn bound(&self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }

    /// Whether the interval lies inside `[-tolerance, tolerance]` (the equivalence
    /// decision of a two one-sided tests procedure at the interval's level). False
    /// for a non-finite or negative tolerance.
    pub fn within(&self, tolerance: f64) -> bool {
        tolerance.is_finite() && tolerance >= 0.0 && self.lo >= -tolerance && self.hi <= tolerance
    }
}

/// Widens a tolerance to one refinement's paired differences from the reference:
/// the larger of `t` and the far end of their 95 % interval; NaN when a difference
/// is not finite (nothing is then equivalent on it). O(K).
pub fn widen_tolerance(t: &mut f64, differences: &[f64]) -> Result<(), StatsError> {
    match paired_interval(differences) {
        Ok(iv) => *t = t.max(iv.bound()),
        Err(StatsError::NonFinite { .. }) => *t = f64::NAN,
        Err(e) => return Err(e),
    }
    Ok(())
}

/// The 95 % Student-t interval of the mean of paired differences `d` (one per seed):
/// `mean ± t(0.975, k - 1) · sd / √k`. O(k).
///
/// Errors: fewer than two samples ([`StatsError::TooFewSamples`]); a non-finite
/// sample ([`StatsError::NonFinite`], the first one's index).
pub fn paired_interval(d: &[f64]) -> Result<Interval, StatsError> {
    interval_at(d, 0.95)
}

/// [`paired_interval`] at another two-sided `level` in (0, 1).
pub fn interval_at(d: &[f64], level: f64) -> Result<Interval, StatsError> {
    let k = d.len();
    if k < 2 {
        return Err(StatsError::TooFewSamples { k });
    }
    if let Some(index) = d.iter().position(|x| !x.is_finite()) {
        return Err(StatsError::NonFinite { index });
    }
    if !(level > 0.0 && level < 1.0) {
        return Err(StatsError::InvalidParameter {
            reason: format!("a confidence level must be in (0, 1), got {level}"),
        });
    }
    let n = k as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    let sd = var.sqrt();
    let t = t_quantile(0.5 + level / 2.0, n - 1.0)?;
    let half = t * sd / n.sqrt();
    Ok(Interval {
        k,
        mean,
        sd,
        lo: mean - half,
        hi: mean + half,
    })
}

/// The Wasserstein-1 (earth mover's) distance of two one-dimensional empirical
/// distributions, each sample weighted equally: `∫ |F_a(x) - F_b(x)| dx`, in the
/// samples' unit. The samples may differ in size. O((n + m) log(n + m)).
///
/// Errors: an empty sample, or a non-finite value (its index in `a`, then in `b`
/// counted after `a`).
pub fn wasserstein1(a: &[f64], b: &[f64]) -> Result<f64, StatsError> {
    if a.is_empty() || b.is_empty() {
        return Err(StatsError::InvalidParameter {
            reason: "Wasserstein distance of an empty sample".into(),
        });
    }
    if let Some(index) = a.iter().chain(b).position(|x| !x.is_finite()) {
        return Err(StatsError::NonFinite { index });
    }
    let mut xa = a.to_vec();
    let mut xb = b.to_vec();
    xa.sort_by(f64::total_cmp);
    xb.sort_by(f64::total_cmp);
    let (na, nb) = (xa.len() as f64, xb.len() as f64);
    let (mut i, mut j) = (0usize, 0usize);
    let mut total = 0.0;
    let mut x = xa[0].min(xb[0]);
    // Walk the merged sample: between consecutive points both CDFs are constant.
    while i < xa.len() || j < xb.len() {
        let next = match (xa.get(i), xb.get(j)) {
            (Some(&p), Some(&q)) => p.min(q),
            (Some(&p), None) => p,
            (None, Some(&q)) => q,
            (None, None) => break,
        };
        let fa = i as f64 / na;
        let fb = j as f64 / nb;
        total += (fa - fb).abs() * (next - x);
        x = next;
        while i < xa.len() && xa[i] == x {
            i += 1;
        }
        while j < xb.len() && xb[j] == x {
            j += 1;
        }
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// splitmix64: a deterministic generator for the synthetic samples.
    struct Rng(u64);

    impl Rng {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        /// Uniform in (0, 1).
        fn uniform(&mut self) -> f64 {
            ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
        /// Standard normal (Box–Muller).
        fn normal(&mut self) -> f64 {
            let (u, v) = (self.uniform(), self.uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        }
    }

    #[test]
    fn t_quantiles_match_the_tables() {
        // Two-sided 95 % critical values (e.g. Abramowitz & Stegun, Table 26.10).
        for (df, want) in [
            (1.0, 12.7062),
            (2.0, 4.3027),
            (3.0, 3.1824),
            (7.0, 2.3646),
            (9.0, 2.2622),
            (30.0, 2.0423),
            (1e6, 1.9600),
        ] {
            let q = t_quantile(0.975, df).unwrap();
            assert!((q - want).abs() < 1e-4, "df {df}: {q}");
        }
        assert!((t_quantile(0.025, 7.0).unwrap() + 2.3646).abs() < 1e-4);
        assert!(t_quantile(0.5, 3.0).unwrap().abs() < 1e-9);
        assert!((t_cdf(0.0, 5.0) - 0.5).abs() < 1e-15);
        for bad in [0.0, 1.0, f64::NAN, -0.1] {
            assert!(t_quantile(bad, 3.0).is_err());
        }
        assert!(t_quantile(0.9, 0.0).is_err());
        assert!(t_quantile(0.9, f64::INFINITY).is_err());
    }

    #[test]
    fn intervals_of_known_samples() {
        let iv = paired_interval(&[1.0, 2.0, 3.0, 4.0]).unwrap();
        assert_eq!((iv.k, iv.mean), (4, 2.5));
        let sd = (5.0f64 / 3.0).sqrt();
        assert!((iv.sd - sd).abs() < 1e-12);
        let half = 3.182_446_305 * sd / 2.0;
        assert!((iv.lo - (2.5 - half)).abs() < 1e-6 && (iv.hi - (2.5 + half)).abs() < 1e-6);
        // Identical samples: a zero-width interval at the value.
        let z = paired_interval(&[0.0; 8]).unwrap();
        assert_eq!((z.lo, z.hi, z.bound()), (0.0, 0.0, 0.0));
        assert!(z.within(0.0) && z.within(1.0));
    }

    #[test]
    fn too_few_seeds_and_non_finite_samples_are_errors() {
        assert_eq!(
            paired_interval(&[]).unwrap_err(),
            StatsError::TooFewSamples { k: 0 }
        );
        assert_eq!(
            paired_interval(&[1.0]).unwrap_err(),
            StatsError::TooFewSamples { k: 1 }
        );
        assert_eq!(
            paired_interval(&[1.0, f64::NAN, 2.0]).unwrap_err(),
            StatsError::NonFinite { index: 1 }
        );
        assert_eq!(
            paired_interval(&[f64::INFINITY, 1.0]).unwrap_err(),
            StatsError::NonFinite { index: 0 }
        );
        assert!(interval_at(&[1.0, 2.0], 1.0).is_err());
        assert!(StatsError::TooFewSamples { k: 1 }
            .to_string()
            .contains("at least 2"));
    }

    #[test]
    fn equivalence_decisions() {
        let iv = |lo, hi| Interval {
            k: 8,
            mean: (lo + hi) / 2.0,
            sd: 1.0,
            lo,
            hi,
        };
        assert!(iv(-0.5, 0.5).within(1.0));
        assert!(iv(-1.0, 1.0).within(1.0), "the edge is inside");
        assert!(!iv(-0.5, 1.5).within(1.0), "upper end outside");
        assert!(!iv(-1.5, 0.5).within(1.0), "lower end outside");
        assert!(!iv(2.0, 3.0).within(1.0), "clearly different");
        assert!(!iv(-0.5, 0.5).within(f64::NAN));
        assert!(!iv(-0.5, 0.5).within(f64::INFINITY));
        assert!(!iv(-0.5, 0.5).within(-1.0));
        assert_eq!(iv(-3.0, 1.0).bound(), 3.0);
    }

    #[test]
    fn intervals_cover_the_true_mean_95_percent_of_the_time() {
        // 4,000 synthetic ensembles of K = 8 normal differences with mean 0.3 and
        // sd 2: the 95 % interval must cover 0.3 in 95 % ± 1.1 % (3 standard errors)
        // of them. The same at K = 3, where a normal quantile would under-cover.
        for k in [3usize, 8] {
            let mut rng = Rng(17 + k as u64);
            let trials = 4000;
            let mut covered = 0;
            for _ in 0..trials {
                let d: Vec<f64> = (0..k).map(|_| 0.3 + 2.0 * rng.normal()).collect();
                let iv = paired_interval(&d).unwrap();
                covered += usize::from(iv.lo <= 0.3 && 0.3 <= iv.hi);
            }
            let rate = covered as f64 / trials as f64;
            assert!((rate - 0.95).abs() < 0.011, "K = {k}: coverage {rate}");
        }
    }

    #[test]
    fn equivalence_rejects_a_shift_beyond_the_tolerance_and_accepts_none() {
        // Deterministic synthetic ensembles (K = 8, sd 0.1): no shift is judged
        // equivalent within 0.5 nearly always; a shift of 1.0 never.
        let mut rng = Rng(5);
        let (mut same, mut shifted) = (0, 0);
        for _ in 0..500 {
            let d: Vec<f64> = (0..8).map(|_| 0.1 * rng.normal()).collect();
            same += usize::from(paired_interval(&d).unwrap().within(0.5));
            let e: Vec<f64> = (0..8).map(|_| 1.0 + 0.1 * rng.normal()).collect();
            shifted += usize::from(paired_interval(&e).unwrap().within(0.5));
        }
        assert_eq!((same, shifted), (500, 0));
    }

    #[test]
    fn wasserstein_of_known_distributions() {
        let a: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        // A shifted sample: the distance is the shift.
        let b: Vec<f64> = a.iter().map(|x| x + 0.7).collect();
        assert!((wasserstein1(&a, &b).unwrap() - 0.7).abs() < 1e-9);
        assert!((wasserstein1(&b, &a).unwrap() - 0.7).abs() < 1e-9);
        // Identical (in any order): zero.
        let mut r = a.clone();
        r.reverse();
        assert_eq!(wasserstein1(&a, &r).unwrap(), 0.0);
        // Point masses: |x - y|; different sizes: {0, 1} against {0.5} is 0.5.
        assert_eq!(wasserstein1(&[2.0], &[5.0]).unwrap(), 3.0);
        assert_eq!(wasserstein1(&[0.0, 1.0], &[0.5]).unwrap(), 0.5);
        // Half the mass moved by 2: distance 1.
        assert_eq!(wasserstein1(&[0.0, 0.0], &[0.0, 2.0]).unwrap(), 1.0);
        // Two large samples of U(0, 1) and U(0, 2): W1 = ∫|x - x/2|... = 0.5.
        let mut rng = Rng(3);
        let u: Vec<f64> = (0..20_000).map(|_| rng.uniform()).collect();
        let v: Vec<f64> = (0..20_000).map(|_| 2.0 * rng.uniform()).collect();
        assert!((wasserstein1(&u, &v).unwrap() - 0.5).abs() < 0.02);
        assert!(wasserstein1(&[], &[1.0]).is_err());
        assert_eq!(
            wasserstein1(&[1.0], &[2.0, f64::NAN]).unwrap_err(),
            StatsError::NonFinite { index: 2 }
        );
    }
}
