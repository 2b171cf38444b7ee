//! `rcg-lab stability`: the stability suite measured. Every scene of
//! [`rcg_scenes::stability`] under the reference, brute force, stock
//! Rapier, the contact graph and all 2^7 combinations of the speed-up switches; each
//! run's deviation from the scene's reference and its plausibility violations by kind.
//!
//! ```text
//! cargo lab stability [--configs all|quick|LIST] [--scenes all|LIST] [--repair] [--out DIR]
//! ```
//! `--configs`: `all` (default: the named runs and the 128 combinations), `quick` (the
//! named runs and each switch alone), or a comma list of `reference`, `plain` (the DIKU
//! run's reference), `brute`, `cg`, `stock`, combination labels like `C-----F` or
//! numbers 0–127. Each scene also runs its targets and their controls (see
//! [`StabilityCase::target_spec`]). `--scenes`: `all` (default) or a comma list of scene
//! names. Writes `results.csv` into `DIR` (default `target/stability`) and prints two
//! markdown tables: per scene, the violations and deviation under the named runs, each
//! switch alone and the worst combination; then per scene and target, the target's
//! run against its control and whether the failure shows.
//!
//! # Variants and the monitor mode
//! A run is a `Variant`: a configuration ([`RunSpec`]) and a `MonitorMode`. By
//! default the mode is `Detect`: an observing monitor reports and nothing is repaired.
//! `--repair` adds a second pass of every layered configuration with the layer's
//! monitor repairing ([`RunSpec::with_repair`]); plain Rapier runs (the plain reference,
//! brute force, stock) cannot repair and are left out of it. Every run, repaired or
//! not, is measured against the same, unrepaired reference. The CSV has a `monitor`
//! column, and the tables are printed once per mode.

use std::path::PathBuf;
use std::time::Instant;

use rapier_contact_graph::monitor::{MonitorConfig, ViolationKind};

use crate::measure::{self, Mode, RunOptions, RunResult, RunSpec};
use crate::stability::{self, Failure, StabilityCase, Target};

/// Options of `rcg-lab stability`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Configurations: `all`, `quick` (the named runs and each switch alone), or a
    /// comma list of reference, plain, brute, cg, stock and combination labels (e.g.
    /// C-----F) or numbers 0-127.
    #[arg(
        long,
        value_name = "all|quick|LIST",
        default_value = "all",
        value_parser = parse_configs
    )]
    pub configs: Configs,
    /// Scenes: `all` or a comma list of scene names.
    #[arg(long, value_name = "all|LIST", default_value = "all", value_parser = parse_scenes)]
    pub scenes: Scenes,
    /// Also run every layered configuration with the layer's monitor repairing.
    #[arg(long)]
    pub repair: bool,
    /// Directory for results.csv.
    #[arg(long, value_name = "DIR", default_value = "target/stability")]
    pub out: PathBuf,
}

/// The configurations to run, the reference first.
#[derive(Clone, Debug)]
pub struct Configs(pub Vec<RunSpec>);

/// The scenes to run.
#[derive(Clone, Debug)]
pub struct Scenes(pub Vec<&'static StabilityCase>);

/// The columns of `results.csv`.
pub const CSV_HEADER: [&str; 23] = [
    "scene",
    "configuration",
    "kind",
    "cache",
    "tweak",
    "reduce",
    "zero",
    "damp",
    "subgroup",
    "fixate",
    "monitor",
    "deviation_radii",
    "violations",
    "hanging",
    "launch",
    "penetration",
    "escape",
    "peak_hang",
    "peak_launch",
    "peak_penetration",
    "left_region",
    "final_awake",
    "time_s",
];

/// What the plausibility monitor does during a run.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
enum MonitorMode {
    /// Detect and count; change nothing.
    Detect,
    /// The layer's monitor repairs ([`RunSpec::with_repair`]).
    Repair,
}

impl MonitorMode {
    fn name(self) -> &'static str {
        match self {
            MonitorMode::Detect => "detect",
            MonitorMode::Repair => "repair",
        }
    }
}

/// One run of a scene: a configuration and a monitor mode.
#[derive(Clone, Debug)]
struct Variant {
    spec: RunSpec,
    monitor: MonitorMode,
}

/// The configurations of a `--configs` value; the reference always comes first.
pub fn parse_configs(list: &str) -> Result<Configs, String> {
    let mut out = vec![stability::reference()];
    let named = [
        RunSpec {
            name: "plain reference".into(),
            ..RunSpec::reference()
        },
        RunSpec::brute_force(),
        RunSpec::stock(),
        RunSpec::contact_graph(),
    ];
    match list {
        "all" => {
            out.extend(named);
            out.extend((0..128u8).map(RunSpec::combination));
        }
        "quick" => {
            out.extend(named);
            out.extend((0..7).map(|b| RunSpec::combination(1 << b)));
            out.push(RunSpec::combination(127));
        }
        _ => {
            for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
                match item {
                    "reference" => {}
                    "plain" => out.push(RunSpec {
                        name: "plain reference".into(),
                        ..RunSpec::reference()
                    }),
                    "brute" => out.push(RunSpec::brute_force()),
                    "cg" => out.push(RunSpec::contact_graph()),
                    "stock" => out.push(RunSpec::stock()),
                    other => {
                        let b = crate::table5::combination_bits(other)
                            .ok_or(format!("unknown configuration `{other}`"))?;
                        out.push(RunSpec::combination(b));
                    }
                }
            }
        }
    }
    Ok(Configs(out))
}

/// The scenes of a `--scenes` value.
pub fn parse_scenes(list: &str) -> Result<Scenes, String> {
    if list == "all" {
        return Ok(Scenes(stability::suite().iter().collect()));
    }
    list.split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|n| stability::case(n).ok_or(format!("unknown scene `{n}`")))
        .collect::<Result<_, _>>()
        .map(Scenes)
}

/// Runs one variant of a case against its reference trajectory (`None`: this is the
/// reference).
fn run_variant(
    case: &StabilityCase,
    variant: &Variant,
    reference: Option<&measure::Trajectory>,
) -> rapier_contact_graph::Result<(RunResult, measure::Trajectory)> {
    let scene = (case.build)();
    let bodies = case.measured_bodies(&scene);
    let inside = |p| case.inside.is_none_or(|f| f(p));
    let opts = RunOptions {
        steps: case.steps,
        sample_every: stability::SAMPLE_EVERY,
        radius: case.radius,
        bodies: &bodies,
        reference,
        inside: &inside,
        monitor: MonitorConfig::default(),
    };
    match variant.monitor {
        MonitorMode::Detect => measure::run(&variant.spec, scene, &opts),
        MonitorMode::Repair => measure::run(&variant.spec.clone().with_repair(), scene, &opts),
    }
}

/// Violations as `2H 1L`; `0` when none. Letters: H hanging sleeper, L launch, P deep
/// penetration, E escape, U unresponsive held body.
fn violations_text(r: &RunResult) -> String {
    let v = r.violations;
    let parts: Vec<String> = [
        (v.hanging, 'H'),
        (v.launch, 'L'),
        (v.penetration, 'P'),
        (v.escape, 'E'),
        (v.unresponsive, 'U'),
    ]
    .iter()
    .filter(|(n, _)| *n > 0)
    .map(|(n, c)| format!("{n}{c}"))
    .collect();
    if parts.is_empty() {
        "0".into()
    } else {
        parts.join(" ")
    }
}

fn violations_text_opt(r: Option<&RunResult>) -> String {
    r.map_or("—".into(), violations_text)
}

fn cell(r: Option<&RunResult>) -> String {
    match r {
        Some(r) => format!("{} · {:.2}", violations_text(r), r.deviation),
        None => "—".into(),
    }
}

fn kind_name(spec: &RunSpec) -> &'static str {
    match (&spec.mode, spec.name.as_str()) {
        (_, "reference") => "reference",
        (_, "plain reference") => "plain_reference",
        (_, "brute force") => "brute_force",
        (_, "contact graph") => "contact_graph",
        (Mode::Stock, _) => "stock",
        (_, name) if crate::table5::combination_bits(name).is_some() => "combination",
        _ => "control",
    }
}

fn failure_name(f: Failure) -> &'static str {
    match f {
        Failure::Violation(k) => k.name(),
        Failure::Deviation => "deviation",
    }
}

/// A case's variants: the requested configurations, then each target's run and
/// control (when not requested already), in every monitor mode.
fn variants_of(case: &StabilityCase, specs: &[RunSpec], modes: &[MonitorMode]) -> Vec<Variant> {
    let mut all: Vec<RunSpec> = specs.to_vec();
    for t in targets_of(case) {
        for s in [case.target_spec(t), case.control_spec(t)] {
            if !all.iter().any(|a| a.name == s.name) {
                all.push(s);
            }
        }
    }
    let mut out = Vec::new();
    for &m in modes {
        for (i, s) in all.iter().enumerate() {
            // The reference is run once, unrepaired; plain Rapier cannot repair.
            let layered = matches!(s.mode, Mode::Layer(_));
            if m == MonitorMode::Detect || (i > 0 && layered) {
                out.push(Variant {
                    spec: s.clone(),
                    monitor: m,
                });
            }
        }
    }
    out
}

/// What a case was built against and what it is expected to fail under, in order.
fn targets_of(case: &StabilityCase) -> Vec<Target> {
    let mut t: Vec<Target> = case.built_against.to_vec();
    for e in case.expected {
        if !t.contains(&e.target) {
            t.push(e.target);
        }
    }
    t
}

/// Runs `rcg-lab stability`.
// Long: a runner: configurations, runs, judgement, table and CSV, in order.
pub fn run(args: &Args) -> Result<(), String> {
    let (specs, cases) = (&args.configs.0, &args.scenes.0);
    let modes: &[MonitorMode] = if args.repair {
        &[MonitorMode::Detect, MonitorMode::Repair]
    } else {
        &[MonitorMode::Detect]
    };

    let started = Instant::now();
    let plan: Vec<(&StabilityCase, Vec<Variant>)> = cases
        .iter()
        .map(|&c| (c, variants_of(c, specs, modes)))
        .collect();
    let total: usize = plan.iter().map(|(_, v)| v.len()).sum();
    let bar = super::progress(total);
    let mut results: Vec<(&StabilityCase, Variant, RunResult)> = Vec::new();
    for (case, variants) in &plan {
        // The reference is the first variant; every run is measured against it.
        let mut reference: Option<measure::Trajectory> = None;
        for v in variants {
            bar.set_message(format!("{} / {}", case.name, v.spec.name));
            match run_variant(case, v, reference.as_ref()) {
                Ok((mut r, traj)) => {
                    if reference.is_none() {
                        r.deviation = 0.0;
                        reference = Some(traj);
                    }
                    // Tables look runs up by configuration; the mode is a column.
                    r.name.clone_from(&v.spec.name);
                    results.push((case, v.clone(), r));
                }
                Err(e) => {
                    bar.abandon();
                    return Err(format!("in {} / {}: {e}", case.name, v.spec.name));
                }
            }
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    eprintln!("{total} runs in {:.1} s", started.elapsed().as_secs_f64());

    // CSV: one row per scene × variant.
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let path = args.out.join("results.csv");
    let rows = results.iter().map(|(case, v, r)| {
        let mut row = vec![
            case.name.to_string(),
            r.name.clone(),
            kind_name(&v.spec).to_string(),
        ];
        row.extend(super::switch_fields(&v.spec));
        row.extend([
            v.monitor.name().to_string(),
            format!("{:.6}", r.deviation),
            r.violations.total().to_string(),
            r.violations.hanging.to_string(),
            r.violations.launch.to_string(),
            r.violations.penetration.to_string(),
            r.violations.escape.to_string(),
            format!("{:.4}", r.peaks.hang),
            format!("{:.4}", r.peaks.launch),
            format!("{:.4}", r.peaks.penetration),
            r.left_region.to_string(),
            r.final_awake.to_string(),
            format!("{:.6}", r.time_s),
        ]);
        row
    });
    super::write_csv(&path, &CSV_HEADER, rows)?;

    for &mode in modes {
        let per_case: Vec<(&StabilityCase, Vec<&RunResult>)> = cases
            .iter()
            .map(|&case| {
                let rows = results
                    .iter()
                    .filter(|(c, v, _)| c.name == case.name && v.monitor == mode)
                    .map(|(_, _, r)| r)
                    .collect();
                (case, rows)
            })
            .collect();
        println!("\n### Monitor: {}\n", mode.name());
        summary_table(&per_case);
        println!();
        verdict_table(&per_case);
    }
    println!(
        "\nCells: violations (H hanging sleeper, L launch, P deep penetration, E escape, U unresponsive) · deviation from the reference in the scene's length unit.\nA failure shows when a target's run has more violations of the expected kind than its control (the same run without the target), or exceeds the control's deviation by {} units.\nwrote {} in {:.1} s",
        stability::DEVIATION_MARGIN,
        path.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Per scene: the named runs, each switch alone (on the contact graph) and the worst
/// combination. Cells are "violations · deviation".
fn summary_table(per_case: &[(&StabilityCase, Vec<&RunResult>)]) {
    let singles: Vec<Target> = Target::ALL
        .iter()
        .copied()
        .filter(|t| t.bit().is_some())
        .collect();
    let mut header = String::from(
        "| scene | reference | plain reference | brute force | stock | contact graph |",
    );
    let mut rule = String::from("|---|---|---|---|---|---|");
    for t in &singles {
        header += &format!(" {} |", t.name());
        rule += "---|";
    }
    header += " worst combination | combinations with violations |";
    rule += "---|---|";
    println!("{header}\n{rule}");
    for (case, rows) in per_case {
        let by_name = |n: &str| rows.iter().copied().find(|r| r.name == n);
        let mut line = format!(
            "| {} | {} | {} | {} | {} | {} |",
            case.name,
            violations_text_opt(by_name("reference")),
            cell(by_name("plain reference")),
            cell(by_name("brute force")),
            cell(by_name("stock Rapier")),
            cell(by_name("contact graph")),
        );
        for t in &singles {
            let name = t
                .bit()
                .map(|b| crate::table5::label(&crate::table5::combination(1 << b)));
            line += &format!(" {} |", cell(name.and_then(|n| by_name(&n))));
        }
        let combos: Vec<&RunResult> = rows
            .iter()
            .copied()
            .filter(|r| crate::table5::combination_bits(&r.name).is_some())
            .collect();
        let worst = combos.iter().copied().max_by(|a, b| {
            a.violations
                .total()
                .cmp(&b.violations.total())
                .then(a.deviation.total_cmp(&b.deviation))
        });
        let with_violations = combos.iter().filter(|r| r.violations.total() > 0).count();
        line += &format!(
            " {} {} | {}/{} |",
            worst.map_or("—".into(), |r| format!("`{}`", r.name)),
            cell(worst),
            with_violations,
            combos.len()
        );
        println!("{line}");
    }
}

/// Per scene and target (what it was built against, then what it is expected to fail
/// under): the target's run against its control, and whether the failure shows.
fn verdict_table(per_case: &[(&StabilityCase, Vec<&RunResult>)]) {
    println!(
        "| scene | target | run | control | expected | shows as violation | shows as deviation |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (case, rows) in per_case {
        let by_name = |n: &str| rows.iter().copied().find(|r| r.name == n);
        for t in targets_of(case) {
            let (run_spec, control_spec) = (case.target_spec(t), case.control_spec(t));
            let (Some(run), Some(control)) = (by_name(&run_spec.name), by_name(&control_spec.name))
            else {
                continue;
            };
            let expected = case.expected.iter().find(|e| e.target == t);
            let kinds: Vec<&str> = ViolationKind::ALL
                .iter()
                .filter(|&&k| stability::shows(Failure::Violation(k), &run.into(), &control.into()))
                .map(|k| k.name())
                .collect();
            println!(
                "| {} | {} | `{}` {} | `{}` {} | {} | {} | {} |",
                case.name,
                t.name(),
                run.name,
                cell(Some(run)),
                control.name,
                cell(Some(control)),
                expected.map_or("none", |e| failure_name(e.failure)),
                if kinds.is_empty() {
                    "no".to_string()
                } else {
                    kinds.join(", ")
                },
                if stability::shows(Failure::Deviation, &run.into(), &control.into()) {
                    format!("yes (+{:.2})", run.deviation - control.deviation)
                } else {
                    format!("no ({:+.2})", run.deviation - control.deviation)
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configuration_and_scene_lists() {
        let quick = parse_configs("quick").unwrap().0;
        assert_eq!(quick.len(), 1 + 4 + 7 + 1);
        assert_eq!(quick[0].name, stability::reference().name);
        let some = parse_configs("plain,cg,C-----F").unwrap().0;
        assert_eq!(some[1].name, "plain reference");
        assert_eq!(kind_name(&some[1]), "plain_reference");
        assert_eq!(kind_name(&some[3]), "combination");
        assert!(parse_configs("C-----F+repair").is_err(), "no +repair here");
        let all = parse_scenes("all").unwrap().0;
        assert_eq!(all.len(), stability::suite().len());
        let first = all[0].name;
        assert_eq!(parse_scenes(first).unwrap().0[0].name, first);
        assert!(parse_scenes("nope").unwrap_err().contains("nope"));
    }
}
