//! The laboratory's command line: one binary, `rcg-lab`, with a subcommand per runner.
//!
//! ```text
//! cargo lab diku [--spheres N] [--configs default|all|quick|LIST] [--steps K] [--seed S]
//!                [--seeds K] [--screen-seeds M] [--full] [--out DIR]
//! cargo lab disturb [--scenes all|LIST] [--boxes N] [--seeds K] [--quick] [--out DIR]
//! cargo lab stability [--configs all|quick|LIST] [--scenes all|LIST] [--repair] [--out DIR]
//! cargo lab frames [--out DIR] [--every K] [--steps N] [--view side|tilted] [--size WxH] [--repair]
//! ```
//! (`cargo lab` is the workspace's alias for `cargo run --release -p rcg-lab --`;
//! `rcg-lab help SUBCOMMAND` prints each one's options.)
//!
//! # Design
//! - **[clap] (derive)** parses: each subcommand is a struct of options with their
//!   defaults and help, and the configuration and scene lists are parsed by value
//!   parsers, so a typo is a usage error (exit code 2) naming the option, before
//!   anything runs. The runners were examples parsing `std::env::args` by hand, three
//!   times over.
//! - **[indicatif]** shows progress on standard error, and nothing when that is not a
//!   terminal (CI, a pipe): the tables on standard output stay clean.
//! - **[csv]** writes the results files (quoting included); the columns are those of
//!   the hand-written CSV before.
//! - Errors of a run (a configuration the layer refuses, a file that cannot be
//!   written) are printed as `error: ...` with exit code 1.

pub mod diku;
pub mod disturb;
pub mod frames;
pub mod stability;

use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::measure::Mode;
use crate::measure::RunSpec;

/// The laboratory of rapier-contact-graph: the DIKU speed-versus-accuracy run, the
/// disturbed piles, the stability suite and frames of a scene.
#[derive(Debug, Parser)]
#[command(name = "rcg-lab", version, about, long_about = None)]
pub struct Cli {
    /// The runner.
    #[command(subcommand)]
    pub command: Command,
}

/// The runners.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The DIKU scene under every configuration: speed against accuracy on paired
    /// seed ensembles, table, CSV and chart (paper §7; `docs/accuracy.md`).
    Diku(diku::Args),
    /// Settled piles disturbed (thrown ball, removed support, paddle, a sphere thrown
    /// into the settled DIKU pile, a heavy ball into the mixed bin) under the
    /// reference, stock Rapier and the sleep presets, judged on paired seeds.
    Disturb(disturb::Args),
    /// The stability suite: every scene under the configurations, violations and
    /// deviation per scene, and whether each target's failure shows.
    Stability(stability::Args),
    /// PNG frames of the hanging-sleeper scene, bodies coloured by state (paper
    /// Fig. 17).
    Frames(frames::Args),
}

/// Parses the process' arguments and runs the subcommand: exit code 0, 2 for a usage
/// error (from clap), 1 for an error of the run.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Diku(args) => diku::run(&args),
        Command::Disturb(args) => disturb::run(&args),
        Command::Stability(args) => stability::run(&args),
        Command::Frames(args) => frames::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}

/// A progress bar of `total` steps on standard error, hidden when that is not a
/// terminal.
pub(crate) fn progress(total: usize) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template(
        "[{bar:30}] {pos}/{len} {msg:<24} {elapsed:>4} elapsed, ~{eta:>4} left",
    )
    .map(|s| s.progress_chars("#> "))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style);
    bar.enable_steady_tick(Duration::from_millis(250));
    bar
}

/// The seven switches of a layered configuration (Table 5's order) as `0`/`1` CSV fields, empty for a
/// plain Rapier run.
pub(crate) fn switch_fields(spec: &RunSpec) -> [String; 7] {
    match &spec.mode {
        Mode::Layer(s) => crate::table5::switches(s).map(|b| u8::from(b).to_string()),
        _ => std::array::from_fn(|_| String::new()),
    }
}

/// Writes `rows` under `header` as CSV at `path`.
pub(crate) fn write_csv(
    path: &std::path::Path,
    header: &[&str],
    rows: impl IntoIterator<Item = Vec<String>>,
) -> Result<(), String> {
    let fail = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(|e| fail(&e))?;
    w.write_record(header).map_err(|e| fail(&e))?;
    for row in rows {
        w.write_record(&row).map_err(|e| fail(&e))?;
    }
    w.flush().map_err(|e| fail(&e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn csv_files_keep_their_columns() {
        // The columns of the hand-written CSV files before the csv crate.
        // The DIKU run's columns changed with the accuracy measure (`docs/accuracy.md`).
        assert_eq!(
            diku::CSV_HEADER.join(","),
            "configuration,kind,cache,tweak,reduce,zero,damp,subgroup,fixate,seeds,time_s,speedup_brute,speedup_stock,accuracy,equivalent,differs,not_judged,deviation_radii,own_ulp_floor_radii,violations,hanging,launch,penetration,escape,peak_penetration_mm,resting_penetration_mm,mean_groups,mean_awake,last_second_s,left_plane"
        );
        let per_observable = diku::observable_columns();
        assert_eq!(
            per_observable.len(),
            5 * crate::accuracy::observables::COUNT
        );
        assert_eq!(
            per_observable[..5].join(","),
            "rim_ref,rim_diff,rim_lo,rim_hi,rim_tol"
        );
        assert_eq!(
            stability::CSV_HEADER.join(","),
            "scene,configuration,kind,cache,tweak,reduce,zero,damp,subgroup,fixate,monitor,deviation_radii,violations,hanging,launch,penetration,escape,peak_hang,peak_launch,peak_penetration,left_region,final_awake,time_s"
        );
        assert_eq!(
            switch_fields(&RunSpec::combination(0b100_0001)),
            ["1", "0", "0", "0", "0", "0", "1"].map(String::from)
        );
        assert_eq!(
            switch_fields(&RunSpec::stock()),
            std::array::from_fn(|_| String::new())
        );
        // Written and read back; a field with a comma or a quote is quoted.
        let path = std::env::temp_dir().join(format!("rcg_lab_csv_{}.csv", std::process::id()));
        let rows = vec![
            vec!["plain".to_string(), "1.5".to_string()],
            vec!["a, \"b\"".to_string(), "NaN".to_string()],
        ];
        write_csv(&path, &["name", "value"], rows.clone()).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with("name,value\nplain,1.5\n\"a, \"\"b\"\"\",NaN\n"),
            "{text}"
        );
        let read: Vec<Vec<String>> = csv::Reader::from_path(&path)
            .unwrap()
            .records()
            .map(|r| r.unwrap().iter().map(String::from).collect())
            .collect();
        assert_eq!(read, rows);
        std::fs::remove_file(&path).unwrap();
        let missing = std::env::temp_dir().join("no such dir/x.csv");
        assert!(write_csv(&missing, &["a"], Vec::new())
            .unwrap_err()
            .contains("cannot write"));
    }

    #[test]
    fn subcommands_parse_their_options_and_refuse_typos() {
        let cli = Cli::try_parse_from([
            "rcg-lab",
            "diku",
            "--spheres",
            "30",
            "--configs",
            "quick",
            "--steps",
            "50",
        ])
        .unwrap();
        match cli.command {
            Command::Diku(a) => {
                assert_eq!((a.spheres, a.steps, a.seed), (30, 50, 0));
                assert_eq!((a.seeds, a.screen_seeds, a.full), (8, 2, false));
                assert_eq!(a.configs.0.len(), 20);
                assert_eq!(a.configs.0[0].name, "reference");
            }
            other => panic!("{other:?}"),
        }
        for bad in [
            &["rcg-lab", "diku", "--spheres", "0"][..],
            &["rcg-lab", "diku", "--steps", "-1"],
            &["rcg-lab", "diku", "--configs", "brute,nonsense"],
            &["rcg-lab", "diku", "--bogus"],
            // Fewer than two seeds cannot give an interval: a usage error.
            &["rcg-lab", "diku", "--seeds", "1"],
            &["rcg-lab", "diku", "--screen-seeds", "0"],
            &["rcg-lab", "stability", "--scenes", "no_such_scene"],
            &["rcg-lab", "frames", "--size", "800"],
            &["rcg-lab", "frames", "--every", "0"],
            &["rcg-lab", "frames", "--view", "top"],
            &["rcg-lab"],
        ] {
            let e = Cli::try_parse_from(bad).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{bad:?}: {e}");
        }
        let cli = Cli::try_parse_from(["rcg-lab", "frames", "--size", "640x360", "--repair"]);
        match cli.unwrap().command {
            Command::Frames(a) => assert_eq!((a.size.0, a.size.1, a.repair), (640, 360, true)),
            other => panic!("{other:?}"),
        }
    }
}
