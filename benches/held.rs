//! What held bodies cost (`docs/ARCHITECTURE.md`, §7 "Held bodies"): a speed-ups
//! preset (`SpeedUps::reliable_sleep()` unless `--preset` says otherwise, and
//! optionally the repair monitor) against stock Rapier on the same piles, stepped in
//! lockstep.
//!
//! For each scene two identical worlds are built and stepped alternately (stock first
//! on even steps, the layer first on odd ones), each step timed in thread CPU time
//! (in the settled phase, batches of `--batch` steps, alternating likewise):
//! - *stock*: `world.step()`, Rapier's own sleep;
//! - *held*: `ContactLayer::step` with the preset: `reliable` (the default),
//!   `SpeedUps::reliable_sleep()`, the paper's sleepy objects, subgroups and fixation
//!   with warm start; `fastest`, `SpeedUps::papers_fastest()`; `observe`, no speed-ups
//!   (the observe-only layer, for comparison).
//!
//! Reported per scene, as ratios within the run (absolute times for orientation only):
//! the whole run, the settled phase (the last `--tail` steps) per step, and for each
//! world the first step from which 95% of the dynamic bodies stay held or asleep.
//! A game sees the worst step, not the mean: each world's worst step and 99th
//! percentile step (nearest rank) are reported too, in ms and as ratios held/stock,
//! against the target that held bodies are judged by, a worst step at most
//! [`WORST_STEP_TARGET`] × stock's (met or not on the median ratio over the repeats),
//! with the step each run's worst was at (a layer's first analysis of a world built in
//! contact falls on step 0, a burst of holds later). These come from the steps timed one by one, the first `--steps` − `--tail` (all of
//! them with `--batch 1`); the settled batches only give a mean per step and are left
//! out (a settled step of either world is far cheaper than a falling one).
//! After the run, the held world is timed once more beside its *floor* (see
//! [`floor_of`]): the same bodies where they are, the held ones fixed from the start
//! (out of Rapier's active set) and no layer, in batches alternating, both worlds
//! small: what Rapier alone charges for the moving bodies left, apart from the layer
//! and the held bodies Rapier keeps in its active set.
//!
//! Scenes, each `name` or `name:size`: `boxes` (500 boxes in stacks: stock Rapier
//! sleeps them), `pyramid` (40 rows, 820 boxes: stock sleeps it too), `spheres` (the
//! 1,000-sphere pile in a bin, which stock Rapier leaves partly awake) and `mixed`
//! (the same bin with 1,000 bodies, every second one a box); on request the same
//! scenes at another size, e.g. `mixed:4000` (the bin of 4,000 mixed bodies) or
//! `spheres:5000` (`spheres5000` and `mixed4000` are aliases); the 20,000-body pile is
//! `spheres:20000` (alias `spheres20000`; e.g. `--steps 400 --tail 100 --repeats 1`,
//! a few minutes).
//!
//! Built with the crate's `parallel` feature Rapier steps on rayon's threads and every
//! step is timed in wall-clock time instead (thread CPU time would miss the pool's
//! workers).
//!
//! `--hit STEP` throws the lab's `bin_hit` ball into both worlds of a bin (`mixed`,
//! `spheres`) before step `STEP` and reports what it displaced in each and the time
//! from the hit on (`held/hit.rs`).
//!
//! `--phases N` prints instead each scene's `N` slowest held steps, each split into
//! the layer's pre-step, Rapier's step and the analysis, with what the pre-step
//! applied and stock's step beside it: where a spike comes from (with `--hit`, the
//! ball is thrown as above).
//!
//! `--first-step N` times instead the first step of `N` fresh worlds of each scene,
//! stock's and the held world's in turn (`held/first.rs`): the pyramid's worst step
//! is its first, one sample a run.
//!
//! ```text
//! cargo bench --bench held                        # all scenes, 1,000 steps, 3 repeats
//! cargo bench --bench held -- --scene boxes --repeats 5
//! cargo bench --bench held -- --monitor           # with the repair monitor
//! cargo bench --bench held -- --scene mixed:4000 --repeats 3   # the 4,000-body bin
//! cargo bench --bench held -- --scene spheres20000 --steps 400 --tail 100 --repeats 1
//! cargo bench --bench held -- --preset fastest    # SpeedUps::papers_fastest()
//! cargo bench --bench held -- --scene boxes --phases 10   # the slowest steps, split
//! cargo bench --bench held -- --scene mixed --hit 1000 --steps 1600   # hit at 10 s
//! RCG_HELD_ALONE=held cargo bench --bench held -- --scene boxes --steps 200000
//!                                                  # one settled world alone, for `perf`
//! RCG_HELD_ALONE=held RCG_HELD_ALONE_FROM=100 cargo bench --bench held -- --scene mixed
//!     --steps 200 --tail 100                       # the same world while it falls
//! cargo bench --bench held -- --scene mixed --windows 200   # the run in windows
//! cargo bench --bench held -- --scene pyramid --first-step 40   # first steps alone
//! ```

use clap::Parser;
/// Thread CPU time single-threaded; wall clock when Rapier runs on rayon's threads.
#[cfg(not(feature = "parallel"))]
use cpu_time::ThreadTime as StepClock;
use rapier3d::prelude::{PhysicsWorld, RigidBodyType};
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;
use rcg_scenes as scenes;
#[cfg(feature = "parallel")]
use std::time::Instant as StepClock;

#[path = "held/first.rs"]
mod first;
#[path = "held/hit.rs"]
mod hit;
#[path = "held/phases.rs"]
mod phases;

#[derive(Parser)]
#[command(about = "Held bodies against stock Rapier's sleeping bodies")]
struct Args {
    /// Scenes to run, each `name` or `name:size` (boxes, pyramid, spheres, mixed;
    /// e.g. mixed:4000); boxes, pyramid, spheres and mixed at their default sizes
    /// when omitted.
    #[arg(long = "scene")]
    scenes: Vec<String>,
    /// Steps per run (dt = 0.01 s).
    #[arg(long, default_value_t = 1000)]
    steps: usize,
    /// Steps at the end counted as the settled phase.
    #[arg(long, default_value_t = 200)]
    tail: usize,
    /// Settled steps timed together (see `run`).
    #[arg(long, default_value_t = 10)]
    batch: usize,
    /// Runs per scene (min / median / max are printed).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Add the repair monitor to the held world.
    #[arg(long)]
    monitor: bool,
    /// The held world's layer: reliable (`SpeedUps::reliable_sleep()`), fastest
    /// (`SpeedUps::papers_fastest()`), reliable-nowrites (`reliable_sleep()` with
    /// `release_written` off) or observe (no speed-ups).
    #[arg(long, default_value = "reliable")]
    preset: String,
    /// Instead of the table: the `N` slowest steps of the held world of each scene,
    /// each split into the layer's pre-step, Rapier's step and the analysis, with
    /// stock's step beside it (`--repeats` runs of `--steps` steps, all timed one by
    /// one).
    #[arg(long, value_name = "N")]
    phases: Option<usize>,
    /// Also print, for each run, the steps in windows of `N`: stock's and the held
    /// world's time in each and their ratio (where the whole run's ratio comes from:
    /// the fall, the settling, the hit). Only the steps timed one by one.
    #[arg(long, value_name = "N")]
    windows: Option<usize>,
    /// Throw the heavy ball of the lab's `bin_hit` scene into both worlds before step
    /// `STEP` (the bins `mixed` and `spheres` only; before the settled tail) and report
    /// the bodies displaced from the hit to the end in each world (see `held/hit.rs`).
    #[arg(long, value_name = "STEP")]
    hit: Option<usize>,
    /// Instead of the table: the first step of `N` fresh worlds of each scene, stock's
    /// and the held world's in turn, their ratios' min / quartiles / max (a world
    /// built in contact: its first step is the run's worst, see `held/first.rs`).
    #[arg(long, value_name = "N")]
    first_step: Option<usize>,
    /// cargo passes `--bench` to benches without the default harness.
    #[arg(long, hide = true)]
    bench: bool,
}

/// The held world's worst step may be at most this many times stock's worst step.
const WORST_STEP_TARGET: f64 = 1.25;

/// A scene by name (`name` or `name:size`, see the module doc).
fn build(scene: &str) -> Option<PhysicsWorld> {
    let scene = match scene {
        "spheres5000" => "spheres:5000",
        "spheres20000" => "spheres:20000",
        "mixed4000" => "mixed:4000",
        s => s,
    };
    let (name, size) = match scene.split_once(':') {
        Some((name, size)) => (name, Some(size.parse::<usize>().ok().filter(|&n| n > 0)?)),
        None => (scene, None),
    };
    Some(match name {
        "boxes" => scenes::box_pile(size.unwrap_or(500), 1).world,
        "pyramid" => scenes::stability::pyramid::pyramid_of(size.unwrap_or(40)).world,
        "spheres" => scenes::sphere_pile(size.unwrap_or(1000), 1).world,
        "mixed" => scenes::mixed_pile(size.unwrap_or(1000), 1).world,
        _ => return None,
    })
}

/// The held world's speed-ups (`--preset`); `None` for the observe-only layer.
fn config(preset: &str) -> Option<Option<SpeedUps>> {
    match preset {
        "reliable" => Some(Some(SpeedUps::reliable_sleep())),
        "fastest" => Some(Some(SpeedUps::papers_fastest())),
        "reliable-nowrites" => Some(Some(SpeedUps {
            release_written: false,
            ..SpeedUps::reliable_sleep()
        })),
        "observe" => Some(None),
        _ => None,
    }
}

/// Dynamic bodies (fixated ones included) at the start: the scenes have no other
/// moving bodies and none is added or removed.
fn dynamic_bodies(world: &PhysicsWorld) -> usize {
    world
        .bodies
        .iter()
        .filter(|(_, rb)| rb.is_dynamic())
        .count()
}

struct Run {
    /// Seconds per step, per world (in a settled batch, the batch's mean).
    stock: Vec<f64>,
    held: Vec<f64>,
    /// The leading steps of `stock` and `held` timed one by one (the others were
    /// timed in batches).
    timed_alone: usize,
    /// The "moving bodies only" limit of each step: stock's time × the bodies Rapier
    /// integrates in the held world / those it integrates in the stock world (`None`
    /// when stock integrates nothing).
    limit: Vec<Option<f64>>,
    /// First step from which 95% of the bodies stayed still, per world.
    still_from: [Option<usize>; 2],
    awake_end: [usize; 2],
    fixated_end: usize,
    parked_end: usize,
    violations: usize,
    /// After the run: the held world and its *floor* stepped in batches alternately,
    /// seconds per step (held, floor).
    floor: (f64, f64),
    /// With `--hit`: what the hit did, `[stock, held]`.
    hit: Option<[hit::Outcome; 2]>,
}

/// Rapier's floor for a held world: a fresh world of the scene with every body where
/// the held world has it, the held bodies fixed before its first step (so never in
/// Rapier's active set, as no change after a step can achieve) and the others dynamic
/// with their velocities and sleep settings; no layer. What Rapier alone charges for
/// the held world's moving bodies.
fn floor_of(scene: &str, held: &PhysicsWorld, layer: &ContactLayer) -> PhysicsWorld {
    let mut f = build(scene).expect("scene");
    let s = layer.speedups();
    for (h, rb) in held.bodies.iter() {
        let Some(fb) = f.bodies.get_mut(h) else {
            continue;
        };
        fb.set_position(*rb.position(), false);
        *fb.activation_mut() = *rb.activation();
        if s.is_some_and(|s| s.is_fixated(h)) {
            fb.set_body_type(RigidBodyType::Fixed, false);
        } else {
            fb.set_linvel(rb.linvel(), false);
            fb.set_angvel(rb.angvel(), false);
        }
    }
    f
}

/// The held world's layer: the speed-ups of `--preset` ([`config`]), and the repair
/// monitor with `--monitor`.
fn held_layer(args: &Args) -> ContactLayer {
    let mut layer = ContactLayer::new();
    let speedups = config(&args.preset).expect("preset checked in main");
    layer.speedups_mut().set(speedups).expect("valid speed-ups");
    if args.monitor {
        layer
            .monitor_mut()
            .set(
                MonitorMode::Repair,
                MonitorConfig::default(),
                RepairConfig::default(),
            )
            .expect("valid monitor");
    }
    layer
}

fn run(scene: &str, args: &Args) -> Run {
    let mut stock = build(scene).expect("scene");
    let mut held = build(scene).expect("scene");
    let n = dynamic_bodies(&stock);
    let mut layer = held_layer(args);
    let mut r = Run {
        stock: Vec::with_capacity(args.steps),
        held: Vec::with_capacity(args.steps),
        timed_alone: 0,
        limit: Vec::with_capacity(args.steps),
        still_from: [None; 2],
        awake_end: [0; 2],
        fixated_end: 0,
        parked_end: 0,
        violations: 0,
        floor: (0.0, 0.0),
        hit: None,
    };
    let mut hit = args.hit.map(|at| hit::Hit::new(at, &stock));
    // Falling and settling: each step timed. The settled tail: batches of `--batch`
    // steps timed as one (a settled step costs about a microsecond, of the order of
    // two reads of the thread CPU clock, which would otherwise weigh on both worlds
    // alike and pull the ratio towards 1); each step of a batch is counted at the
    // batch's mean. Stock first on even timed units (steps, then batches).
    let settled_from = args.steps - args.tail;
    let mut i = 0;
    let mut unit = 0usize;
    let mut awake_s = Vec::new();
    let mut awake_h = Vec::new();
    while i < args.steps {
        if let Some(h) = hit.as_mut() {
            h.before_step(i, [&mut stock, &mut held]);
        }
        let b = if i >= settled_from {
            args.batch.max(1).min(args.steps - i)
        } else {
            1
        };
        let stock_first = unit.is_multiple_of(2);
        unit += 1;
        awake_s.clear();
        awake_h.clear();
        let mut v = 0;
        let time_stock = |w: &mut PhysicsWorld, awake: &mut Vec<usize>| {
            let t = StepClock::now();
            for _ in 0..b {
                w.step();
                awake.push(w.islands.num_active_bodies());
            }
            t.elapsed().as_secs_f64() / b as f64
        };
        let mut time_held = |w: &mut PhysicsWorld, l: &mut ContactLayer, awake: &mut Vec<usize>| {
            let t = StepClock::now();
            for _ in 0..b {
                let s = l.step(w);
                v += s.violations;
                awake.push(s.awake_bodies);
            }
            t.elapsed().as_secs_f64() / b as f64
        };
        let (ts, th) = if stock_first {
            let ts = time_stock(&mut stock, &mut awake_s);
            (ts, time_held(&mut held, &mut layer, &mut awake_h))
        } else {
            let th = time_held(&mut held, &mut layer, &mut awake_h);
            (time_stock(&mut stock, &mut awake_s), th)
        };
        r.violations += v;
        if b == 1 && r.timed_alone == i {
            r.timed_alone += 1;
        }
        for (&a_s, &a_h) in awake_s.iter().zip(&awake_h) {
            r.stock.push(ts);
            r.held.push(th);
            // Still: not integrated by Rapier (asleep, or held by the layer).
            r.limit
                .push((a_s > 0).then(|| ts * a_h as f64 / a_s as f64));
            for (k, awake) in [a_s, a_h].into_iter().enumerate() {
                if 20 * n.saturating_sub(awake) >= 19 * n {
                    r.still_from[k].get_or_insert(i);
                } else {
                    r.still_from[k] = None;
                }
            }
            i += 1;
        }
    }
    r.awake_end = [
        stock.islands.num_active_bodies(),
        layer.analysis().stats().awake_bodies,
    ];
    r.fixated_end = layer.speedups().map_or(0, |s| s.fixated().count());
    r.parked_end = layer.speedups().map_or(0, |s| s.stats().parked);
    r.hit = hit
        .as_ref()
        .and_then(|h| Some([h.outcome(0, &stock)?, h.outcome(1, &held)?]));
    // The floor: 100 steps to settle its fresh contacts, then `--tail` steps of each
    // world in batches of `--batch`, alternating (both are small now).
    let mut floor = floor_of(scene, &held, &layer);
    if let Some(h) = &hit {
        let fixed = |b| layer.speedups().is_some_and(|s| s.is_fixated(b));
        hit::add_ball(&mut floor, &held, h, h.ball(1).is_some_and(fixed));
    }
    for _ in 0..100 {
        floor.step();
    }
    let (mut th, mut tf) = (0.0, 0.0);
    let b = args.batch.max(1);
    // Thread CPU seconds of `b` calls of `step`.
    let batch = |step: &mut dyn FnMut()| {
        let t = StepClock::now();
        for _ in 0..b {
            step();
        }
        t.elapsed().as_secs_f64()
    };
    for unit in 0..args.tail.div_ceil(b) {
        let mut held_step = || {
            layer.step(&mut held);
        };
        let mut floor_step = || floor.step();
        if unit % 2 == 0 {
            th += batch(&mut held_step);
            tf += batch(&mut floor_step);
        } else {
            tf += batch(&mut floor_step);
            th += batch(&mut held_step);
        }
    }
    let steps = (args.tail.div_ceil(b) * b) as f64;
    r.floor = (th / steps, tf / steps);
    r
}

fn sum(v: &[f64]) -> f64 {
    v.iter().sum()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn spread(mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    let m = v[v.len() / 2];
    format!("{:.3} / {:.3} / {:.3}", v[0], m, v[v.len() - 1])
}

/// The worst and the 99th percentile (nearest rank) of step times; `None` for no
/// steps.
fn worst_and_p99(v: &[f64]) -> Option<(f64, f64)> {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let worst = *v.last()?;
    let rank = (v.len() * 99).div_ceil(100);
    Some((worst, v[rank - 1]))
}

/// Worst and p99 step of each world in one run, seconds: `[stock, held]` of
/// `(worst, p99)`, over the steps timed one by one.
fn step_tails(r: &Run) -> Option<[(f64, f64); 2]> {
    let n = r.timed_alone;
    Some([worst_and_p99(&r.stock[..n])?, worst_and_p99(&r.held[..n])?])
}

/// The worst-step and p99-step lines of a scene, and whether it meets
/// [`WORST_STEP_TARGET`] on the median ratio.
fn print_step_tails(runs: &[Run]) {
    let tails: Option<Vec<[(f64, f64); 2]>> = runs.iter().map(step_tails).collect();
    let Some(tails) = tails else {
        println!("  worst / p99 step: n/a (no step timed alone: --tail = --steps)");
        return;
    };
    let ms = |v: Vec<f64>| spread(v.into_iter().map(|x| x * 1e3).collect());
    for (name, pick) in [("worst step", 0), ("p99 step  ", 1)] {
        let of = |t: &(f64, f64)| if pick == 0 { t.0 } else { t.1 };
        println!(
            "  {name}  held/stock  {}   ms stock {}   held {}",
            spread(tails.iter().map(|[s, h]| of(h) / of(s)).collect()),
            ms(tails.iter().map(|[s, _]| of(s)).collect()),
            ms(tails.iter().map(|[_, h]| of(h)).collect())
        );
    }
    // Where each run's worst steps were: the layer's first analysis, a burst of
    // holds, or a step of the awake phase.
    let at = |v: &[f64]| {
        v.iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i)
    };
    let n = runs[0].timed_alone;
    let steps: Vec<String> = runs
        .iter()
        .map(|r| format!("{} · {}", at(&r.stock[..n]), at(&r.held[..n])))
        .collect();
    println!(
        "  worst at step, stock · held, by run: {}",
        steps.join(", ")
    );
    let m = median(tails.iter().map(|[s, h]| h.0 / s.0).collect());
    println!(
        "  target: worst step ≤ {WORST_STEP_TARGET:.2}× stock's   {} (median {m:.3}, over the first {} steps)",
        if m <= WORST_STEP_TARGET { "met" } else { "NOT met" },
        runs[0].timed_alone
    );
}

fn main() {
    let args = Args::parse();
    let chosen: Vec<String> = if args.scenes.is_empty() {
        ["boxes", "pyramid", "spheres", "mixed"]
            .map(String::from)
            .to_vec()
    } else {
        args.scenes.clone()
    };
    assert!(args.repeats > 0, "--repeats must be positive");
    assert!(
        args.tail > 0 && args.tail <= args.steps,
        "--tail must be in 1..=steps"
    );
    // Diagnostics: one world alone, settled, stepped `--steps` times (`RCG_HELD_ALONE=stock`
    // or `held`), its mean thread CPU time per step; for profiles.
    if config(&args.preset).is_none() {
        eprintln!(
            "held: unknown preset {:?} (reliable, fastest, observe)",
            args.preset
        );
        std::process::exit(2);
    }
    for scene in &chosen {
        if build(scene).is_none() {
            eprintln!(
                "held: unknown scene {scene:?} (boxes, pyramid, spheres, mixed, each with an optional :size)"
            );
            std::process::exit(2);
        }
    }
    if let Some(at) = args.hit {
        let alone = std::env::var("RCG_HELD_ALONE").is_ok();
        let bad = chosen.iter().find(|s| !hit::applies_to(s));
        if at >= args.steps - args.tail || alone || bad.is_some() {
            eprintln!(
                "held: --hit STEP needs STEP < --steps − --tail, the bins (mixed, spheres) only, and not RCG_HELD_ALONE"
            );
            std::process::exit(2);
        }
    }
    if let Ok(which) = std::env::var("RCG_HELD_ALONE") {
        alone(&chosen[0], &which, &args);
        return;
    }
    if let Some(n) = args.first_step.filter(|&n| n > 0) {
        for scene in &chosen {
            first::run(
                scene,
                n,
                || build(scene).expect("scene"),
                || held_layer(&args),
            );
        }
        return;
    }
    if let Some(top) = args.phases {
        for scene in &chosen {
            for _ in 0..args.repeats {
                let (Some(mut stock), Some(mut held)) = (build(scene), build(scene)) else {
                    unreachable!("scenes checked above");
                };
                println!("{scene}, {} steps:", args.steps);
                let hit = args.hit.map(|at| hit::Hit::new(at, &stock));
                phases::run(
                    &mut stock,
                    &mut held,
                    &mut held_layer(&args),
                    args.steps,
                    top,
                    hit,
                );
            }
        }
        return;
    }
    let preset = match args.preset.as_str() {
        "reliable" => "reliable_sleep() (sleep + subgroup + fixate + warm start)",
        "fastest" => "papers_fastest() (+ zero + damp)",
        "reliable-nowrites" => "reliable_sleep() without release_written",
        _ => "the observe-only layer (no speed-ups)",
    };
    println!(
        "held: {preset}{} vs stock Rapier, {} steps, settled = last {}, thread CPU time, {} repeats",
        if args.monitor { " + repair monitor" } else { "" },
        args.steps,
        args.tail,
        args.repeats
    );
    for scene in &chosen {
        let runs: Vec<Run> = (0..args.repeats).map(|_| run(scene, &args)).collect();
        let whole: Vec<f64> = runs.iter().map(|r| sum(&r.held) / sum(&r.stock)).collect();
        let tail = |v: &[f64]| sum(&v[v.len() - args.tail..]) / args.tail as f64;
        let settled: Vec<f64> = runs
            .iter()
            .map(|r| tail(&r.held) / tail(&r.stock))
            .collect();
        let r = &runs[0];
        let us = |v: Vec<f64>| spread(v.into_iter().map(|x| x * 1e6).collect());
        println!("\n{scene}:");
        println!(
            "  whole run   held/stock  {}   (stock {:.3} s, held {:.3} s, first run)",
            spread(whole.clone()),
            sum(&r.stock),
            sum(&r.held)
        );
        println!("  settled     held/stock  {}", spread(settled));
        if let Some(w) = args.windows.filter(|&w| w > 0) {
            for r in &runs {
                print_windows(r, w, args.steps - args.tail);
            }
        }
        if let Some(at) = args.hit {
            let hits: Option<Vec<_>> = runs
                .iter()
                .map(|r| Some((r.hit?, (&r.stock[..], &r.held[..]))))
                .collect();
            match hits {
                Some(h) => hit::print(at, &h, &whole),
                None => println!("  hit: n/a (no ball found at the end)"),
            }
        }
        // Against the moving bodies alone: only where stock integrates something in
        // every settled step (a pile stock cannot put to sleep).
        let limits: Option<Vec<f64>> = runs
            .iter()
            .map(|r| {
                let tail_limit: Option<Vec<f64>> = r.limit[r.limit.len() - args.tail..]
                    .iter()
                    .copied()
                    .collect();
                tail_limit.map(|l| sum(&r.held[r.held.len() - args.tail..]) / sum(&l))
            })
            .collect();
        match limits {
            Some(l) => println!("  settled     held/moving-bodies-only limit  {}", spread(l)),
            None => println!("  settled     moving-bodies-only limit: n/a (stock sleeps)"),
        }
        println!(
            "  settled µs/step         stock {}   held {}",
            us(runs.iter().map(|r| tail(&r.stock)).collect()),
            us(runs.iter().map(|r| tail(&r.held)).collect())
        );
        print_step_tails(&runs);
        println!(
            "  after, beside Rapier's floor (held bodies fixed from the start, no layer): held/floor {}   µs/step held {}   floor {}",
            spread(runs.iter().map(|r| r.floor.0 / r.floor.1).collect()),
            us(runs.iter().map(|r| r.floor.0).collect()),
            us(runs.iter().map(|r| r.floor.1).collect())
        );
        let when = |s: Option<usize>| match s {
            Some(i) => format!("{:.2} s", i as f64 * scenes::DT as f64),
            None => "never".into(),
        };
        println!(
            "  95% still from          stock {}   held {}",
            when(r.still_from[0]),
            when(r.still_from[1])
        );
        println!(
            "  at the end              stock {} awake   held {} awake, {} fixated ({} parked), {} violations",
            r.awake_end[0], r.awake_end[1], r.fixated_end, r.parked_end, r.violations
        );
    }
}

/// One run's steps in windows of `w` (up to step `upto`, the steps timed one by one):
/// stock's and the held world's milliseconds in each, and held / stock.
fn print_windows(r: &Run, w: usize, upto: usize) {
    let mut line = String::from("  windows, from step: ms stock / held = ratio:");
    let mut i = 0;
    while i < upto.min(r.stock.len()) {
        let e = (i + w).min(upto).min(r.stock.len());
        let (s, h) = (sum(&r.stock[i..e]), sum(&r.held[i..e]));
        line += &format!("  {i}: {:.1} / {:.1} = {:.2}", s * 1e3, h * 1e3, h / s);
        i = e;
    }
    println!("{line}");
}

/// One settled world alone (see `main`).
fn alone(scene: &str, which: &str, args: &Args) {
    let mut w = build(scene).expect("scene");
    let mut layer = held_layer(args);
    let mut step = |w: &mut PhysicsWorld| match which {
        "stock" => w.step(),
        _ => {
            layer.step(w);
        }
    };
    // Timed from step `RCG_HELD_ALONE_FROM` (1,000 unless set: the settled world;
    // 0 or 100 profile the fall).
    let from = std::env::var("RCG_HELD_ALONE_FROM")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    for _ in 0..from {
        step(&mut w);
    }
    let t = StepClock::now();
    for _ in 0..args.steps {
        step(&mut w);
    }
    println!(
        "{scene} {which} alone: {:.3} µs/step",
        t.elapsed().as_secs_f64() * 1e6 / args.steps as f64
    );
}
