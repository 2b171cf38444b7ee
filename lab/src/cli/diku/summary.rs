//! A configuration's runs (`Row`) summed up against the reference: the accuracy verdict,
//! the mean time, the speed-ups, the violations and its chart point.

use crate::accuracy::ensemble::{outcomes, SeedRun};
use crate::accuracy::observables::{Outcome, COUNT};
use crate::accuracy::{judge, Judgement};
use crate::measure::{self, RunSpec};
use crate::report::ChartPoint;

use super::kind_of;

/// A configuration with its runs on the first seeds.
pub(super) struct Row {
    pub(super) spec: RunSpec,
    pub(super) runs: Vec<SeedRun>,
    /// The trajectory deviation's floor on the configuration's own solver: its run on
    /// the first seed against the same run with every sphere moved by one ulp, in
    /// radii (measured for the reference and the reported configurations).
    pub(super) own_floor: Option<f64>,
}

/// A row summed up against the reference.
pub(super) struct Summary {
    pub(super) judgement: Result<Judgement, String>,
    pub(super) time_s: f64,
    pub(super) speedup_brute: f64,
    pub(super) speedup_stock: f64,
}

/// The mean of `xs`; NaN if empty.
pub(super) fn mean(xs: impl Iterator<Item = f64>) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for x in xs {
        s += x;
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        s / n as f64
    }
}

/// Mean time per run over the first `n` runs of the row named `name`.
fn mean_time(rows: &[Row], name: &str, n: usize) -> Option<f64> {
    let row = rows.iter().find(|r| r.spec.name == name)?;
    (row.runs.len() >= n).then(|| mean(row.runs[..n].iter().map(|r| r.result.time_s)))
}

/// `row` summed up against the reference outcomes and tolerances; the speed-ups
/// against brute force and stock Rapier on as many seeds as `row` has.
pub(super) fn summarize(
    rows: &[Row],
    row: &Row,
    reference: &[Outcome],
    tol: &[f64; COUNT],
) -> Summary {
    let n = row.runs.len();
    let time_s = mean(row.runs.iter().map(|r| r.result.time_s));
    let ratio = |name: &str| mean_time(rows, name, n).map_or(f64::NAN, |b| b / time_s);
    Summary {
        judgement: judge(
            &outcomes(&row.runs),
            &reference[..n.min(reference.len())],
            tol,
        )
        .map_err(|e| e.to_string()),
        time_s,
        speedup_brute: ratio("brute force"),
        speedup_stock: ratio("stock Rapier"),
    }
}

/// The accuracy number (the chart's x); infinite when not judged.
pub(super) fn accuracy_of(s: &Summary) -> f64 {
    s.judgement
        .as_ref()
        .map_or(f64::INFINITY, Judgement::accuracy)
}

/// The violations of all of a row's runs.
pub(super) fn violations_of(row: &Row) -> measure::Violations {
    let mut v = measure::Violations::default();
    for r in &row.runs {
        let w = r.result.violations;
        v.hanging += w.hanging;
        v.launch += w.launch;
        v.penetration += w.penetration;
        v.escape += w.escape;
    }
    v
}

/// A row's chart point: x the accuracy number, y the speed-up over brute force.
pub(super) fn point(row: &Row, s: &Summary) -> ChartPoint {
    ChartPoint {
        label: row.spec.name.clone(),
        deviation: accuracy_of(s),
        speedup: s.speedup_brute,
        violations: violations_of(row).total(),
        kind: kind_of(&row.spec),
    }
}
