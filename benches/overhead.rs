//! What observing costs: the contact-graph layer, observe-only, against plain Rapier on
//! the same pile (`docs/results.md`, "Overhead of the observe-only layer").
//!
//! For each scene and size two identical worlds are built and stepped in lockstep:
//! - *plain*: `world.step()` only;
//! - *layered*: what `ContactLayer::step` does, timed in two parts: Rapier's step (with
//!   the layer's hooks and event handler) and the layer's own work (`pre_step` and
//!   `analyze`), with the subscriptions asked for, their receivers drained every step.
//!
//! The order alternates every step (plain first, then layered first) so that machine
//! noise (a shared 2-core box) hits both alike; every step is timed in thread CPU time,
//! or in wall-clock time with `--clock wall`. Only ratios within one run mean anything;
//! absolute times are for orientation. Each configuration runs `--repeats` times:
//! min / median / max of the ratios are printed, and beside them each world's median,
//! 99th-percentile (nearest rank) and worst step of the last run, in ms.
//!
//! *Parallel mode*: built with the crate's `parallel` feature (`rapier3d/parallel`),
//! Rapier steps both worlds on rayon's global pool (as many threads as rayon gives,
//! `RAYON_NUM_THREADS` to choose) and the clock is the wall clock (the default then:
//! thread CPU time would miss the pool's workers). Both worlds are built the same way,
//! so the ratio is the layer's cost over Rapier with the same threads.
//!
//! Subscriptions (`--events`):
//! - `contact` (default): contact starts and stops and sensor entries and exits, what
//!   a user who wants "who touches what" subscribes to. The layer then follows Rapier's
//!   own collision events (touching tracking, its default).
//! - `all`: every kind, proximity and persist events included: every awake pair is
//!   read every step (proximity tracking, while that subscription lasts).
//! - `none`: no subscription (queries only).
//!
//! `--tracking proximity` asks for proximity tracking whatever the subscriptions.
//!
//! ```text
//! cargo bench --bench overhead                                  # spheres, N = 1000 and 5000
//! cargo bench --bench overhead -- --scene mixed 1000            # 1,000 balls and boxes
//! cargo bench --bench overhead -- --events all --repeats 3      # proximity and persist
//! cargo bench --bench overhead -- --sensor 5000                # with a sensor over a quarter of the bin
//! cargo bench --bench overhead -- 20000 --steps 300 --tail 100  # 20,000 spheres
//! cargo bench --bench overhead --features parallel -- --repeats 5   # parallel mode
//! ```
//! The default 600 steps (6 simulated seconds at dt = 0.01) cover the fall and the
//! settling of the pile; the last `--tail` steps are also reported on their own as the
//! "settled" phase.

use std::hint::black_box;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use cpu_time::ThreadTime;
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, Vector};
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::events::{Event, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, Receiver, WorldMut, WorldView};
use rcg_scenes as scenes;

const SEED: u64 = 1;

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum SceneArg {
    /// `sphere_pile(N)`: N spheres dropped into a bin (Rapier sleeps almost none).
    Spheres,
    /// `mixed_pile(N)`: the same with every second body a box.
    Mixed,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum EventsArg {
    /// Contact started / stopped, sensor started / stopped.
    Contact,
    /// Every kind (proximity and persist included).
    All,
    /// No subscription.
    None,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum TrackingArg {
    /// The layer's default: touching tracking where nothing needs every pair.
    Touching,
    /// Proximity tracking whatever the subscriptions.
    Proximity,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum ClockArg {
    /// Thread CPU time (single-threaded builds only: it misses rayon's workers).
    Cpu,
    /// Wall-clock time (the default with the `parallel` feature).
    Wall,
}

/// The clock when none is asked for: wall clock under `parallel`.
const DEFAULT_CLOCK: ClockArg = if cfg!(feature = "parallel") {
    ClockArg::Wall
} else {
    ClockArg::Cpu
};

#[derive(Parser)]
#[command(about = "What the observe-only layer costs over plain Rapier")]
struct Args {
    /// Pile sizes.
    #[arg(default_values_t = [1000, 5000])]
    sizes: Vec<usize>,
    /// Scenes (repeatable).
    #[arg(long = "scene", value_enum, default_values_t = [SceneArg::Spheres])]
    scenes: Vec<SceneArg>,
    /// Subscriptions.
    #[arg(long, value_enum, default_value_t = EventsArg::Contact)]
    events: EventsArg,
    /// Tracking asked for.
    #[arg(long, value_enum, default_value_t = TrackingArg::Touching)]
    tracking: TrackingArg,
    /// Steps per run (dt = 0.01 s).
    #[arg(long, default_value_t = 600)]
    steps: usize,
    /// Steps at the end counted as the settled phase.
    #[arg(long, default_value_t = 200)]
    tail: usize,
    /// Runs per configuration (min / median / max are printed).
    #[arg(long, default_value_t = 1)]
    repeats: usize,
    /// Adds a sensor to the bin (a box over one quarter of the floor, 1 m high,
    /// without a body): the bodies inside it hold geometric edges.
    #[arg(long)]
    sensor: bool,
    /// The clock steps are timed with.
    #[arg(long, value_enum, default_value_t = DEFAULT_CLOCK)]
    clock: ClockArg,
    /// cargo passes `--bench` to benches without the default harness.
    #[arg(long, hide = true)]
    bench: bool,
}

/// Per-step thread CPU times, in seconds.
#[derive(Default)]
struct Samples {
    plain: Vec<f64>,
    rapier: Vec<f64>,
    layer: Vec<f64>,
}

/// One run's figures.
struct Run {
    /// Layered / plain over the whole run and over the tail.
    whole: f64,
    settled: f64,
    /// The layer's own work / Rapier's step in the layered world (sums).
    share_whole: f64,
    share_settled: f64,
    identical: bool,
    /// Each world's steps (plain, layered: Rapier's step and the layer's work), in
    /// seconds: median, 99th percentile, worst.
    steps_plain: [f64; 3],
    steps_layered: [f64; 3],
    touching_at_end: bool,
    awake_plain: usize,
    awake_layered: usize,
    edges: usize,
    events: u64,
}

fn build(scene: SceneArg, n: usize, sensor: bool) -> PhysicsWorld {
    let mut world = match scene {
        SceneArg::Spheres => scenes::sphere_pile(n, SEED).world,
        SceneArg::Mixed => scenes::mixed_pile(n, SEED).world,
    };
    if sensor {
        let q = scenes::pile::inner_half_width(n) / 2.0;
        world.insert_collider(
            ColliderBuilder::cuboid(q, 0.5, q)
                .translation(Vector::new(q, 0.5, q))
                .sensor(true),
            None,
        );
    }
    world
}

/// The clock of the run (`--clock`), set once in `main`.
static CLOCK: std::sync::OnceLock<ClockArg> = std::sync::OnceLock::new();

fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    match CLOCK.get().copied().unwrap_or(DEFAULT_CLOCK) {
        ClockArg::Cpu => {
            let t0 = ThreadTime::now();
            let out = f();
            (out, t0.elapsed().as_secs_f64())
        }
        ClockArg::Wall => {
            let t0 = Instant::now();
            let out = f();
            (out, t0.elapsed().as_secs_f64())
        }
    }
}

/// Median, 99th percentile (nearest rank) and maximum of per-step times.
fn step_quantiles(v: &[f64]) -> [f64; 3] {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return [0.0; 3];
    }
    let rank = |q: f64| v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
    [v[v.len() / 2], rank(0.99), v[v.len() - 1]]
}

/// `ContactLayer::step`, with Rapier's part and the layer's timed apart; the
/// receivers drained as a user would.
fn layered_step(
    world: &mut PhysicsWorld,
    layer: &mut ContactLayer,
    receivers: &[Receiver<Event>],
    events: &mut u64,
) -> (f64, f64) {
    let ((), pre) = timed(|| layer.pre_step(WorldMut::from(&mut *world)));
    let ((), rapier) = timed(|| world.step_with_events(&layer.hooks(), layer.event_handler()));
    let ((), analysis) = timed(|| {
        black_box(layer.analyze(WorldView::from(&*world)));
        for r in receivers {
            for e in r.try_iter() {
                black_box(e);
                *events += 1;
            }
        }
    });
    (rapier, pre + analysis)
}

/// Poses and velocities of every body, compared bit for bit, in handle order.
fn bit_identical(a: &PhysicsWorld, b: &PhysicsWorld) -> bool {
    fn bits(w: &PhysicsWorld) -> Vec<u32> {
        let mut out = Vec::with_capacity(w.bodies.len() * 15);
        for (h, rb) in w.bodies.iter() {
            let (i, g) = h.into_raw_parts();
            out.extend([i, g]);
            let p = rb.position();
            let (v, av) = (rb.linvel(), rb.angvel());
            let r = p.rotation;
            let t = p.translation;
            for x in [
                t.x, t.y, t.z, r.x, r.y, r.z, r.w, v.x, v.y, v.z, av.x, av.y, av.z,
            ] {
                out.push(x.to_bits());
            }
        }
        out
    }
    bits(a) == bits(b)
}

fn run(scene: SceneArg, n: usize, args: &Args) -> Run {
    let mut plain = build(scene, n, args.sensor);
    let mut layered = build(scene, n, args.sensor);
    let mut layer = ContactLayer::new();
    if args.tracking == TrackingArg::Proximity {
        layer.set_tracking(Tracking::Proximity);
    }
    let receivers: Vec<Receiver<Event>> = match args.events {
        EventsArg::None => Vec::new(),
        EventsArg::All => vec![layer.subscribe(Filter::all())],
        EventsArg::Contact => vec![layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS))],
    };
    let mut s = Samples::default();
    let mut events = 0;
    for i in 0..args.steps {
        let (tp, (tr, tl)) = if i % 2 == 0 {
            let tp = timed(|| plain.step()).1;
            (
                tp,
                layered_step(&mut layered, &mut layer, &receivers, &mut events),
            )
        } else {
            let tl = layered_step(&mut layered, &mut layer, &receivers, &mut events);
            (timed(|| plain.step()).1, tl)
        };
        s.plain.push(tp);
        s.rapier.push(tr);
        s.layer.push(tl);
    }
    let sum = |v: &[f64], r: std::ops::Range<usize>| v[r].iter().sum::<f64>();
    let tail = args.steps - args.tail.min(args.steps)..args.steps;
    let all = 0..args.steps;
    let ratio = |r: std::ops::Range<usize>| {
        (sum(&s.rapier, r.clone()) + sum(&s.layer, r.clone())) / sum(&s.plain, r)
    };
    let share = |r: std::ops::Range<usize>| sum(&s.layer, r.clone()) / sum(&s.rapier, r);
    Run {
        whole: ratio(all.clone()),
        settled: ratio(tail.clone()),
        share_whole: share(all),
        share_settled: share(tail),
        identical: bit_identical(&plain, &layered),
        steps_plain: step_quantiles(&s.plain),
        steps_layered: step_quantiles(
            &s.rapier
                .iter()
                .zip(&s.layer)
                .map(|(r, l)| r + l)
                .collect::<Vec<_>>(),
        ),
        touching_at_end: layer.analysis().coherence().tracking() == Tracking::Touching,
        awake_plain: plain.islands.num_active_bodies(),
        awake_layered: layered.islands.num_active_bodies(),
        edges: layer.analysis().stats().edges,
        events,
    }
}

/// "min / median / max" of `f` over the runs.
fn spread(runs: &[Run], f: impl Fn(&Run) -> f64, fmt: impl Fn(f64) -> String) -> String {
    let mut v: Vec<f64> = runs.iter().map(f).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => "-".into(),
        1 => fmt(v[0]),
        n => format!("{} / {} / {}", fmt(v[0]), fmt(v[n / 2]), fmt(v[n - 1])),
    }
}

fn main() {
    let args = Args::parse();
    if cfg!(debug_assertions) {
        eprintln!("overhead: warning, debug assertions are on; use `cargo bench`");
    }
    if args.repeats == 0 || args.steps == 0 {
        eprintln!("overhead: --repeats and --steps must be at least 1");
        std::process::exit(2);
    }
    CLOCK.get_or_init(|| args.clock);
    if cfg!(feature = "parallel") && args.clock == ClockArg::Cpu {
        eprintln!("overhead: warning, thread CPU time misses rayon's workers; use --clock wall");
    }
    println!(
        "observe-only layer / plain Rapier, {} steps (settled: last {}), events {:?}, \
         tracking asked {:?}, {} run(s) each (min / median / max), {}, {}{}",
        args.steps,
        args.tail.min(args.steps),
        args.events,
        args.tracking,
        args.repeats,
        threads(),
        match args.clock {
            ClockArg::Cpu => "thread CPU time",
            ClockArg::Wall => "wall clock",
        },
        if args.sensor {
            ", a sensor in the bin"
        } else {
            ""
        }
    );
    println!(
        "| scene | N | tracking at end | layered / plain, whole run | layered / plain, settled \
         | layer / Rapier, whole | layer / Rapier, settled | step ms plain: median · p99 · max \
         | step ms layered: median · p99 · max | awake plain · layered | edges | events | trajectories |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut differ = false;
    for &scene in &args.scenes {
        for &n in &args.sizes {
            let runs: Vec<Run> = (0..args.repeats)
                .map(|k| {
                    eprintln!("overhead: {scene:?} N = {n}, run {} ...", k + 1);
                    run(scene, n, &args)
                })
                .collect();
            let r = |x: f64| format!("{x:.3}");
            let p = |x: f64| format!("{:.1} %", 100.0 * x);
            let last = &runs[runs.len() - 1];
            let identical = runs.iter().all(|r| r.identical);
            differ |= !identical;
            let ms =
                |q: [f64; 3]| format!("{:.2} · {:.2} · {:.2}", 1e3 * q[0], 1e3 * q[1], 1e3 * q[2]);
            println!(
                "| {scene:?} | {n} | {} | {} | {} | {} | {} | {} | {} | {} · {} | {} | {} | {} |",
                if last.touching_at_end {
                    "touching"
                } else {
                    "proximity"
                },
                spread(&runs, |x| x.whole, r),
                spread(&runs, |x| x.settled, r),
                spread(&runs, |x| x.share_whole, p),
                spread(&runs, |x| x.share_settled, p),
                ms(last.steps_plain),
                ms(last.steps_layered),
                last.awake_plain,
                last.awake_layered,
                last.edges,
                last.events,
                if identical { "bit-identical" } else { "DIFFER" },
            );
        }
    }
    if differ {
        eprintln!("overhead: trajectories differ between the plain and the layered run");
        std::process::exit(1);
    }
}

/// Which threads Rapier steps on.
fn threads() -> String {
    #[cfg(feature = "parallel")]
    {
        // Rayon's global pool: `RAYON_NUM_THREADS` threads, else one per core.
        let threads = std::env::var("RAYON_NUM_THREADS")
            .ok()
            .and_then(|n| n.parse::<usize>().ok())
            .filter(|&n| n > 0)
            .or_else(|| std::thread::available_parallelism().ok().map(|n| n.get()))
            .unwrap_or(1);
        format!("parallel (rayon, {threads} threads)")
    }
    #[cfg(not(feature = "parallel"))]
    {
        "single-threaded".to_string()
    }
}
