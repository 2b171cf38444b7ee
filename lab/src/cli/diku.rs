//! `rcg-lab diku`: the project's main job. The DIKU scene (paper §7, Fig. 12) run
//! under the reference, brute force, the contact graph, stock Rapier and all 2^7
//! combinations of cache, tweak, reduce, zero, damp, subgroup and fixate; every run
//! measured for speed, and for accuracy on paired seed ensembles against the reference
//! ([`crate::accuracy`], `docs/accuracy.md`).
//!
//! ```text
//! cargo lab diku [--spheres N] [--configs default|all|quick|LIST] [--steps K]
//!                [--seed S] [--seeds K] [--screen-seeds M] [--full] [--out DIR]
//! ```
//! `LIST` is `default` (the named runs, the contact graph with the monitor repairing,
//! and the 128 combinations), `all` (those and every combination again with the
//! monitor repairing), `quick` (the named runs and 8 combinations, each with and
//! without repair), or a comma list of `reference`, `brute`, `cg`, `cg+repair`,
//! `stock` and combination labels like `C-----F` or numbers 0–127, each optionally
//! with a `+repair` suffix.
//!
//! # The run
//! 1. The reference on `K` seeds `S, S+1, ..` (default 8), and its two refinements
//!    (twice its iterations, half its time step) on the same seeds: the tolerances.
//!    The reference once more with every sphere nudged by one ulp: the chaos floor of
//!    the trajectory deviation.
//! 2. **Screening:** every configuration on the first `M` seeds (default 2).
//! 3. **The reported table:** the named configurations (brute force, contact graph,
//!    stock Rapier, contact graph +repair, the 8 combinations of `quick`, and
//!    fixation alone, `------F`), the
//!    Pareto front of the screening (zero violations) and the four fastest
//!    zero-violation configurations whose screening accuracy is within the band, on
//!    all `K` seeds. `--full` runs every configuration on all `K` seeds instead.
//!
//! Which configurations reach step 3 depends on the screening's measured speed-ups;
//! everything else a row reports about accuracy (observables, intervals, verdict) is
//! the same bit for bit for the same seeds. Writes `results.csv` (one row per
//! configuration), `runs.csv` (one row per run), `chart.svg` and `chart.png` into `DIR`
//! (default `target/diku`), and prints the table.

use std::path::PathBuf;
use std::time::Instant;

use rapier_contact_graph::speedups::SpeedUps;

use crate::accuracy::ensemble::{
    outcomes, reference_double_iterations, run_reference, run_seed, ReferenceRun, SeedRun, Setup,
    Variant,
};
use crate::accuracy::observables::{Outcome, COUNT, OBSERVABLES};
use crate::accuracy::{judge, tolerances, Judgement};
use crate::measure::{self, Mode, RunSpec};
use crate::report::{self, ChartPoint, ChartSpec, PointKind};

/// Options of `rcg-lab diku`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Spheres dropped on the plane.
    #[arg(long, value_name = "N", default_value_t = 120, value_parser = positive)]
    pub spheres: usize,
    /// Configurations: `default`, `all`, `quick`, or a comma list of reference, brute,
    /// cg, cg+repair, stock and combination labels (e.g. C-----F) or numbers 0-127,
    /// each optionally suffixed +repair (the monitor repairing).
    #[arg(
        long,
        value_name = "default|all|quick|LIST",
        default_value = "default",
        value_parser = parse_configs
    )]
    pub configs: Configs,
    /// Steps of 0.01 s per run.
    #[arg(long, value_name = "K", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    pub steps: u64,
    /// The first seed of the scene's sphere placement; the ensembles use S, S+1, ...
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Seeds of the reported table and of the tolerances (at least 2).
    #[arg(long, value_name = "K", default_value_t = 8, value_parser = clap::value_parser!(u64).range(2..=1000))]
    pub seeds: u64,
    /// Seeds every configuration is screened on (at least 2, at most --seeds).
    #[arg(long, value_name = "M", default_value_t = 2, value_parser = clap::value_parser!(u64).range(2..=1000))]
    pub screen_seeds: u64,
    /// Run every configuration on all --seeds seeds (no screening).
    #[arg(long)]
    pub full: bool,
    /// Directory for results.csv, runs.csv, chart.svg and chart.png.
    #[arg(long, value_name = "DIR", default_value = "target/diku")]
    pub out: PathBuf,
}

/// The configurations to run, the reference first.
#[derive(Clone, Debug)]
pub struct Configs(pub Vec<RunSpec>);

fn positive(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("must be positive".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

/// The 8 combinations of `quick` (and of the table in `docs/results.md`): cache, tweak, damp,
/// subgroup + fixate, `C----SF`, the paper's ♠ `C--ZDSF`, `CT-ZDSF`, and all seven.
pub const NAMED_COMBINATIONS: [u8; 8] = [
    0b000_0001, 0b000_0010, 0b001_0000, 0b110_0000, 0b110_0001, 0b111_1001, 0b111_1011, 127,
];

/// Fixation alone (`------F`), the paper's big win (its Table 5): always reported on
/// all seeds with [`NAMED_COMBINATIONS`].
pub const FIXATE_ALONE: u8 = 0b100_0000;

/// The configurations of a `--configs` value; the reference always comes first.
pub fn parse_configs(list: &str) -> Result<Configs, String> {
    let mut out = vec![RunSpec::reference()];
    let named = [
        RunSpec::brute_force(),
        RunSpec::contact_graph(),
        RunSpec::stock(),
    ];
    match list {
        "default" | "all" => {
            out.extend(named);
            out.push(RunSpec::contact_graph().with_repair());
            out.extend((0..128u8).map(RunSpec::combination));
            if list == "all" {
                // Every combination again with the monitor repairing: the speed
                // given up for safety.
                out.extend((0..128u8).map(|b| RunSpec::combination(b).with_repair()));
            }
        }
        "quick" => {
            out.extend(named);
            for b in NAMED_COMBINATIONS {
                out.push(RunSpec::combination(b));
                out.push(RunSpec::combination(b).with_repair());
            }
        }
        _ => {
            for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
                match item {
                    "reference" => {}
                    "brute" => out.push(RunSpec::brute_force()),
                    "cg" => out.push(RunSpec::contact_graph()),
                    "stock" => out.push(RunSpec::stock()),
                    "cg+repair" => out.push(RunSpec::contact_graph().with_repair()),
                    other => {
                        let (label, repair) = match other.strip_suffix("+repair") {
                            Some(l) => (l, true),
                            None => (other, false),
                        };
                        let b = SpeedUps::combination_bits(label)
                            .ok_or(format!("unknown configuration `{other}`"))?;
                        let spec = RunSpec::combination(b);
                        out.push(if repair { spec.with_repair() } else { spec });
                    }
                }
            }
        }
    }
    Ok(Configs(out))
}

/// The chart marker of a configuration.
pub fn kind_of(spec: &RunSpec) -> PointKind {
    if spec.repair {
        return PointKind::Repaired;
    }
    match (&spec.mode, spec.name.as_str()) {
        (_, "reference") => PointKind::Reference,
        (_, "brute force") => PointKind::BruteForce,
        (_, "contact graph") => PointKind::ContactGraph,
        (Mode::Stock, _) => PointKind::StockRapier,
        (Mode::Plain { .. }, _) => PointKind::Reference,
        _ => PointKind::Combination,
    }
}

/// Whether a configuration is one of the named ones that always get all `K` seeds.
fn is_named(spec: &RunSpec) -> bool {
    let named_combination = match &spec.mode {
        Mode::Layer(s) => {
            !spec.repair
                && NAMED_COMBINATIONS
                    .iter()
                    .chain([&FIXATE_ALONE])
                    .any(|&b| SpeedUps::combination(b) == *s)
        }
        _ => false,
    };
    let plain = !matches!(kind_of(spec), PointKind::Combination | PointKind::Repaired);
    plain || spec.name == "contact graph +repair" || named_combination
}

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

/// A configuration with its runs on the first seeds.
struct Row {
    spec: RunSpec,
    runs: Vec<SeedRun>,
    /// The trajectory deviation's floor on the configuration's own solver: its run on
    /// the first seed against the same run with every sphere moved by one ulp, in
    /// radii (measured for the reference and the reported configurations).
    own_floor: Option<f64>,
}

/// A row summed up against the reference.
struct Summary {
    judgement: Result<Judgement, String>,
    time_s: f64,
    speedup_brute: f64,
    speedup_stock: f64,
}

fn mean(xs: impl Iterator<Item = f64>) -> f64 {
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

fn summarize(rows: &[Row], row: &Row, reference: &[Outcome], tol: &[f64; COUNT]) -> Summary {
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

fn accuracy_of(s: &Summary) -> f64 {
    s.judgement
        .as_ref()
        .map_or(f64::INFINITY, Judgement::accuracy)
}

fn violations_of(row: &Row) -> measure::Violations {
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

/// Runs `spec` on seeds `from..to` of `refs`, appending to `runs`.
fn extend_runs(
    setup: Setup,
    spec: &RunSpec,
    refs: &[ReferenceRun],
    runs: &mut Vec<SeedRun>,
    to: usize,
    bar: &indicatif::ProgressBar,
) -> Result<(), String> {
    bar.set_message(spec.name.clone());
    for r in refs.iter().take(to).skip(runs.len()) {
        let (run, _) = run_seed(setup, spec, r.run.seed, Variant::AsBuilt, Some(r))?;
        runs.push(run);
        bar.inc(1);
    }
    Ok(())
}

/// Runs `rcg-lab diku`.
pub fn run(args: &Args) -> Result<(), String> {
    let specs = &args.configs.0;
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
    let others: Vec<&RunSpec> = specs
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
    let started = Instant::now();
    let bar = super::progress(3 * k + 1 + others.len() * screen);

    // 1. The reference and its refinements on every seed.
    bar.set_message("reference");
    let mut refs = Vec::with_capacity(k);
    for &seed in &seeds {
        refs.push(run_reference(setup, seed)?);
        bar.inc(1);
    }
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
        let mut runs = Vec::with_capacity(k);
        for r in &refs {
            runs.push(run_seed(setup, &spec, r.run.seed, variant, Some(r))?.0);
            bar.inc(1);
        }
        refined.push(Row {
            spec,
            runs,
            own_floor: None,
        });
    }
    let reference: Vec<Outcome> = refs.iter().map(|r| r.run.outcome).collect();
    let tol = tolerances(
        &[&outcomes(&refined[0].runs), &outcomes(&refined[1].runs)],
        &reference,
    )
    .map_err(|e| format!("tolerances: {e}"))?;
    bar.set_message("reference, one ulp");
    let ulp_floor = run_seed(
        setup,
        &RunSpec::reference(),
        seeds[0],
        Variant::UlpNudge,
        Some(&refs[0]),
    )?
    .0
    .result
    .deviation;
    bar.inc(1);
    let radius = setup.params(seeds[0]).radius;
    let seed_floor = measure::deviation(&refs[1].trajectory, &refs[0].trajectory, radius);

    // 2. Screening.
    let mut rows: Vec<Row> = vec![Row {
        spec: RunSpec::reference(),
        runs: refs.iter().map(|r| r.run.clone()).collect(),
        own_floor: Some(ulp_floor),
    }];
    rows.append(&mut refined);
    for spec in &others {
        let mut runs = Vec::with_capacity(k);
        extend_runs(setup, spec, &refs, &mut runs, screen, &bar)?;
        rows.push(Row {
            spec: (*spec).clone(),
            runs,
            own_floor: None,
        });
    }

    // 3. The named configurations and the screening's candidates on all K seeds.
    if screen < k {
        let summaries: Vec<Summary> = rows
            .iter()
            .map(|r| summarize(&rows, r, &reference, &tol))
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
        let extra: usize = chosen.iter().filter(|&&c| c).count() * (k - screen);
        bar.inc_length(extra as u64);
        for (row, _) in rows.iter_mut().zip(&chosen).filter(|(_, c)| **c) {
            let spec = row.spec.clone();
            extend_runs(setup, &spec, &refs, &mut row.runs, k, &bar)?;
        }
    }

    // 4. The trajectory deviation's floor on each reported configuration's own solver
    // (`docs/accuracy.md`): the configuration on the first seed against itself with every
    // sphere moved by one ulp. The reported ones are those on K seeds (only the named
    // ones when every configuration runs on K seeds: two runs each).
    let reported: Vec<usize> = (3..rows.len())
        .filter(|&i| rows[i].runs.len() == k && (screen < k || is_named(&rows[i].spec)))
        .collect();
    bar.inc_length(2 * reported.len() as u64);
    for i in reported {
        let spec = rows[i].spec.clone();
        bar.set_message(format!("{}, one ulp", spec.name));
        let (_, own) = run_seed(setup, &spec, seeds[0], Variant::AsBuilt, None)?;
        bar.inc(1);
        let (_, nudged) = run_seed(setup, &spec, seeds[0], Variant::UlpNudge, None)?;
        bar.inc(1);
        rows[i].own_floor = Some(measure::deviation(&nudged, &own, radius));
    }
    bar.finish_and_clear();

    let summaries: Vec<Summary> = rows
        .iter()
        .map(|r| summarize(&rows, r, &reference, &tol))
        .collect();
    print_tolerances(&rows[..3], &reference, &tol);
    print_table(&rows, &summaries, ulp_floor, seed_floor);
    write_results(args, &rows, &summaries, &reference, &tol)?;

    let points: Vec<ChartPoint> = rows
        .iter()
        .zip(&summaries)
        .map(|(r, s)| point(r, s))
        .collect();
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
    write("chart.svg", report::svg(&points, &spec).as_bytes())?;
    write("chart.png", &report::png(&points, &spec))?;
    print_front(&rows, &summaries, &points);
    println!(
        "\nwrote {}/results.csv, runs.csv, chart.svg, chart.png in {:.1} s",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// A row's chart point: x the accuracy number, y the speed-up over brute force.
fn point(row: &Row, s: &Summary) -> ChartPoint {
    ChartPoint {
        label: row.spec.name.clone(),
        deviation: accuracy_of(s),
        speedup: s.speedup_brute,
        violations: violations_of(row).total(),
        kind: kind_of(&row.spec),
    }
}

/// The tolerance of every observable, with the refinements' intervals it comes from.
fn print_tolerances(reference_rows: &[Row], reference: &[Outcome], tol: &[f64; COUNT]) {
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
fn print_table(rows: &[Row], summaries: &[Summary], ulp_floor: f64, seed_floor: f64) {
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
fn print_front(rows: &[Row], summaries: &[Summary], points: &[ChartPoint]) {
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
    // The fastest layered configuration judged equivalent, with and without repair.
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

/// `results.csv` and `runs.csv`.
fn write_results(
    args: &Args,
    rows: &[Row],
    summaries: &[Summary],
    reference: &[Outcome],
    tol: &[f64; COUNT],
) -> Result<(), String> {
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let f = |x: f64| format!("{x:.6}");
    let table = rows.iter().zip(summaries).map(|(row, s)| {
        let n = row.runs.len();
        let v = violations_of(row);
        let runs = &row.runs;
        let mut out = vec![row.spec.name.clone(), format!("{:?}", kind_of(&row.spec))];
        out.extend(super::switch_fields(&row.spec));
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
    });
    let mut header: Vec<String> = CSV_HEADER.iter().map(|s| s.to_string()).collect();
    header.extend(observable_columns());
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    super::write_csv(&args.out.join("results.csv"), &header, table)?;

    let per_run = rows.iter().flat_map(|row| {
        row.runs.iter().map(move |r| {
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
        })
    });
    let mut header: Vec<&str> = RUNS_CSV_HEADER.to_vec();
    header.extend(OBSERVABLES.iter().map(|o| o.key));
    super::write_csv(&args.out.join("runs.csv"), &header, per_run)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configuration_lists() {
        let all = parse_configs("all").unwrap().0;
        assert_eq!(all.len(), 1 + 3 + 1 + 128 + 128);
        assert_eq!(all[0].name, "reference");
        let default = parse_configs("default").unwrap().0;
        assert_eq!(default.len(), 1 + 3 + 1 + 128);
        assert_eq!(default[..], all[..133]);
        let some = parse_configs("brute, C-----F+repair,127").unwrap().0;
        let names: Vec<&str> = some.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names[..2], ["reference", "brute force"]);
        assert!(some[2].repair && !some[3].repair);
        assert_eq!(kind_of(&some[2]), PointKind::Repaired);
        assert_eq!(kind_of(&some[1]), PointKind::BruteForce);
        assert_eq!(kind_of(&RunSpec::stock()), PointKind::StockRapier);
        assert_eq!(
            kind_of(&reference_double_iterations()),
            PointKind::Reference
        );
        assert!(parse_configs("bogus").unwrap_err().contains("bogus"));
    }

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

    #[test]
    fn named_configurations_always_get_every_seed() {
        let default = parse_configs("default").unwrap().0;
        let named: Vec<&str> = default
            .iter()
            .filter(|s| is_named(s))
            .map(|s| s.name.as_str())
            .collect();
        assert_eq!(named.len(), 5 + NAMED_COMBINATIONS.len() + 1, "{named:?}");
        assert!(named.contains(&"------F"));
        assert!(named.contains(&"contact graph +repair"));
        assert!(named.contains(&"CTRZDSF"));
        assert!(!is_named(&RunSpec::combination(127).with_repair()));
        assert!(!is_named(&RunSpec::combination(4)));
    }
}
