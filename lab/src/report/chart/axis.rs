//! The axes: ranges from the data (padded, widened when degenerate, cut at
//! [`LIMIT`](super::palette::LIMIT)), "nice" ticks (1-2-5 steps; decades on a log axis)
//! with their labels, and the plotters coordinate over them. A log axis is a linear axis
//! over log₁₀ of the values, its ticks at the logs of 1-2-5 values and labelled with the
//! values: the tick choice stays ours (plotters' own log key points are sparse on short
//! ranges) and both axes have one coordinate type.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, ValueFormatter};
use plotters::prelude::*;

use super::palette::LIMIT;
use crate::report::ChartPoint;

/// The chart's two axes.
pub(super) struct Axes {
    pub(super) x: Axis,
    pub(super) y: Axis,
}

impl Axes {
    /// Axis ranges and ticks for the visible points, about one labelled tick per 110 px
    /// across and per 70 px up; the equivalence band's edge `band` stays in view.
    pub(super) fn new(
        points: &[ChartPoint],
        visible: &[usize],
        log_y: bool,
        band: Option<f64>,
        w: f64,
        h: f64,
    ) -> Axes {
        let min_max = |f: &dyn Fn(&ChartPoint) -> f64| {
            visible
                .iter()
                .map(|&i| f(&points[i]))
                .fold(None, |acc: Option<(f64, f64)>, v| {
                    Some(acc.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
                })
        };
        let x_target = ((w - 160.0) / 110.0).round().clamp(2.0, 12.0) as usize;
        let y_target = ((h - 140.0) / 70.0).round().clamp(2.0, 10.0) as usize;
        // Deviation and (on a linear axis) speed-up include 0. Ranges beyond ±1e150 (or
        // 1e±150 on the log axis) are cut there, so that the padding and tick arithmetic
        // cannot overflow; points beyond sit on the frame.
        let (x_lo, x_hi) = min_max(&|p| p.deviation.clamp(-LIMIT, LIMIT)).unwrap_or((0.0, 1.0));
        // The band's edge stays in view, with a little room beyond it.
        let x_hi = band.map_or(x_hi, |b| x_hi.max(b * 1.15));
        let x = Axis::linear(x_lo.min(0.0), x_hi.max(0.0), x_target);
        let y = if log_y {
            let (lo, hi) = min_max(&|p| p.speedup.clamp(1.0 / LIMIT, LIMIT)).unwrap_or((1.0, 10.0));
            Axis::log(lo, hi, y_target)
        } else {
            let (lo, hi) = min_max(&|p| p.speedup.clamp(-LIMIT, LIMIT)).unwrap_or((0.0, 1.0));
            Axis::linear(lo.min(0.0), hi.max(0.0), y_target)
        };
        Axes { x, y }
    }

    /// Point `p` in drawing space, pinned to the axes' ends.
    pub(super) fn at(&self, p: &ChartPoint) -> (f64, f64) {
        (self.x.place(p.deviation), self.y.place(p.speedup))
    }
}

/// An axis: data domain, mapping and ticks.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    /// Labelled ticks.
    major: Vec<f64>,
    /// Unlabelled grid lines.
    minor: Vec<f64>,
    pub(super) labels: Vec<String>,
}

impl Axis {
    /// A linear axis over `[lo, hi]` (padded by 4% each side), about `target` ticks.
    fn linear(lo: f64, hi: f64, target: usize) -> Axis {
        let (lo, hi) = widen(lo, hi);
        let pad = (hi - lo) * 0.04;
        let (lo, hi) = (lo - pad, hi + pad);
        let (major, decimals) = nice_ticks(lo, hi, target);
        let labels = major.iter().map(|&v| tick_label(v, decimals)).collect();
        Axis {
            lo,
            hi,
            log: false,
            major,
            minor: Vec::new(),
            labels,
        }
    }

    /// A log₁₀ axis over positive `[lo, hi]` (padded by 5% of the decades each side).
    fn log(lo: f64, hi: f64, target: usize) -> Axis {
        let (mut a, mut b) = (lo.log10(), hi.log10());
        if b - a < 0.3 {
            let mid = 0.5 * (a + b);
            (a, b) = (mid - 0.15, mid + 0.15);
        }
        let pad = (b - a) * 0.05;
        let (lo, hi) = (10f64.powf(a - pad), 10f64.powf(b + pad));
        let (major, minor, labels) = log_ticks(lo, hi, target);
        Axis {
            lo,
            hi,
            log: true,
            major,
            minor,
            labels,
        }
    }

    /// `v` in the axis' drawing space: itself, or its log₁₀ on a log axis.
    fn to_space(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// The ends in drawing space.
    pub(super) fn span(&self) -> (f64, f64) {
        (self.to_space(self.lo), self.to_space(self.hi))
    }

    /// `v` in drawing space, pinned to the ends (values beyond the axis sit on the
    /// frame).
    pub(super) fn place(&self, v: f64) -> f64 {
        let (a, b) = self.span();
        self.to_space(v).clamp(a.min(b), a.max(b))
    }

    /// The label of the tick at `v` (drawing space; plotters hands back the key points
    /// it was given), or the nearest tick's.
    fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .zip(&self.labels)
            .min_by(|a, b| {
                (self.to_space(*a.0) - v)
                    .abs()
                    .total_cmp(&(self.to_space(*b.0) - v).abs())
            })
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    }
}

/// An axis is a plotters coordinate over its drawing space: the labelled ticks are its
/// bold key points, the unlabelled ones its light (grid-only) points.
impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        // As plotters' own f64 coordinate, with non-finite fractions pinned.
        let (a, b) = self.span();
        let fraction = (v - a) / (b - a);
        let length = limit.1 - limit.0;
        if !fraction.is_finite() || length == 0 {
            return if fraction.is_sign_negative() {
                limit.0
            } else {
                limit.1
            };
        }
        limit.0 + (f64::from(length) * fraction + 1e-3).floor() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let points = if hint.weight().allow_light_points() {
            &self.minor
        } else {
            &self.major
        };
        points.iter().map(|&v| self.to_space(v)).collect()
    }

    fn range(&self) -> std::ops::Range<f64> {
        let (a, b) = self.span();
        a..b
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(v: &f64) -> String {
        format!("{v}")
    }

    fn format_ext(&self, v: &f64) -> String {
        self.label(*v)
    }
}

/// A non-degenerate range: an empty span is widened around its value.
fn widen(lo: f64, hi: f64) -> (f64, f64) {
    if hi - lo > 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        (lo, hi)
    } else if lo == 0.0 {
        (0.0, 1.0)
    } else {
        let d = lo.abs() * 0.5;
        if d.is_normal() && (lo - d) < lo && (hi + d) > hi {
            (lo - d, hi + d)
        } else {
            // A subnormal range (or one the half-width cannot widen): a unit around it.
            (lo - 0.5, hi + 0.5)
        }
    }
}

/// The power-of-ten exponent of a 1-2-5 step.
fn step_exponent(step: f64) -> i32 {
    (step.log10() + 1e-9).floor() as i32
}

/// Ticks at multiples of a 1-2-5 step inside `[lo, hi]`, about `target` of them, and
/// the number of decimals their labels need.
fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, usize) {
    let raw = (hi - lo) / target.max(2) as f64;
    let base = 10f64.powf(raw.log10().floor());
    // The 1-2-5 step nearest to the raw step (by ratio).
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .min_by(|a, b| (a / raw).ln().abs().total_cmp(&(b / raw).ln().abs()))
        .unwrap_or(base);
    let first = (lo / step).ceil();
    let last = (hi / step + 1e-9).floor();
    // A degenerate step (an underflowed range) gives the two ends only.
    if !(step.is_normal() && first.is_finite() && last.is_finite() && last - first < 10_000.0) {
        return (vec![lo, hi], 3);
    }
    let (first, last) = (first as i64, last as i64);
    let ticks = (first..=last)
        .map(|k| if k == 0 { 0.0 } else { k as f64 * step })
        .collect();
    (ticks, (-step_exponent(step)).max(0) as usize)
}

/// Log-axis ticks: decades if they give at least three, else 1-2-5 per decade, else
/// 1..9 per decade, else (a range narrower than about a factor 2) linear ticks.
/// Returns (labelled, grid-only, labels).
fn log_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, Vec<f64>, Vec<String>) {
    let in_range = |v: f64| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let decade_step = ((k1 - k0) as usize).div_ceil(target.max(1) * 3 / 2).max(1);
    let with = |mantissas: &[u32], every: usize| -> Vec<(u32, i32)> {
        (k0..=k1)
            .filter(|k| (k - k0) as usize % every == 0)
            .flat_map(|k| mantissas.iter().map(move |&m| (m, k)))
            .filter(|&(m, k)| in_range(f64::from(m) * 10f64.powi(k)))
            .collect()
    };
    let all: Vec<u32> = (1..=9).collect();
    for set in [&[1][..], &[1, 2, 5][..], &all[..]] {
        let every = if set.len() == 1 { decade_step } else { 1 };
        let major = with(set, every);
        if major.len() >= 3 {
            let minor = if set.len() == 9 || (k1 - k0) > 8 {
                Vec::new()
            } else {
                with(&all, 1)
                    .into_iter()
                    .filter(|t| !major.contains(t))
                    .collect()
            };
            let value = |&(m, k): &(u32, i32)| f64::from(m) * 10f64.powi(k);
            let labels = major.iter().map(|&(m, k)| fmt_power(m, k)).collect();
            return (
                major.iter().map(value).collect(),
                minor.iter().map(value).collect(),
                labels,
            );
        }
    }
    let (ticks, decimals) = nice_ticks(lo, hi, target);
    let ticks: Vec<f64> = ticks.into_iter().filter(|&v| v > 0.0).collect();
    let labels = ticks.iter().map(|&v| tick_label(v, decimals)).collect();
    (ticks, Vec::new(), labels)
}

/// A linear tick's label: fixed-point, or scientific when that would be long.
fn tick_label(v: f64, decimals: usize) -> String {
    if decimals > 6 || v.abs() >= 1e7 {
        if v == 0.0 {
            "0".to_string()
        } else {
            format!("{v:.2e}")
        }
    } else {
        fmt_fixed(v, decimals)
    }
}

/// `v` with `decimals` decimals, never "-0".
fn fmt_fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// `m × 10^k` as a plain number, or as `me k` when that would be long.
fn fmt_power(m: u32, k: i32) -> String {
    if (-4..=5).contains(&k) {
        fmt_fixed(f64::from(m) * 10f64.powi(k), (-k).max(0) as usize)
    } else {
        format!("{m}e{k}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ticks_use_1_2_5_steps() {
        let (t, d) = nice_ticks(0.0, 1.0, 5);
        assert_eq!(t, vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert_eq!(d, 1);
        let (t, d) = nice_ticks(-0.04, 2.3, 6);
        let labels: Vec<String> = t.iter().map(|&v| fmt_fixed(v, d)).collect();
        assert_eq!(labels, ["0.0", "0.5", "1.0", "1.5", "2.0"]);
        let (t, d) = nice_ticks(-3.0, 1200.0, 5);
        assert_eq!((t[0], t.len(), d), (0.0, 7, 0));
    }

    #[test]
    fn log_ticks_pick_decades_or_finer() {
        let (major, minor, labels) = log_ticks(0.2, 50.0, 6);
        assert_eq!(labels, ["0.2", "0.5", "1", "2", "5", "10", "20", "50"]);
        assert_eq!(major.len(), 8);
        assert!(!minor.is_empty());
        let (_, _, labels) = log_ticks(0.05, 2000.0, 6);
        assert_eq!(labels, ["0.1", "1", "10", "100", "1000"]);
        let (_, _, labels) = log_ticks(1.1, 1.9, 6);
        assert!(labels.len() >= 2, "{labels:?}");
        assert_eq!(fmt_power(1, 7), "1e7");
        assert_eq!(tick_label(2e150, 0), "2.00e150");
        assert_eq!(tick_label(3e-9, 9), "3.00e-9");
        assert_eq!(tick_label(0.0, 9), "0");
        assert_eq!(fmt_fixed(-0.0001, 2), "0.00");
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(widen(0.0, 0.0), (0.0, 1.0));
        assert_eq!(widen(2.0, 2.0), (1.0, 3.0));
        let a = Axis::log(3.0, 3.0, 6);
        assert!(a.lo < 3.0 && a.hi > 3.0 && a.major.len() >= 2);
        // Drawn in log space, labelled with the values.
        let (lo, hi) = a.span();
        assert!(a.place(3.0) > lo && a.place(3.0) < hi);
        assert_eq!(a.place(1e9), hi);
        assert_eq!(a.label(a.to_space(a.major[0])), a.labels[0]);
        assert_eq!(a.range(), lo..hi);
        assert_eq!(a.map(&lo, (10, 110)), 10);
        assert_eq!(a.map(&hi, (10, 110)), 110);
    }
}
