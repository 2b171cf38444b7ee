//! # rcg-lab: the laboratory of `rapier-contact-graph`
//!
//! Everything the project measures with, kept out of the plugin a Rapier user links:
//! - [`accuracy`]: the DIKU run's measure of accuracy: chaos-robust observables,
//!   paired seed ensembles, tolerances from the reference's own discretisation error,
//!   the equivalence decision (`docs/accuracy.md`);
//! - [`measure`]: one configuration run on a scene, timed, compared against a
//!   reference, its plausibility violations counted (paper §7, Tables 4–5);
//! - [`report`]: charts of speed against accuracy with the Pareto front (plotters, SVG
//!   and PNG), and frames of a scene: Rapier's debug render coloured by body state
//!   (paper Fig. 17; tiny-skia, PNG);
//! - [`disturb`]: settled piles disturbed (a thrown ball, a removed floor segment, a
//!   paddle), judged on paired seeds against a reference without sleep;
//! - [`stability`]: the stability suite, each scene of `rcg_scenes::stability` with
//!   the switch it is built against, its control run and its reference;
//! - [`table5`]: the paper's Table 5, its seven switches by their letters and words,
//!   their 2^7 combinations and the labels (`C--ZDSF`);
//! - [`cli`]: the runners as subcommands of the one binary, `rcg-lab` (clap,
//!   indicatif, csv): `cargo lab diku`, `cargo lab disturb`, `cargo lab stability`,
//!   `cargo lab frames`.
//!
//! The scenes live in `rcg-scenes`, shared with the plugin's tests and benchmarks. Not
//! published.

#![warn(missing_docs)]

pub mod accuracy;
pub mod cli;
pub mod disturb;
pub mod measure;
pub mod report;
pub mod stability;
pub mod table5;
