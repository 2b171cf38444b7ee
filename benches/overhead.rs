//! Overhead of the contact-graph layer over plain Rapier (docs/ARCHITECTURE.md §6: ≤ 3% of Rapier's
//! step time on a 5,000-sphere pile, ratio measured within one run).
//!
//! For each pile size N two identical worlds are built with `scenes::sphere_pile(N, 1)`
//! and stepped in lockstep:
//! - *plain*: `world.step()` only;
//! - *layered*: `world.step()` then `layer.analyze(WorldView::from(&world))` — the same
//!   work as `ContactLayer::step`, with the Rapier part and the analysis timed apart.
//!
//! The order alternates every step (plain first, then layered first) so that machine
//! noise (a shared 2-core box) hits both runs alike. Only ratios within one run are
//! meaningful; absolute times are printed for orientation only.
//!
//! Usage:
//! ```text
//! cargo bench --bench overhead                      # N = 1000 and 5000, 600 steps
//! cargo bench --bench overhead -- 1000              # only N = 1000
//! cargo bench --bench overhead -- 5000 --steps 300  # other step count
//! cargo bench --bench overhead -- --touching        # touching tracking (Rapier's events)
//! ```
//! With `--touching` the layered world is stepped as a user stepping Rapier
//! themselves would: `pre_step` (timed with the analysis), Rapier's step with the
//! layer's hooks and event handler, then `analyze`.
//! The default 600 steps (6 simulated seconds at dt = 0.01) cover the fall and the
//! settling of the pile, when (almost) every body is awake; the last 200 steps are
//! also reported on their own as the "settled" phase.

use std::hint::black_box;
use std::time::Instant;

use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes as scenes;

const DEFAULT_SIZES: [usize; 2] = [1000, 5000];
const DEFAULT_STEPS: usize = 600;
/// Length of the tail reported separately (the settled phase).
const TAIL: usize = 200;
const SEED: u64 = 1;

struct Args {
    sizes: Vec<usize>,
    steps: usize,
    /// Touching tracking (Rapier's collision events drive the graph) instead of
    /// proximity tracking.
    touching: bool,
}

fn parse_args() -> Args {
    let mut sizes = Vec::new();
    let mut steps = DEFAULT_STEPS;
    let mut touching = false;
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            // cargo passes `--bench` to harness = false benches.
            "--bench" => {}
            "--touching" => touching = true,
            "--steps" => {
                let v = it.next().expect("--steps needs a value");
                steps = v.parse().expect("--steps: not a number");
            }
            s if s.starts_with("--steps=") => {
                steps = s["--steps=".len()..]
                    .parse()
                    .expect("--steps: not a number");
            }
            s if s.starts_with('-') => eprintln!("overhead: ignoring option {s}"),
            s => match s.parse::<usize>() {
                Ok(n) if n > 0 => sizes.push(n),
                _ => eprintln!("overhead: ignoring argument {s:?} (expected a pile size)"),
            },
        }
    }
    if sizes.is_empty() {
        sizes = DEFAULT_SIZES.to_vec();
    }
    assert!(steps > 0, "--steps must be positive");
    Args {
        sizes,
        steps,
        touching,
    }
}

/// Per-step timings in seconds.
#[derive(Default)]
struct Samples {
    plain: Vec<f64>,
    rapier: Vec<f64>,
    analysis: Vec<f64>,
}

struct Outcome {
    n: usize,
    steps: usize,
    samples: Samples,
    identical: bool,
    bodies: usize,
    awake_plain: usize,
    awake_layered: usize,
    nodes: usize,
    edges: usize,
    touching: usize,
    groups: usize,
    wall: f64,
}

fn plain_step(world: &mut PhysicsWorld) -> f64 {
    let t0 = Instant::now();
    world.step();
    t0.elapsed().as_secs_f64()
}

fn layered_step(world: &mut PhysicsWorld, layer: &mut ContactLayer) -> (f64, f64) {
    if layer.touching_in_effect() {
        // Touching tracking: the pre-step flags new colliders, Rapier's step reports
        // touch transitions to the layer's event handler.
        let t0 = Instant::now();
        layer.pre_step((&mut *world).into());
        let t1 = Instant::now();
        world.step_with_events(&layer.hooks(), layer.event_handler());
        let t2 = Instant::now();
        let stats = layer.analyze(WorldView::from(&*world));
        let t3 = Instant::now();
        black_box(stats);
        return (
            (t2 - t1).as_secs_f64(),
            (t1 - t0).as_secs_f64() + (t3 - t2).as_secs_f64(),
        );
    }
    let t0 = Instant::now();
    world.step();
    let t1 = Instant::now();
    let stats = layer.analyze(WorldView::from(&*world));
    let t2 = Instant::now();
    black_box(stats);
    ((t1 - t0).as_secs_f64(), (t2 - t1).as_secs_f64())
}

/// Poses and velocities of every body, compared bit for bit, in handle order.
fn bit_identical(a: &PhysicsWorld, b: &PhysicsWorld) -> bool {
    fn bits(w: &PhysicsWorld) -> Vec<u32> {
        let mut out = Vec::with_capacity(w.bodies.len() * 13);
        for (h, rb) in w.bodies.iter() {
            let (i, g) = h.into_raw_parts();
            out.extend([i, g]);
            let p = rb.position();
            let v = rb.linvel();
            let av = rb.angvel();
            for x in [
                p.translation.x,
                p.translation.y,
                p.translation.z,
                p.rotation.x,
                p.rotation.y,
                p.rotation.z,
                p.rotation.w,
                v.x,
                v.y,
                v.z,
                av.x,
                av.y,
                av.z,
            ] {
                out.push(x.to_bits());
            }
        }
        out
    }
    bits(a) == bits(b)
}

fn run(n: usize, steps: usize, touching: bool) -> Outcome {
    let wall0 = Instant::now();
    let mut plain = scenes::sphere_pile(n, SEED).world;
    let mut layered = scenes::sphere_pile(n, SEED).world;
    let mut layer = ContactLayer::new();
    if touching {
        layer.set_tracking(rapier_contact_graph::coherence::Tracking::Touching);
    }
    let mut s = Samples {
        plain: Vec::with_capacity(steps),
        rapier: Vec::with_capacity(steps),
        analysis: Vec::with_capacity(steps),
    };
    for i in 0..steps {
        let (tp, (tr, ta)) = if i % 2 == 0 {
            let tp = plain_step(&mut plain);
            (tp, layered_step(&mut layered, &mut layer))
        } else {
            let tl = layered_step(&mut layered, &mut layer);
            (plain_step(&mut plain), tl)
        };
        s.plain.push(tp);
        s.rapier.push(tr);
        s.analysis.push(ta);
    }
    let stats = layer.stats();
    let touching = layer
        .graph()
        .edges()
        .filter(|(_, e)| e.cache().touching)
        .count();
    Outcome {
        n,
        steps,
        identical: bit_identical(&plain, &layered),
        bodies: layered.bodies.len(),
        awake_plain: plain.islands.num_active_bodies(),
        awake_layered: layered.islands.num_active_bodies(),
        nodes: stats.nodes,
        edges: stats.edges,
        touching,
        groups: stats.groups.count,
        samples: s,
        wall: wall0.elapsed().as_secs_f64(),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// Figures over the steps `range` of one outcome.
struct Phase {
    steps: usize,
    plain: f64,
    rapier: f64,
    analysis: f64,
    /// Median over steps of analysis / Rapier (same step, same world).
    median_analysis_ratio: f64,
    /// Median over steps of layered / plain.
    median_layered_ratio: f64,
    max_analysis: f64,
}

impl Phase {
    fn of(s: &Samples, range: std::ops::Range<usize>) -> Phase {
        let sum = |v: &[f64]| v[range.clone()].iter().sum::<f64>();
        let idx = range.clone();
        Phase {
            steps: range.len(),
            plain: sum(&s.plain),
            rapier: sum(&s.rapier),
            analysis: sum(&s.analysis),
            median_analysis_ratio: median(
                idx.clone().map(|i| s.analysis[i] / s.rapier[i]).collect(),
            ),
            median_layered_ratio: median(
                idx.clone()
                    .map(|i| (s.rapier[i] + s.analysis[i]) / s.plain[i])
                    .collect(),
            ),
            max_analysis: idx.map(|i| s.analysis[i]).fold(0.0, f64::max),
        }
    }
    fn layered(&self) -> f64 {
        self.rapier + self.analysis
    }
}

fn ms(x: f64) -> String {
    format!("{:.1} ms", x * 1e3)
}
fn pct(x: f64) -> String {
    format!("{:.2} %", x * 100.0)
}
fn ratio(x: f64) -> String {
    format!("{x:.4}")
}

fn print_table(outcomes: &[Outcome]) {
    let phases: Vec<(Phase, Phase)> = outcomes
        .iter()
        .map(|o| {
            let steps = o.steps;
            let tail = TAIL.min(steps);
            (
                Phase::of(&o.samples, 0..steps),
                Phase::of(&o.samples, steps - tail..steps),
            )
        })
        .collect();
    let mut rows: Vec<(String, Vec<String>)> = Vec::new();
    let mut row = |name: &str, f: &dyn Fn(&Outcome, &Phase, &Phase) -> String| {
        let cells = outcomes
            .iter()
            .zip(&phases)
            .map(|(o, (all, tail))| f(o, all, tail))
            .collect();
        rows.push((name.to_string(), cells));
    };
    row("spheres", &|o, _, _| o.n.to_string());
    row("steps", &|o, _, _| o.steps.to_string());
    row("ALL STEPS", &|_, _, _| String::new());
    row("  plain total", &|_, a, _| ms(a.plain));
    row("  layered total (rapier+analysis)", &|_, a, _| {
        ms(a.layered())
    });
    row("    rapier part", &|_, a, _| ms(a.rapier));
    row("    analysis part", &|_, a, _| ms(a.analysis));
    row("  layered / plain", &|_, a, _| ratio(a.layered() / a.plain));
    row("  rapier(layered) / plain", &|_, a, _| {
        ratio(a.rapier / a.plain)
    });
    row("  analysis / rapier (sums)", &|_, a, _| {
        pct(a.analysis / a.rapier)
    });
    row("  analysis / rapier (median/step)", &|_, a, _| {
        pct(a.median_analysis_ratio)
    });
    row("  layered / plain (median/step)", &|_, a, _| {
        ratio(a.median_layered_ratio)
    });
    row("  analysis per step (mean)", &|_, a, _| {
        format!("{:.3} ms", a.analysis / a.steps as f64 * 1e3)
    });
    row("  analysis per step (max)", &|_, a, _| {
        format!("{:.3} ms", a.max_analysis * 1e3)
    });
    row("  rapier per step (mean)", &|_, a, _| {
        format!("{:.2} ms", a.rapier / a.steps as f64 * 1e3)
    });
    row("LAST STEPS (settled phase)", &|_, _, t| {
        format!("last {}", t.steps)
    });
    row("  plain total", &|_, _, t| ms(t.plain));
    row("  layered total", &|_, _, t| ms(t.layered()));
    row("  layered / plain", &|_, _, t| ratio(t.layered() / t.plain));
    row("  analysis / rapier (sums)", &|_, _, t| {
        pct(t.analysis / t.rapier)
    });
    row("  analysis / rapier (median/step)", &|_, _, t| {
        pct(t.median_analysis_ratio)
    });
    row("  layered / plain (median/step)", &|_, _, t| {
        ratio(t.median_layered_ratio)
    });
    row("  analysis per step (mean)", &|_, _, t| {
        format!("{:.3} ms", t.analysis / t.steps as f64 * 1e3)
    });
    row("AT THE END", &|_, _, _| String::new());
    row("  bodies (incl. container)", &|o, _, _| {
        o.bodies.to_string()
    });
    row("  awake bodies plain / layered", &|o, _, _| {
        format!("{} / {}", o.awake_plain, o.awake_layered)
    });
    row("  graph nodes", &|o, _, _| o.nodes.to_string());
    row("  graph edges (touching)", &|o, _, _| {
        format!("{} ({})", o.edges, o.touching)
    });
    row("  contact groups", &|o, _, _| o.groups.to_string());
    row("  identical", &|o, _, _| {
        if o.identical { "yes" } else { "NO" }.to_string()
    });
    row("  wall time of the run", &|o, _, _| {
        format!("{:.1} s", o.wall)
    });

    let w0 = rows.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
    let wc = rows
        .iter()
        .flat_map(|(_, c)| c.iter().map(|s| s.chars().count()))
        .max()
        .unwrap_or(0)
        .max(8);
    println!();
    println!("contact-graph layer overhead (sphere_pile(N, {SEED}), dt = 0.01)");
    println!("{}", "-".repeat(w0 + (wc + 3) * outcomes.len()));
    for (name, cells) in &rows {
        print!("{name:<w0$}");
        for c in cells {
            print!(" | {c:>wc$}");
        }
        println!();
    }
    println!("{}", "-".repeat(w0 + (wc + 3) * outcomes.len()));
    println!("target (docs/ARCHITECTURE.md §6): analysis / rapier <= 3.00 % at N = 5000, identical = yes");
}

fn main() {
    let args = parse_args();
    if cfg!(debug_assertions) {
        eprintln!("overhead: warning, debug assertions are on; use `cargo bench`");
    }
    let mut outcomes = Vec::new();
    for &n in &args.sizes {
        eprintln!("overhead: N = {n}, {} steps ...", args.steps);
        let o = run(n, args.steps, args.touching);
        eprintln!(
            "overhead: N = {n} done in {:.1} s (identical: {})",
            o.wall,
            if o.identical { "yes" } else { "no" }
        );
        outcomes.push(o);
    }
    print_table(&outcomes);
    if outcomes.iter().any(|o| !o.identical) {
        eprintln!("overhead: trajectories differ between the plain and the layered run");
        std::process::exit(1);
    }
}
