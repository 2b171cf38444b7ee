//! The command line of `rcg-lab diku`: its options, the configuration lists and which
//! configurations are the named ones.

use std::path::PathBuf;

use crate::measure::{Mode, RunSpec};
use crate::report::PointKind;

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
                        let b = crate::table5::combination_bits(label)
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
pub(super) fn is_named(spec: &RunSpec) -> bool {
    let named_combination = match &spec.mode {
        Mode::Layer(s) => {
            !spec.repair
                && NAMED_COMBINATIONS
                    .iter()
                    .chain([&FIXATE_ALONE])
                    .any(|&b| crate::table5::combination(b) == *s)
        }
        _ => false,
    };
    let plain = !matches!(kind_of(spec), PointKind::Combination | PointKind::Repaired);
    plain || spec.name == "contact graph +repair" || named_combination
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accuracy::ensemble::reference_double_iterations;

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
