//! The printed report of `rcg-lab diku`: the tolerances, the table (one line per
//! configuration), the Pareto front and the equivalent configurations.

use crate::accuracy::ensemble::outcomes;
use crate::accuracy::observables::{Outcome, COUNT, OBSERVABLES};
use crate::accuracy::{judge, Judgement};
use crate::measure::Mode;
use crate::report::{self, ChartPoint};

use super::summary::{accuracy_of, mean, violations_of, Row, Summary};

/// The tolerance of every observable, with the refinements' intervals it comes from.
pub(super) fn print_tolerances(reference_rows: &[Row], reference: &[Outcome], tol: &[f64; COUNT]) {
    println!(
        "\nTolerances from the reference's own discretisation error ({} seeds; the larger \
         |end| of the two refinements' 95% intervals, at least the resolution):",
        reference.len()
    );
    println!(
        "{:<12} {:>8} {:>10} {:>24} {:>24} {:>9}",
        "observable",
        "unit",
        "reference",
        "2x iterations: diff [95%]",
        "half dt: diff [95%]",
        "tolerance"
    );
    let judged: Vec<Option<Judgement>> = reference_rows[1..]
        .iter()
        .map(|r| judge(&outcomes(&r.runs), reference, tol).ok())
        .collect();
    for (j, o) in OBSERVABLES.iter().enumerate() {
        let cell = |x: &Option<Judgement>| match x.as_ref().map(|x| &x.comparisons[j].interval) {
            Some(Ok(iv)) => format!("{:+.3} [{:+.3}, {:+.3}]", iv.mean, iv.lo, iv.hi),
            Some(Err(e)) => e.to_string(),
            None => "—".into(),
        };
        println!(
            "{:<12} {:>8} {:>10.3} {:>24} {:>24} {:>9.3}",
            o.key,
            o.unit,
            mean(reference.iter().map(|r| r[j])),
            cell(&judged[0]),
            cell(&judged[1]),
            tol[j]
        );
    }
}

/// The printed table: one line per configuration.
pub(super) fn print_table(rows: &[Row], summaries: &[Summary], ulp_floor: f64, seed_floor: f64) {
    println!(
        "\n{:<26} {:>2} {:>6} {:>6} {:>8} {:>5} {:>4} {:>7} {:>7} {:>7} {:>9}  differs (sign: +/- higher/lower, ? undecided, ! not finite)",
        "configuration", "K", "xbrute", "xstock", "accuracy", "equiv", "viol", "peak mm", "rest mm", "dev (r)", "floor (r)"
    );
    for (row, s) in rows.iter().zip(summaries) {
        let v = violations_of(row).total();
        let (equiv, differs) = match &s.judgement {
            Ok(j) => (if j.equivalent() { "yes" } else { "no" }, j.differs()),
            Err(e) => ("—", e.clone()),
        };
        let floor = row
            .own_floor
            .map_or_else(|| "-".to_string(), |x| format!("{x:.2}"));
        println!(
            "{:<26} {:>2} {:>6.2} {:>6.2} {:>8.2} {:>5} {:>4} {:>7.1} {:>7.2} {:>7.2} {floor:>9}  {differs}",
            row.spec.name,
            row.runs.len(),
            s.speedup_brute,
            s.speedup_stock,
            accuracy_of(s),
            equiv,
            v,
            row.runs
                .iter()
                .map(|r| r.plausibility.peak_penetration_mm)
                .fold(0.0, f64::max),
            mean(
                row.runs
                    .iter()
                    .map(|r| r.plausibility.resting_penetration_mm)
            ),
            mean(row.runs.iter().map(|r| r.result.deviation)),
        );
        if let Ok(j) = &s.judgement {
            for reason in j.reasons() {
                println!("{:<26}    not judged: {reason}", "");
            }
        }
    }
    println!(
        "\ndev (r): the old trajectory deviation against the same-seed reference (mean over \
         the seeds), beside its floors: the reference against itself with every sphere moved \
         by one ulp {ulp_floor:.2} r, against another seed {seed_floor:.2} r. floor (r): the \
         configuration against itself with every sphere moved by one ulp (first seed), the \
         chaos floor of its own solver; a dev (r) within it says nothing."
    );
}

/// The Pareto front and the equivalent configurations.
pub(super) fn print_front(rows: &[Row], summaries: &[Summary], points: &[ChartPoint]) {
    let front = report::pareto_front(points, true);
    println!("\nPareto front (zero violations), by accuracy:");
    for i in front {
        println!(
            "  {:<26} accuracy {:>7.2}, speed-up {:>5.2}x brute force, {} seeds",
            points[i].label,
            points[i].deviation,
            points[i].speedup,
            rows[i].runs.len()
        );
    }
    let equivalent: Vec<&str> = rows
        .iter()
        .zip(summaries)
        .filter(|(_, s)| s.judgement.as_ref().is_ok_and(Judgement::equivalent))
        .map(|(r, _)| r.spec.name.as_str())
        .collect();
    println!(
        "\nequivalent to the reference on every observable: {}",
        if equivalent.is_empty() {
            "none".to_string()
        } else {
            equivalent.join(", ")
        }
    );
    print_fastest(rows, summaries);
}

/// The fastest layered configuration judged equivalent, with and without repair.
fn print_fastest(rows: &[Row], summaries: &[Summary]) {
    for repaired in [false, true] {
        let best = rows
            .iter()
            .zip(summaries)
            .filter(|(r, s)| {
                matches!(r.spec.mode, Mode::Layer(_))
                    && r.spec.repair == repaired
                    && violations_of(r).total() == 0
                    && s.judgement.as_ref().is_ok_and(Judgement::equivalent)
            })
            .max_by(|a, b| a.1.speedup_brute.total_cmp(&b.1.speedup_brute));
        let what = if repaired { "repaired" } else { "unrepaired" };
        match best {
            Some((r, s)) => println!(
                "fastest equivalent {what} layered configuration without violations: {} \
                 ({:.2}x brute force, {:.2}x stock, {} seeds)",
                r.spec.name,
                s.speedup_brute,
                s.speedup_stock,
                r.runs.len()
            ),
            None => println!("fastest equivalent {what} layered configuration: none"),
        }
    }
}
