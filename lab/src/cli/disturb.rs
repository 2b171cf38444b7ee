//! `rcg-lab disturb`: settled piles disturbed (a thrown ball, a removed floor segment,
//! a sweeping paddle; the DIKU scene's pile hit by a thrown sphere; the mixed bin of
//! balls and boxes hit by a heavy ball) under the reference, stock Rapier and the
//! layer's sleep presets, judged on paired seeds against the reference
//! ([`crate::disturb`]).
//!
//! ```text
//! cargo lab disturb [--scenes all|LIST] [--boxes N] [--seeds K] [--seed S]
//!                   [--at STEP] [--after STEPS] [--quick] [--configs LIST] [--out DIR]
//! ```
//! `--boxes`, `--at` and `--after` apply to every scene run; without them each scene
//! has its own ([`SCENES`]: the box piles 250 boxes, disturbed at step 300; the DIKU
//! scene 120 spheres, hit at step 1000; 200 steps after; the mixed bin 1,000 bodies,
//! hit at step 1000, 600 steps after).
//! Per scene and seed: the reference (Rapier's defaults, sleep off), its two
//! refinements (8 solver iterations; half the time step), then stock Rapier, the
//! layer with `SpeedUps::default()`, `reliable_sleep()`, `reliable_sleep()` with the
//! monitor repairing, and `papers_fastest()` (`--configs` picks some of these by their
//! short names, or names `rel-rest50`, run only when named: `reliable_sleep()` holding
//! a body after 0.5 s at rest; the reference and its refinements always run, since
//! they make the tolerance). Prints per scene a table of each
//! observable's mean over seeds and, per configuration, its paired difference from
//! the reference with the 95 % interval's half width and the verdict (`=` equivalent,
//! `+`/`-` differs upwards/downwards, `?` undecided, `!` not finite). Writes
//! `runs.csv` (one row per run) and `results.csv` (one row per scene, configuration
//! and observable) into `DIR` (default `target/disturb`). `--quick` (CI): 3 seeds,
//! 150 boxes, the DIKU scene's 120 spheres, a mixed bin of 120 bodies. Runs are
//! sequential: the step times are of one core.

use std::path::PathBuf;

use rcg_scenes::disturb::DisturbParams;

use crate::disturb::judge::{judge, tolerances, Comparison, Verdict};
use crate::disturb::{self, configs, reference, refinements, Config, Outcome, SceneSpec};
use crate::disturb::{COUNT, OBSERVABLES, SCENES};

/// Options of `rcg-lab disturb`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scenes: `all` or a comma list of thrown_ball, support_removed, paddle,
    /// diku_throw, bin_hit.
    #[arg(long, value_name = "all|LIST", default_value = "all", value_parser = parse_scenes)]
    pub scenes: Scenes,
    /// Bodies in each pile, boxes or spheres (default: the scene's, 250 boxes, 120
    /// spheres, 1,000 mixed bodies; with --quick 150 boxes, 120 spheres, 120 mixed).
    #[arg(long, visible_alias = "bodies", value_name = "N", value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub boxes: Option<u64>,
    /// Paired seeds S, S+1, ... (at least 2; default 8; 3 with --quick).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(2..=1000))]
    pub seeds: Option<u64>,
    /// The first seed.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// The disturbance step (settling before it; steps of 0.01 s; default: the
    /// scene's, 300 for the box piles, 1000 for diku_throw and bin_hit).
    #[arg(long, value_name = "STEP", value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    pub at: Option<u64>,
    /// Steps run after the disturbance (default: the scene's, 200; 600 for bin_hit).
    #[arg(long, value_name = "STEPS", value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    pub after: Option<u64>,
    /// The CI settings: 3 seeds, 150 boxes, 120 spheres and 120 mixed bodies unless
    /// given.
    #[arg(long)]
    pub quick: bool,
    /// The configurations judged: `all` or a comma list of their short names (stock,
    /// sleep, reliable, rel-nogroup, reliable+rep, fastest; and, only when named,
    /// rel-rest50: `reliable_sleep()` holding a body after 0.5 s at rest). The
    /// reference and its refinements always run.
    #[arg(long, value_name = "all|LIST", default_value = "all", value_parser = parse_configs)]
    pub configs: Configs,
    /// Directory for runs.csv and results.csv.
    #[arg(long, value_name = "DIR", default_value = "target/disturb")]
    pub out: PathBuf,
}

/// The configurations judged, in report order.
#[derive(Clone, Debug)]
pub struct Configs(pub Vec<Config>);

/// The configurations of a `--configs` value, by short name; unknown names and an
/// empty list are errors.
pub fn parse_configs(list: &str) -> Result<Configs, String> {
    let all = configs();
    if list == "all" {
        return Ok(Configs(all));
    }
    let known: Vec<Config> = all.into_iter().chain(disturb::named_only()).collect();
    let mut out: Vec<Config> = Vec::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let found = known.iter().find(|c| c.short == item).ok_or(format!(
            "unknown configuration `{item}` (one of: {})",
            known.iter().map(|c| c.short).collect::<Vec<_>>().join(", ")
        ))?;
        if !out.iter().any(|c| c.short == found.short) {
            out.push(found.clone());
        }
    }
    if out.is_empty() {
        return Err("no configuration given".into());
    }
    // In the order of the full run, whatever the list's.
    out.sort_by_key(|c| known.iter().position(|k| k.short == c.short));
    Ok(Configs(out))
}

/// The scenes to run, in report order.
#[derive(Clone, Debug)]
pub struct Scenes(pub Vec<SceneSpec>);

/// The scenes of a `--scenes` value; unknown names and an empty list are errors.
pub fn parse_scenes(list: &str) -> Result<Scenes, String> {
    if list == "all" {
        return Ok(Scenes(SCENES.to_vec()));
    }
    let mut out = Vec::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let found = SCENES
            .iter()
            .find(|s| s.name == item)
            .ok_or(format!("unknown scene `{item}`"))?;
        if !out.iter().any(|s: &SceneSpec| s.name == found.name) {
            out.push(*found);
        }
    }
    if out.is_empty() {
        return Err("no scene given".into());
    }
    Ok(Scenes(out))
}

impl Args {
    /// The number of seeds after `--quick`.
    pub fn seeds(&self) -> u64 {
        self.seeds.unwrap_or(if self.quick { 3 } else { 8 })
    }

    /// A scene's parameters (seed `--seed`) after `--quick` and the options given.
    pub fn params(&self, scene: &SceneSpec) -> DisturbParams {
        let d = scene.defaults;
        let quick = if self.quick {
            scene.quick_bodies
        } else {
            d.boxes
        };
        DisturbParams {
            boxes: self.boxes.map_or(quick, |b| b as usize),
            seed: self.seed,
            at: self.at.unwrap_or(d.at),
            after: self.after.unwrap_or(d.after),
        }
    }
}

/// One configuration's runs on one scene.
struct Ensemble {
    config: Config,
    outcomes: Vec<Outcome>,
    held_at: Vec<usize>,
}

/// The columns of `runs.csv` before the observables.
pub const RUNS_HEADER: [&str; 5] = [
    "scene",
    "configuration",
    "seed",
    "boxes",
    "held_at_disturbance",
];
/// The columns of `results.csv`.
pub const RESULTS_HEADER: [&str; 11] = [
    "scene",
    "configuration",
    "observable",
    "unit",
    "mean",
    "reference_mean",
    "diff",
    "diff_lo",
    "diff_hi",
    "tolerance",
    "verdict",
];

/// Runs the disturbance scenes: tables on standard output, CSV files in `--out`.
pub fn run(args: &Args) -> Result<(), String> {
    let k = args.seeds();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut all: Vec<Config> = vec![reference()];
    all.extend(refinements());
    all.extend(args.configs.0.iter().cloned());
    let bar = super::progress(args.scenes.0.len() * all.len() * k as usize);
    let mut runs_rows = Vec::new();
    let mut results_rows = Vec::new();
    let started = std::time::Instant::now();
    for spec in &args.scenes.0 {
        let (scene, base) = (spec.name, args.params(spec));
        let mut ensembles: Vec<Ensemble> = Vec::new();
        for config in &all {
            let mut e = Ensemble {
                config: config.clone(),
                outcomes: Vec::new(),
                held_at: Vec::new(),
            };
            for seed in args.seed..args.seed + k {
                bar.set_message(format!("{scene} {}", config.short));
                let params = DisturbParams { seed, ..base };
                let r = disturb::run(config, spec.build, &params)?;
                let mut row = vec![
                    scene.to_string(),
                    config.name.to_string(),
                    seed.to_string(),
                    base.boxes.to_string(),
                    r.held_at_disturbance.to_string(),
                ];
                row.extend(r.outcome.iter().map(|v| v.to_string()));
                runs_rows.push(row);
                e.outcomes.push(r.outcome);
                e.held_at.push(r.held_at_disturbance);
                bar.inc(1);
            }
            ensembles.push(e);
        }
        let reference = &ensembles[0].outcomes;
        let refined: Vec<&[Outcome]> = ensembles[1..3].iter().map(|e| &e.outcomes[..]).collect();
        let tol = tolerances(&refined, reference).map_err(|e| e.to_string())?;
        let mut judged = Vec::new();
        for e in &ensembles {
            let c = judge(&e.outcomes, reference, &tol).map_err(|e| e.to_string())?;
            for (j, cmp) in c.iter().enumerate() {
                results_rows.push(result_row(spec, e.config.name, j, cmp, reference));
            }
            judged.push((e, c));
        }
        bar.suspend(|| print_table(spec, &base, k, &judged, &tol));
    }
    bar.finish_and_clear();
    let mut header: Vec<&str> = RUNS_HEADER.to_vec();
    header.extend(OBSERVABLES.iter().map(|o| o.key));
    super::write_csv(&args.out.join("runs.csv"), &header, runs_rows)?;
    super::write_csv(&args.out.join("results.csv"), &RESULTS_HEADER, results_rows)?;
    println!(
        "wrote {}/runs.csv and results.csv; {:.1} s in all",
        args.out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// An observable's unit in a scene: `displaced` counts the scene's pile bodies.
fn unit(scene: &SceneSpec, j: usize) -> &'static str {
    match OBSERVABLES[j].unit {
        "boxes" => scene.bodies,
        u => u,
    }
}

/// A row of `results.csv`.
fn result_row(
    scene: &SceneSpec,
    config: &str,
    j: usize,
    cmp: &Comparison,
    reference: &[Outcome],
) -> Vec<String> {
    let ref_mean = reference.iter().map(|o| o[j]).sum::<f64>() / reference.len() as f64;
    let (d, lo, hi) = match &cmp.interval {
        Ok(iv) => (iv.mean, iv.lo, iv.hi),
        Err(_) => (f64::NAN, f64::NAN, f64::NAN),
    };
    vec![
        scene.name.into(),
        config.into(),
        OBSERVABLES[j].key.into(),
        unit(scene, j).into(),
        cmp.mean.to_string(),
        ref_mean.to_string(),
        d.to_string(),
        lo.to_string(),
        hi.to_string(),
        cmp.tolerance.to_string(),
        cmp.verdict.symbol().trim().to_string(),
    ]
}

/// A number in about five significant characters.
fn num(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() {
        format!("{x}")
    } else if a >= 100.0 || x == x.trunc() && a < 1e5 {
        format!("{x:.0}")
    } else if a >= 10.0 {
        format!("{x:.1}")
    } else if a >= 0.1 {
        format!("{x:.2}")
    } else {
        format!("{x:.3}")
    }
}

/// The table of one scene: per observable a line of means and a line of paired
/// differences `±` the 95 % interval's half width, with the verdict.
fn print_table(
    scene: &SceneSpec,
    p: &DisturbParams,
    k: u64,
    judged: &[(&Ensemble, Vec<Comparison>)],
    tol: &[f64; COUNT],
) {
    const W: usize = 16;
    let held_ref = judged
        .iter()
        .map(|(e, _)| {
            let mean = e.held_at.iter().sum::<usize>() as f64 / e.held_at.len().max(1) as f64;
            format!("{:>W$}", num(mean))
        })
        .collect::<String>();
    println!(
        "\n{}: {} {}, {k} seeds from {}, disturbance at step {}, {} steps after",
        scene.name, p.boxes, scene.bodies, p.seed, p.at, p.after
    );
    let mut head = format!("{:<22}{:>8}", "observable [unit]", "tol");
    for (e, _) in judged {
        head.push_str(&format!("{:>W$}", e.config.short));
    }
    println!("{head}");
    println!("{:<30}{held_ref}", "held at disturbance");
    for (j, o) in OBSERVABLES.iter().enumerate() {
        if judged[0].1[j].mean.is_nan() {
            continue;
        }
        let label = format!("{} [{}]", o.key, unit(scene, j));
        let t = if tol[j].is_finite() {
            num(tol[j])
        } else {
            String::new()
        };
        let mut means = format!("{label:<22}{t:>8}");
        let mut diffs = format!("{:<30}", "  diff ± 95%");
        for (i, (_, c)) in judged.iter().enumerate() {
            means.push_str(&format!("{:>W$}", num(c[j].mean)));
            let cell = match (&c[j].interval, i) {
                (_, 0) => String::new(),
                (Ok(iv), _) => format!(
                    "{}{}±{} {}",
                    if iv.mean >= 0.0 { "+" } else { "" },
                    num(iv.mean),
                    num((iv.hi - iv.lo) / 2.0),
                    c[j].verdict.symbol()
                ),
                (Err(_), _) => format!("n/a {}", c[j].verdict.symbol()),
            };
            diffs.push_str(&format!("{cell:>W$}"));
        }
        println!("{means}");
        println!("{diffs}");
    }
    let mut line = format!("{:<30}", "verdict");
    for (i, (_, c)) in judged.iter().enumerate() {
        let differs: Vec<&str> = (0..COUNT)
            .filter(|&j| !judged[0].1[j].mean.is_nan())
            .filter(|&j| !matches!(c[j].verdict, Verdict::Equivalent | Verdict::Reported))
            .map(|j| OBSERVABLES[j].key)
            .collect();
        let cell = if i == 0 {
            "-".to_string()
        } else if differs.is_empty() {
            "equivalent".to_string()
        } else {
            format!("{} differ", differs.len())
        };
        line.push_str(&format!("{cell:>W$}"));
    }
    println!("{line}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_are_picked_by_short_name_in_the_full_runs_order() {
        assert_eq!(parse_configs("all").unwrap().0, configs());
        let picked = parse_configs("fastest, stock,stock").unwrap().0;
        let shorts: Vec<&str> = picked.iter().map(|c| c.short).collect();
        assert_eq!(shorts, ["stock", "fastest"]);
        assert!(parse_configs("nope").unwrap_err().contains("nope"));
        assert!(parse_configs(" , ").is_err());
    }

    #[test]
    fn a_named_only_configuration_runs_when_named_and_not_under_all() {
        let all = parse_configs("all").unwrap().0;
        assert!(all.iter().all(|c| c.short != "rel-rest50"));
        let picked = parse_configs("rel-rest50,reliable").unwrap().0;
        let shorts: Vec<&str> = picked.iter().map(|c| c.short).collect();
        assert_eq!(shorts, ["reliable", "rel-rest50"]);
    }
}
