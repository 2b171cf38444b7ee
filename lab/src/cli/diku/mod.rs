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
//!
//! Cost: 3K + 1 runs of the reference, M runs per configuration, K − M more for each
//! reported one and two for its own floor; each run is `--steps` steps of the scene.

mod args;
mod csv;
mod print;
mod run;
mod summary;

pub use self::args::{kind_of, parse_configs, Args, Configs, FIXATE_ALONE, NAMED_COMBINATIONS};
pub use self::csv::{observable_columns, CSV_HEADER, RUNS_CSV_HEADER};
pub use self::run::run;
