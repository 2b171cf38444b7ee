//! The files `results.csv` (one row per configuration) and `runs.csv` (one row per run):
//! their columns and their rows.

use std::path::Path;

use crate::accuracy::ensemble::SeedRun;
use crate::accuracy::observables::{Outcome, COUNT, OBSERVABLES};

use super::kind_of;
use super::summary::{accuracy_of, mean, violations_of, Row, Summary};

/// The columns of `results.csv` before the per-observable ones.
pub const CSV_HEADER: [&str; 30] = [
    "configuration",
    "kind",
    "cache",
    "tweak",
    "reduce",
    "zero",
    "damp",
    "subgroup",
    "fixate",
    "seeds",
    "time_s",
    "speedup_brute",
    "speedup_stock",
    "accuracy",
    "equivalent",
    "differs",
    "not_judged",
    "deviation_radii",
    "own_ulp_floor_radii",
    "violations",
    "hanging",
    "launch",
    "penetration",
    "escape",
    "peak_penetration_mm",
    "resting_penetration_mm",
    "mean_groups",
    "mean_awake",
    "last_second_s",
    "left_plane",
];

/// Per observable, the columns of `results.csv` after [`CSV_HEADER`]: the reference's
/// mean over the row's seeds, the paired mean difference, its 95 % interval and the
/// tolerance, each `KEY_` prefixed (e.g. `rim_ref, rim_diff, rim_lo, rim_hi,
/// rim_tol`).
pub fn observable_columns() -> Vec<String> {
    OBSERVABLES
        .iter()
        .flat_map(|o| ["ref", "diff", "lo", "hi", "tol"].map(|s| format!("{}_{s}", o.key)))
        .collect()
}

/// The columns of `runs.csv` before the observables (one column per observable key).
pub const RUNS_CSV_HEADER: [&str; 8] = [
    "configuration",
    "seed",
    "time_s",
    "deviation_radii",
    "violations",
    "peak_penetration_mm",
    "resting_penetration_mm",
    "left_plane",
];

/// `results.csv` and `runs.csv` into `out` (created if missing).
pub(super) fn write_results(
    out: &Path,
    rows: &[Row],
    summaries: &[Summary],
    reference: &[Outcome],
    tol: &[f64; COUNT],
) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let table = rows
        .iter()
        .zip(summaries)
        .map(|(row, s)| results_row(row, s, reference, tol));
    let mut header: Vec<String> = CSV_HEADER.iter().map(|s| s.to_string()).collect();
    header.extend(observable_columns());
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    super::super::write_csv(&out.join("results.csv"), &header, table)?;

    let per_run = rows
        .iter()
        .flat_map(|row| row.runs.iter().map(move |r| runs_row(row, r)));
    let mut header: Vec<&str> = RUNS_CSV_HEADER.to_vec();
    header.extend(OBSERVABLES.iter().map(|o| o.key));
    super::super::write_csv(&out.join("runs.csv"), &header, per_run)
}

/// A number with 6 decimals.
fn f(x: f64) -> String {
    format!("{x:.6}")
}

/// A configuration's row of `results.csv`: [`CSV_HEADER`], then
/// [`observable_columns`].
fn results_row(row: &Row, s: &Summary, reference: &[Outcome], tol: &[f64; COUNT]) -> Vec<String> {
    let n = row.runs.len();
    let v = violations_of(row);
    let runs = &row.runs;
    let mut out = vec![row.spec.name.clone(), format!("{:?}", kind_of(&row.spec))];
    out.extend(super::super::switch_fields(&row.spec));
    let (equivalent, differs, reasons) = match &s.judgement {
        Ok(j) => (
            u8::from(j.equivalent()).to_string(),
            j.differs(),
            j.reasons().join("; "),
        ),
        Err(e) => (String::new(), String::new(), e.clone()),
    };
    out.extend([
        n.to_string(),
        f(s.time_s),
        format!("{:.4}", s.speedup_brute),
        format!("{:.4}", s.speedup_stock),
        f(accuracy_of(s)),
        equivalent,
        differs,
        reasons,
        f(mean(runs.iter().map(|r| r.result.deviation))),
        row.own_floor.map(f).unwrap_or_default(),
        v.total().to_string(),
        v.hanging.to_string(),
        v.launch.to_string(),
        v.penetration.to_string(),
        v.escape.to_string(),
        f(runs
            .iter()
            .map(|r| r.plausibility.peak_penetration_mm)
            .fold(0.0, f64::max)),
        f(mean(
            runs.iter().map(|r| r.plausibility.resting_penetration_mm),
        )),
        format!("{:.3}", mean(runs.iter().map(|r| r.result.mean_groups))),
        format!("{:.3}", mean(runs.iter().map(|r| r.result.mean_awake))),
        f(mean(runs.iter().map(|r| r.result.tail_time_s))),
        runs.iter()
            .map(|r| r.result.left_region)
            .max()
            .unwrap_or(0)
            .to_string(),
    ]);
    out.extend(observable_fields(n, s, reference, tol));
    out
}

/// Per observable: the reference's mean over the first `n` seeds, the paired mean
/// difference, its 95 % interval and the tolerance ("NaN" where not judged).
fn observable_fields(
    n: usize,
    s: &Summary,
    reference: &[Outcome],
    tol: &[f64; COUNT],
) -> Vec<String> {
    let mut out = Vec::with_capacity(5 * COUNT);
    for (j, t) in tol.iter().enumerate() {
        let comparison = s.judgement.as_ref().ok().map(|x| &x.comparisons[j]);
        let iv = comparison.and_then(|c| c.interval.as_ref().ok());
        out.extend([
            f(mean(
                reference[..n.min(reference.len())].iter().map(|r| r[j]),
            )),
            iv.map_or("NaN".into(), |iv| f(iv.mean)),
            iv.map_or("NaN".into(), |iv| f(iv.lo)),
            iv.map_or("NaN".into(), |iv| f(iv.hi)),
            f(*t),
        ]);
    }
    out
}

/// A run's row of `runs.csv`: [`RUNS_CSV_HEADER`], then one column per observable.
fn runs_row(row: &Row, r: &SeedRun) -> Vec<String> {
    let mut out = vec![
        row.spec.name.clone(),
        r.seed.to_string(),
        f(r.result.time_s),
        f(r.result.deviation),
        r.result.violations.total().to_string(),
        f(r.plausibility.peak_penetration_mm),
        f(r.plausibility.resting_penetration_mm),
        r.result.left_region.to_string(),
    ];
    out.extend(r.outcome.iter().map(|&x| f(x)));
    out
}
