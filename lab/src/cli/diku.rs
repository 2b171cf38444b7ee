//! `rcg-lab diku`: the project's main job. The DIKU scene (paper §7, Fig. 12) run
//! under the reference, brute force, the contact graph, stock Rapier and all 2^7
//! combinations of cache, tweak, reduce, zero, damp, subgroup and fixate; every run
//! measured for speed and accuracy in one process (paper §7, Tables 4–5).
//!
//! ```text
//! cargo lab diku [--spheres N] [--configs all|quick|LIST] [--steps K] [--seed S] [--out DIR]
//! ```
//! `LIST` is `all` (default: the named runs, the 128 combinations, and each again with
//! the monitor repairing), `quick` (the named runs and 8 combinations, each with and
//! without repair), or a comma list of `reference`, `brute`, `cg`, `cg+repair`,
//! `stock` and combination labels like `C-----F` or numbers 0–127, each optionally
//! with a `+repair` suffix. Writes `results.csv`, `chart.svg` and `chart.png` into `DIR`
//! (default `target/diku`), and prints the table.

use std::path::PathBuf;
use std::time::Instant;

use rapier3d::prelude::RigidBodyHandle;
use rapier_contact_graph::monitor::MonitorConfig;
use rapier_contact_graph::speedups::SpeedUps;
use rcg_scenes::diku::{diku, is_on_plane, DikuParams};

use crate::measure::{self, Mode, RunOptions, RunResult, RunSpec};
use crate::report::{self, ChartPoint, ChartSpec, PointKind};

/// Options of `rcg-lab diku`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Spheres dropped on the plane.
    #[arg(long, value_name = "N", default_value_t = 120, value_parser = positive)]
    pub spheres: usize,
    /// Configurations: `all`, `quick`, or a comma list of reference, brute, cg,
    /// cg+repair, stock and combination labels (e.g. C-----F) or numbers 0-127, each
    /// optionally suffixed +repair (the monitor repairing).
    #[arg(
        long,
        value_name = "all|quick|LIST",
        default_value = "all",
        value_parser = parse_configs
    )]
    pub configs: Configs,
    /// Steps of 0.01 s per run.
    #[arg(long, value_name = "K", default_value_t = 1000, value_parser = clap::value_parser!(u64).range(1..))]
    pub steps: u64,
    /// Seed of the scene's sphere placement.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Directory for results.csv, chart.svg and chart.png.
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

/// The configurations of a `--configs` value; the reference always comes first.
pub fn parse_configs(list: &str) -> Result<Configs, String> {
    let mut out = vec![RunSpec::reference()];
    let named = [
        RunSpec::brute_force(),
        RunSpec::contact_graph(),
        RunSpec::stock(),
    ];
    match list {
        "all" => {
            out.extend(named);
            out.push(RunSpec::contact_graph().with_repair());
            out.extend((0..128u8).map(RunSpec::combination));
            // Every combination again with the monitor repairing: the speed
            // given up for safety.
            out.extend((0..128u8).map(|b| RunSpec::combination(b).with_repair()));
        }
        "quick" => {
            out.extend(named);
            for b in [
                0b000_0001, 0b000_0010, 0b001_0000, 0b110_0000, 0b110_0001, 0b111_1001, 0b111_1011,
                127,
            ] {
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
        _ => PointKind::Combination,
    }
}

/// The columns of `results.csv`.
pub const CSV_HEADER: [&str; 24] = [
    "configuration",
    "kind",
    "cache",
    "tweak",
    "reduce",
    "zero",
    "damp",
    "subgroup",
    "fixate",
    "time_s",
    "speedup_brute",
    "speedup_stock",
    "deviation_radii",
    "violations",
    "hanging",
    "launch",
    "penetration",
    "escape",
    "mean_groups",
    "max_group_variables",
    "mean_awake",
    "final_awake",
    "last_second_s",
    "left_plane",
];

/// Runs `rcg-lab diku`.
pub fn run(args: &Args) -> Result<(), String> {
    let specs = &args.configs.0;
    let params = DikuParams {
        spheres: args.spheres,
        seed: args.seed,
        ..DikuParams::default()
    };
    let spheres: Vec<RigidBodyHandle> = diku(&params).dynamic_bodies();
    let inside = |p| is_on_plane(&params, p);
    println!(
        "DIKU scene: {} spheres, {} steps of 0.01 s, {} configurations",
        args.spheres,
        args.steps,
        specs.len()
    );
    let started = Instant::now();
    let bar = super::progress(specs.len());
    let mut results: Vec<(RunSpec, RunResult)> = Vec::new();
    let mut reference = None;
    for spec in specs {
        bar.set_message(spec.name.clone());
        let opts = RunOptions {
            steps: args.steps,
            sample_every: 10,
            radius: params.radius,
            bodies: &spheres,
            reference: reference.as_ref(),
            inside: &inside,
            monitor: MonitorConfig::default(),
        };
        match measure::run(spec, diku(&params), &opts) {
            Ok((mut r, traj)) => {
                if reference.is_none() {
                    r.deviation = 0.0;
                    reference = Some(traj);
                }
                results.push((spec.clone(), r));
            }
            Err(e) => {
                bar.abandon();
                return Err(format!("in {}: {e}", spec.name));
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();

    let time_of = |name: &str| {
        results
            .iter()
            .find(|(s, _)| s.name == name)
            .map(|(_, r)| r.time_s)
    };
    let brute = time_of("brute force");
    let stock = time_of("stock Rapier");
    let ratio = |base: Option<f64>, t: f64| base.map_or(f64::NAN, |b| b / t);

    // Table (paper Tables 4–5, with accuracy).
    println!(
        "\n{:<16} {:>8} {:>8} {:>8} {:>9} {:>5} {:>7} {:>9} {:>7} {:>8} {:>5}",
        "configuration",
        "time s",
        "xbrute",
        "xstock",
        "dev (r)",
        "viol",
        "groups",
        "max vars",
        "awake",
        "last 1s",
        "left"
    );
    for (_, r) in &results {
        println!(
            "{:<16} {:>8.3} {:>8.2} {:>8.2} {:>9.4} {:>5} {:>7.1} {:>9} {:>7.1} {:>8.3} {:>5}",
            r.name,
            r.time_s,
            ratio(brute, r.time_s),
            ratio(stock, r.time_s),
            r.deviation,
            r.violations.total(),
            r.mean_groups,
            r.max_largest_variables,
            r.mean_awake,
            r.tail_time_s,
            r.left_region
        );
    }

    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let rows = results.iter().map(|(spec, r)| {
        let mut row = vec![r.name.clone(), format!("{:?}", kind_of(spec))];
        row.extend(super::switch_fields(spec));
        row.extend([
            format!("{:.6}", r.time_s),
            format!("{:.4}", ratio(brute, r.time_s)),
            format!("{:.4}", ratio(stock, r.time_s)),
            format!("{:.6}", r.deviation),
            r.violations.total().to_string(),
            r.violations.hanging.to_string(),
            r.violations.launch.to_string(),
            r.violations.penetration.to_string(),
            r.violations.escape.to_string(),
            format!("{:.3}", r.mean_groups),
            r.max_largest_variables.to_string(),
            format!("{:.3}", r.mean_awake),
            r.final_awake.to_string(),
            format!("{:.6}", r.tail_time_s),
            r.left_region.to_string(),
        ]);
        row
    });
    super::write_csv(&args.out.join("results.csv"), &CSV_HEADER, rows)?;

    let points: Vec<ChartPoint> = results
        .iter()
        .filter(|(_, r)| r.deviation.is_finite())
        .map(|(spec, r)| ChartPoint {
            label: r.name.clone(),
            deviation: r.deviation,
            speedup: ratio(brute, r.time_s),
            violations: r.violations.total(),
            kind: kind_of(spec),
        })
        .collect();
    let title = format!(
        "DIKU, {} spheres: speed-up over brute force vs deviation",
        args.spheres
    );
    let spec = ChartSpec {
        title: &title,
        x_label: "deviation from the reference (sphere radii, RMS of the mean error)",
        y_label: "speed-up over brute force",
        width: 1000,
        height: 640,
        log_y: false,
    };
    let write = |name: &str, bytes: &[u8]| {
        let path = args.out.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    write("chart.svg", report::svg(&points, &spec).as_bytes())?;
    write("chart.png", &report::png(&points, &spec))?;
    let front = report::pareto_front(&points, true);
    println!("\nPareto front (zero violations), by deviation:");
    let mut f: Vec<&ChartPoint> = front.iter().map(|&i| &points[i]).collect();
    f.sort_by(|a, b| a.deviation.total_cmp(&b.deviation));
    for p in f {
        println!(
            "  {:<16} deviation {:>8.4} r, speed-up {:>6.2}x",
            p.label, p.deviation, p.speedup
        );
    }
    // The best zero-violation configuration with and without repair, against stock
    // Rapier (the target: the best repaired one >= 3x stock at N >= 1,200).
    let stock_dev = results
        .iter()
        .find(|(s, _)| s.name == "stock Rapier")
        .map(|(_, r)| r.deviation);
    for repaired in [false, true] {
        let best = results
            .iter()
            .filter(|(s, r)| {
                matches!(s.mode, Mode::Layer(_))
                    && s.repair == repaired
                    && r.violations.total() == 0
            })
            .min_by(|a, b| a.1.time_s.total_cmp(&b.1.time_s));
        let what = if repaired { "repaired" } else { "unrepaired" };
        match best {
            Some((_, r)) => println!(
                "best zero-violation {what}: {:<16} {:>6.2}x stock, {:>6.2}x brute force, deviation {:.3} r (stock {:.3} r)",
                r.name,
                ratio(stock, r.time_s),
                ratio(brute, r.time_s),
                r.deviation,
                stock_dev.unwrap_or(f64::NAN)
            ),
            None => println!("best zero-violation {what}: none ran without violations"),
        }
    }
    let left: usize = results
        .iter()
        .map(|(_, r)| r.left_region)
        .max()
        .unwrap_or(0);
    println!(
        "\nspheres that left the plane (worst run): {left}\nwrote {}/results.csv, chart.svg, chart.png in {:.1} s",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configuration_lists() {
        let all = parse_configs("all").unwrap().0;
        assert_eq!(all.len(), 1 + 3 + 1 + 128 + 128);
        assert_eq!(all[0].name, "reference");
        let some = parse_configs("brute, C-----F+repair,127").unwrap().0;
        let names: Vec<&str> = some.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names[..2], ["reference", "brute force"]);
        assert!(some[2].repair && !some[3].repair);
        assert_eq!(kind_of(&some[2]), PointKind::Repaired);
        assert_eq!(kind_of(&some[1]), PointKind::BruteForce);
        assert_eq!(kind_of(&RunSpec::stock()), PointKind::StockRapier);
        assert!(parse_configs("bogus").unwrap_err().contains("bogus"));
    }
}
