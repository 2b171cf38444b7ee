//! The analysis's passes on rayon's threads against the same passes in order
//! (`docs/results.md`, "The analysis under threads"). Built with the `parallel`
//! feature (without it both worlds run the same serial code: a control).
//!
//! Two identical worlds of the sphere pile, each with an observe-only layer
//! subscribed to the contact events (`--events all`: every kind, so proximity
//! tracking), are stepped in lockstep, the order alternating
//! every step: in one the analysis may put its passes on rayon's threads, in the
//! other it may not (`rapier_contact_graph::coherence::set_parallel_analysis`, switched
//! before each world's step). Each part of the step is timed in wall-clock time: the
//! layer's own work (pre-step and analysis) is reported against the other world's, and
//! against Rapier's step. Checked every step: the event streams are the same, event
//! for event; at the end the poses are the same bit for bit.
//!
//! ```text
//! cargo bench --bench analysis_threads --features parallel -- 5000 --repeats 5
//! cargo bench --bench analysis_threads --features parallel -- 5000 --monitor --preset reliable
//! ```

use std::time::Instant;

use clap::Parser;
use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::coherence::set_parallel_analysis;
use rapier_contact_graph::events::{Event, Filter, KindSet};
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Receiver, WorldMut, WorldView};
use rcg_scenes as scenes;

const SEED: u64 = 1;

#[derive(Parser)]
#[command(about = "The analysis's passes on rayon's threads against the same in order")]
struct Args {
    /// Pile sizes (spheres).
    #[arg(default_values_t = [1000, 5000])]
    sizes: Vec<usize>,
    /// Steps per run (dt = 0.01 s).
    #[arg(long, default_value_t = 400)]
    steps: usize,
    /// Runs per size (min / median / max are printed).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// The layers' speed-ups: observe (none) or reliable (`SpeedUps::reliable_sleep()`).
    #[arg(long, default_value = "observe")]
    preset: String,
    /// The repair monitor on both layers.
    #[arg(long)]
    monitor: bool,
    /// Subscriptions: contact (starts and stops, touching tracking) or all (every
    /// kind: proximity tracking, every awake pair read).
    #[arg(long, default_value = "contact")]
    events: String,
    /// cargo passes `--bench` to benches without the default harness.
    #[arg(long, hide = true)]
    bench: bool,
}

struct World {
    world: PhysicsWorld,
    layer: ContactLayer,
    rx: Receiver<Event>,
    parallel: bool,
    rapier: Vec<f64>,
    layer_time: Vec<f64>,
    events: Vec<Event>,
}

impl World {
    fn new(n: usize, parallel: bool, args: &Args) -> Self {
        let (preset, events) = (args.preset.as_str(), args.events.as_str());
        let mut layer = ContactLayer::new();
        if preset == "reliable" {
            layer
                .set_speedups(Some(SpeedUps::reliable_sleep()))
                .expect("the preset is valid");
        }
        if args.monitor {
            layer
                .set_monitor(
                    MonitorMode::Repair,
                    MonitorConfig::default(),
                    RepairConfig::default(),
                )
                .expect("valid monitor");
        }
        let rx = layer.subscribe(if events == "all" {
            Filter::all()
        } else {
            Filter::kinds(KindSet::COLLISION_EVENTS)
        });
        Self {
            world: scenes::sphere_pile(n, SEED).world,
            layer,
            rx,
            parallel,
            rapier: Vec::new(),
            layer_time: Vec::new(),
            events: Vec::new(),
        }
    }

    fn step(&mut self) {
        set_parallel_analysis(self.parallel);
        let t = Instant::now();
        self.layer.pre_step(WorldMut::from(&mut self.world));
        let pre = t.elapsed().as_secs_f64();
        let t = Instant::now();
        self.world
            .step_with_events(&self.layer.hooks(), self.layer.event_handler());
        self.rapier.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        self.layer.analyze(WorldView::from(&self.world));
        self.layer_time.push(pre + t.elapsed().as_secs_f64());
        self.events.clear();
        self.events.extend(self.rx.try_iter());
    }
}

fn poses(w: &PhysicsWorld) -> Vec<u32> {
    let mut out = Vec::new();
    for (_, rb) in w.bodies.iter() {
        let p = rb.position();
        let (t, r) = (p.translation, p.rotation);
        out.extend([t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f32::to_bits));
    }
    out
}

/// (parallel layer / serial layer, parallel layer / its Rapier, serial / its Rapier)
fn run(n: usize, args: &Args) -> (f64, f64, f64) {
    let mut s = World::new(n, false, args);
    let mut p = World::new(n, true, args);
    for i in 0..args.steps {
        if i % 2 == 0 {
            s.step();
            p.step();
        } else {
            p.step();
            s.step();
        }
        if s.events != p.events {
            eprintln!("analysis_threads: the event streams differ at step {i}");
            std::process::exit(1);
        }
    }
    set_parallel_analysis(true);
    if poses(&s.world) != poses(&p.world) {
        eprintln!("analysis_threads: the poses differ");
        std::process::exit(1);
    }
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    (
        sum(&p.layer_time) / sum(&s.layer_time),
        sum(&p.layer_time) / sum(&p.rapier),
        sum(&s.layer_time) / sum(&s.rapier),
    )
}

fn spread(mut v: Vec<f64>, fmt: impl Fn(f64) -> String) -> String {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    format!("{} / {} / {}", fmt(v[0]), fmt(v[n / 2]), fmt(v[n - 1]))
}

fn main() {
    let args = Args::parse();
    if args.repeats == 0 || args.steps == 0 {
        eprintln!("analysis_threads: --repeats and --steps must be at least 1");
        std::process::exit(2);
    }
    println!(
        "the layer's work with its passes on rayon's threads / in order, {} steps, preset {}, \
         {} run(s) each (min / median / max), wall clock, events {}{}, parallel feature: {}",
        args.steps,
        args.preset,
        args.repeats,
        args.events,
        if args.monitor { ", repair monitor" } else { "" },
        cfg!(feature = "parallel")
    );
    println!(
        "| N | layer's work, threads / in order | layer / Rapier, threads | layer / Rapier, in order | events and poses |"
    );
    println!("|---|---|---|---|---|");
    for &n in &args.sizes {
        let runs: Vec<_> = (0..args.repeats)
            .map(|k| {
                eprintln!("analysis_threads: N = {n}, run {} ...", k + 1);
                run(n, &args)
            })
            .collect();
        let r = |x: f64| format!("{x:.3}");
        let p = |x: f64| format!("{:.1} %", 100.0 * x);
        println!(
            "| {n} | {} | {} | {} | identical |",
            spread(runs.iter().map(|x| x.0).collect(), r),
            spread(runs.iter().map(|x| x.1).collect(), p),
            spread(runs.iter().map(|x| x.2).collect(), p),
        );
    }
}
