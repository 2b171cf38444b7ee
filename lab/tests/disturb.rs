//! The disturbance runner (`rcg-lab disturb`) on small piles: the scenes disturb the
//! pile without sleep, `reliable_sleep()` holds the settled pile, the command line
//! refuses bad input, and a whole small run writes its CSV files.

use clap::Parser;
use rcg_lab::cli::{Cli, Command};
use rcg_lab::disturb::judge::{BALL_SPEED, BALL_X, DISPLACED, HELD, KE};
use rcg_lab::disturb::{configs, reference, run, SCENES};
use rcg_scenes::disturb::{thrown_ball, DisturbParams};

fn small(boxes: usize, at: u64, after: u64) -> DisturbParams {
    DisturbParams {
        boxes,
        seed: 0,
        at,
        after,
    }
}

#[test]
fn the_thrown_ball_displaces_boxes_without_sleep() {
    let r = run(&reference(), thrown_ball, &small(40, 150, 60)).unwrap();
    let o = r.outcome;
    assert!(o[DISPLACED] > 0.0, "{o:?}");
    assert!(o[BALL_X].is_finite() && o[BALL_SPEED].is_finite() && o[KE] >= 0.0);
    assert_eq!((o[HELD], r.held_at_disturbance), (0.0, 0));
}

#[test]
fn reliable_sleep_holds_the_settled_pile_before_the_disturbance() {
    let reliable = configs()
        .into_iter()
        .find(|c| c.short == "reliable")
        .unwrap();
    for (name, build) in SCENES {
        let r = run(&reliable, build, &small(40, 300, 5)).unwrap();
        assert!(
            r.held_at_disturbance >= 36,
            "{name}: {}",
            r.held_at_disturbance
        );
    }
}

#[test]
fn bad_arguments_are_usage_errors() {
    for bad in [
        &["rcg-lab", "disturb", "--seeds", "1"][..],
        &["rcg-lab", "disturb", "--seeds", "x"],
        &["rcg-lab", "disturb", "--boxes", "0"],
        &["rcg-lab", "disturb", "--at", "0"],
        &["rcg-lab", "disturb", "--after", "-3"],
        &["rcg-lab", "disturb", "--scenes", "thrown_ball,nope"],
        &["rcg-lab", "disturb", "--scenes", ","],
        &["rcg-lab", "disturb", "--bogus"],
    ] {
        let e = Cli::try_parse_from(bad).unwrap_err();
        assert_eq!(e.exit_code(), 2, "{bad:?}: {e}");
    }
    let cli = Cli::try_parse_from(["rcg-lab", "disturb", "--quick", "--seeds", "4"]).unwrap();
    match cli.command {
        Command::Disturb(a) => {
            assert_eq!(a.sizes(), (150, 4));
            assert_eq!(a.scenes.0.len(), 3);
        }
        other => panic!("{other:?}"),
    }
    let cli = Cli::try_parse_from(["rcg-lab", "disturb", "--scenes", "paddle"]).unwrap();
    match cli.command {
        Command::Disturb(a) => {
            assert_eq!(a.sizes(), (250, 8));
            assert_eq!(a.scenes.0[0].0, "paddle");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_small_run_writes_both_csv_files() {
    let out = std::env::temp_dir().join(format!("rcg_disturb_{}", std::process::id()));
    let out_s = out.to_str().unwrap();
    let cli = Cli::try_parse_from([
        "rcg-lab",
        "disturb",
        "--scenes",
        "thrown_ball",
        "--boxes",
        "12",
        "--seeds",
        "2",
        "--at",
        "60",
        "--after",
        "30",
        "--out",
        out_s,
    ])
    .unwrap();
    let Command::Disturb(args) = cli.command else {
        panic!("not disturb")
    };
    rcg_lab::cli::disturb::run(&args).unwrap();
    let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let results = std::fs::read_to_string(out.join("results.csv")).unwrap();
    // 9 configurations (the reference, its 2 refinements, 6 judged) on 2 seeds.
    assert_eq!(runs.lines().count(), 1 + 9 * 2);
    assert!(runs.starts_with("scene,configuration,seed,boxes,held_at_disturbance,displaced,"));
    assert!(results.starts_with("scene,configuration,observable,unit,mean"));
    assert_eq!(results.lines().count(), 1 + 9 * 14);
    std::fs::remove_dir_all(&out).unwrap();
}
