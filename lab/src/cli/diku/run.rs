//! The run of `rcg-lab diku`, as its steps: the reference with its refinements and
//! floors, the screening, the reported configurations on every seed, their own floors,
//! then the report (printed tables, CSV files, chart).

use std::time::Instant;

use indicatif::ProgressBar;
use rapier3d::math::Real;

use crate::accuracy::ensemble::{
    outcomes, reference_double_iterations, run_reference, run_seed, ReferenceRun, SeedRun, Setup,
    Variant,
};
use crate::accuracy::observables::{Outcome, COUNT};
use crate::accuracy::tolerances;
use crate::measure::{self, RunSpec};
use crate::report::{self, ChartPoint, ChartSpec};

use super::args::is_named;
use super::csv::write_results;
use super::print::{print_front, print_table, print_tolerances};
use super::summary::{point, summarize, Row, Summary};
use super::Args;

/// The run's sizes, from the arguments.
struct Plan<'a> {
    /// The configurations besides the reference.
    others: Vec<&'a RunSpec>,
    /// Seeds of the reported table (`--seeds`).
    k: usize,
    /// Seeds of the screening (`k` with `--full`).
    screen: usize,
    setup: Setup,
    /// The `k` seeds.
    seeds: Vec<u64>,
}

/// The reference on every seed and what is measured from it.
struct Reference {
    runs: Vec<ReferenceRun>,
    /// Its outcomes, seed by seed.
    outcomes: Vec<Outcome>,
    /// Per observable, from its two refinements.
    tol: [f64; COUNT],
    /// The trajectory deviation's floors: the reference against itself with every
    /// sphere moved by one ulp, and against another seed.
    ulp_floor: f64,
    seed_floor: f64,
    /// The spheres' radius, the deviation's unit.
    radius: Real,
}

/// Runs `rcg-lab diku`.
pub fn run(args: &Args) -> Result<(), String> {
    let plan = plan(args)?;
    let started = Instant::now();
    let bar = super::super::progress(3 * plan.k + 1 + plan.others.len() * plan.screen);

    // 1. The reference and its refinements on every seed.
    let (reference, refined) = reference(&plan, &bar)?;
    // 2. Screening.
    let mut rows = screen(&plan, &reference, refined, &bar)?;
    // 3. The named configurations and the screening's candidates on all K seeds.
    if plan.screen < plan.k {
        let chosen = choose(&rows, &reference);
        let extra: usize = chosen.iter().filter(|&&c| c).count() * (plan.k - plan.screen);
        bar.inc_length(extra as u64);
        for (row, _) in rows.iter_mut().zip(&chosen).filter(|(_, c)| **c) {
            let spec = row.spec.clone();
            extend_runs(
                plan.setup,
                &spec,
                &reference.runs,
                &mut row.runs,
                plan.k,
                &bar,
            )?;
        }
    }
    // 4. The trajectory deviation's floor on each reported configuration's own solver.
    own_floors(&plan, &mut rows, reference.radius, &bar)?;
    bar.finish_and_clear();

    report_all(args, &plan, &reference, &rows)?;
    println!(
        "\nwrote {}/results.csv, runs.csv, chart.svg, chart.png in {:.1} s",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The run's sizes; prints them. A usage error for fewer than 2 seeds.
fn plan(args: &Args) -> Result<Plan<'_>, String> {
    // The command line refuses these; a caller building `Args` itself gets the same
    // usage error instead of a panic.
    if args.seeds < 2 || args.screen_seeds < 2 {
        return Err(format!(
            "a paired interval needs at least 2 seeds: --seeds {} --screen-seeds {}",
            args.seeds, args.screen_seeds
        ));
    }
    let k = args.seeds as usize;
    let screen = if args.full {
        k
    } else {
        (args.screen_seeds as usize).min(k)
    };
    let setup = Setup {
        spheres: args.spheres,
        steps: args.steps,
    };
    let seeds: Vec<u64> = (0..args.seeds).map(|i| args.seed.wrapping_add(i)).collect();
    let others: Vec<&RunSpec> = args
        .configs
        .0
        .iter()
        .filter(|s| **s != RunSpec::reference())
        .collect();
    println!(
        "DIKU scene: {} spheres, {} steps of 0.01 s, {} configurations screened on {screen} seeds, \
         the reported ones on {k} seeds ({}..{})",
        args.spheres,
        args.steps,
        others.len() + 1,
        seeds[0],
        seeds[k - 1]
    );
    Ok(Plan {
        others,
        k,
        screen,
        setup,
        seeds,
    })
}

/// The reference on every seed, its two refinements (twice the iterations, half the
/// time step: the tolerances) and its floors; the refinements' rows beside it.
fn reference(plan: &Plan, bar: &ProgressBar) -> Result<(Reference, Vec<Row>), String> {
    let setup = plan.setup;
    bar.set_message("reference");
    let mut refs = Vec::with_capacity(plan.k);
    for &seed in &plan.seeds {
        refs.push(run_reference(setup, seed)?);
        bar.inc(1);
    }
    let refined = refinements(plan, &refs, bar)?;
    let reference: Vec<Outcome> = refs.iter().map(|r| r.run.outcome).collect();
    let tol = tolerances(
        &[&outcomes(&refined[0].runs), &outcomes(&refined[1].runs)],
        &reference,
    )
    .map_err(|e| format!("tolerances: {e}"))?;
    bar.set_message("reference, one ulp");
    let seed0 = plan.seeds[0];
    let ulp_floor = run_seed(
        setup,
        &RunSpec::reference(),
        seed0,
        Variant::UlpNudge,
        Some(&refs[0]),
    )?
    .0
    .result
    .deviation;
    bar.inc(1);
    let radius = setup.params(seed0).radius;
    let seed_floor = measure::deviation(&refs[1].trajectory, &refs[0].trajectory, radius);
    let reference = Reference {
        runs: refs,
        outcomes: reference,
        tol,
        ulp_floor,
        seed_floor,
        radius,
    };
    Ok((reference, refined))
}

/// The reference's two refinements on the seeds of `refs`.
fn refinements(plan: &Plan, refs: &[ReferenceRun], bar: &ProgressBar) -> Result<Vec<Row>, String> {
    let mut refined = Vec::new();
    for (spec, variant) in [
        (reference_double_iterations(), Variant::AsBuilt),
        (
            RunSpec {
                name: "reference, half dt".into(),
                ..RunSpec::reference()
            },
            Variant::HalfStep,
        ),
    ] {
        bar.set_message(spec.name.clone());
        let mut runs = Vec::with_capacity(plan.k);
        for r in refs {
            runs.push(run_seed(plan.setup, &spec, r.run.seed, variant, Some(r))?.0);
            bar.inc(1);
        }
        refined.push(Row {
            spec,
            runs,
            own_floor: None,
        });
    }
    Ok(refined)
}

/// The rows: the reference, its refinements, then every other configuration on the
/// screening's seeds.
fn screen(
    plan: &Plan,
    reference: &Reference,
    mut refined: Vec<Row>,
    bar: &ProgressBar,
) -> Result<Vec<Row>, String> {
    let mut rows: Vec<Row> = vec![Row {
        spec: RunSpec::reference(),
        runs: reference.runs.iter().map(|r| r.run.clone()).collect(),
        own_floor: Some(reference.ulp_floor),
    }];
    rows.append(&mut refined);
    for spec in &plan.others {
        let mut runs = Vec::with_capacity(plan.k);
        extend_runs(
            plan.setup,
            spec,
            &reference.runs,
            &mut runs,
            plan.screen,
            bar,
        )?;
        rows.push(Row {
            spec: (*spec).clone(),
            runs,
            own_floor: None,
        });
    }
    Ok(rows)
}

/// The rows to run on all seeds: the named configurations, the screening's Pareto front
/// and its four fastest zero-violation configurations within the band.
fn choose(rows: &[Row], reference: &Reference) -> Vec<bool> {
    let summaries: Vec<Summary> = rows
        .iter()
        .map(|r| summarize(rows, r, &reference.outcomes, &reference.tol))
        .collect();
    let points: Vec<ChartPoint> = rows
        .iter()
        .zip(&summaries)
        .map(|(r, s)| point(r, s))
        .collect();
    let mut chosen: Vec<bool> = rows.iter().map(|r| is_named(&r.spec)).collect();
    for i in report::pareto_front(&points, true) {
        chosen[i] = true;
    }
    let mut inside: Vec<usize> = (0..rows.len())
        .filter(|&i| points[i].violations == 0 && points[i].deviation <= 1.0)
        .filter(|&i| points[i].speedup.is_finite())
        .collect();
    inside.sort_by(|&a, &b| points[b].speedup.total_cmp(&points[a].speedup));
    for &i in inside.iter().take(4) {
        chosen[i] = true;
    }
    chosen
}

/// The trajectory deviation's floor on each reported configuration's own solver
/// (`docs/accuracy.md`): the configuration on the first seed against itself with every
/// sphere moved by one ulp. The reported ones are those on K seeds (only the named
/// ones when every configuration runs on K seeds: two runs each).
fn own_floors(
    plan: &Plan,
    rows: &mut [Row],
    radius: Real,
    bar: &ProgressBar,
) -> Result<(), String> {
    let (k, seed0) = (plan.k, plan.seeds[0]);
    let reported: Vec<usize> = (3..rows.len())
        .filter(|&i| rows[i].runs.len() == k && (plan.screen < k || is_named(&rows[i].spec)))
        .collect();
    bar.inc_length(2 * reported.len() as u64);
    for i in reported {
        let spec = rows[i].spec.clone();
        bar.set_message(format!("{}, one ulp", spec.name));
        let (_, own) = run_seed(plan.setup, &spec, seed0, Variant::AsBuilt, None)?;
        bar.inc(1);
        let (_, nudged) = run_seed(plan.setup, &spec, seed0, Variant::UlpNudge, None)?;
        bar.inc(1);
        rows[i].own_floor = Some(measure::deviation(&nudged, &own, radius));
    }
    Ok(())
}

/// Runs `spec` on seeds `from..to` of `refs`, appending to `runs`.
fn extend_runs(
    setup: Setup,
    spec: &RunSpec,
    refs: &[ReferenceRun],
    runs: &mut Vec<SeedRun>,
    to: usize,
    bar: &ProgressBar,
) -> Result<(), String> {
    bar.set_message(spec.name.clone());
    for r in refs.iter().take(to).skip(runs.len()) {
        let (run, _) = run_seed(setup, spec, r.run.seed, Variant::AsBuilt, Some(r))?;
        runs.push(run);
        bar.inc(1);
    }
    Ok(())
}

/// The report: the tolerances and the table printed, `results.csv` and `runs.csv`, the
/// chart, then the front printed.
fn report_all(args: &Args, plan: &Plan, reference: &Reference, rows: &[Row]) -> Result<(), String> {
    let summaries: Vec<Summary> = rows
        .iter()
        .map(|r| summarize(rows, r, &reference.outcomes, &reference.tol))
        .collect();
    print_tolerances(&rows[..3], &reference.outcomes, &reference.tol);
    print_table(rows, &summaries, reference.ulp_floor, reference.seed_floor);
    write_results(
        &args.out,
        rows,
        &summaries,
        &reference.outcomes,
        &reference.tol,
    )?;
    let points: Vec<ChartPoint> = rows
        .iter()
        .zip(&summaries)
        .map(|(r, s)| point(r, s))
        .collect();
    write_chart(args, plan.k, &points)?;
    print_front(rows, &summaries, &points);
    Ok(())
}

/// `chart.svg` and `chart.png`: speed-up over brute force against accuracy.
fn write_chart(args: &Args, k: usize, points: &[ChartPoint]) -> Result<(), String> {
    let title = format!(
        "DIKU, {} spheres: speed-up over brute force vs accuracy ({k} seeds paired)",
        args.spheres
    );
    let spec = ChartSpec {
        title: &title,
        x_label: "accuracy: worst observable's |paired mean difference| / tolerance (1 = the reference's own error)",
        y_label: "speed-up over brute force",
        width: 1000,
        height: 640,
        log_y: false,
        band: Some(1.0),
    };
    let write = |name: &str, bytes: &[u8]| {
        let path = args.out.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    write("chart.svg", report::svg(points, &spec).as_bytes())?;
    write("chart.png", &report::png(points, &spec))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::diku::parse_configs;

    #[test]
    fn fewer_than_two_seeds_is_a_usage_error_before_anything_runs() {
        for (seeds, screen_seeds) in [(1, 2), (0, 2), (8, 1)] {
            let args = Args {
                spheres: 10,
                configs: parse_configs("brute").unwrap(),
                steps: 1,
                seed: 0,
                seeds,
                screen_seeds,
                full: false,
                out: std::env::temp_dir().join("rcg_lab_never_written"),
            };
            assert!(run(&args).unwrap_err().contains("at least 2 seeds"));
        }
    }
}
