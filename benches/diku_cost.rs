//! What the DIKU scene costs per simulated second: stock Rapier,
//! brute force and layered configurations stepped in lockstep, each beside its
//! "moving bodies only" limit.
//!
//! All worlds are the same DIKU scene (`rcg_scenes::diku`, `--spheres` spheres, 10 s at
//! dt = 0.01). Every step each world is stepped once, in an order that rotates every
//! step, and timed in thread CPU time:
//! - *stock*: `world.step()`, Rapier's defaults (its own sleep, warm start);
//! - *brute force*: the paper's: 4 solver iterations, no warm start, no contact
//!   recycling, no sleep;
//! - each `--config` (default: `------F`, fixation alone, and `C----SF`,
//!   `SpeedUps::reliable_sleep()`: the fastest configurations with no violation in the
//!   DIKU table of `docs/results.md`): `ContactLayer::step` with those speed-ups.
//!
//! The **moving-bodies-only limit** of a world is what its steps would cost if each
//! body Rapier integrates cost what it costs stock Rapier: per simulated second,
//! stock's CPU time × (the world's mean integrated bodies / stock's mean awake bodies).
//! The target: a zero-violation configuration within 10% of its limit over the
//! whole run.
//!
//! ```text
//! cargo bench --bench diku_cost                        # 1,200 spheres
//! cargo bench --bench diku_cost -- --spheres 120 --config C--ZDSF
//! ```

use clap::Parser;
use cpu_time::ThreadTime;
use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::monitor::{Monitor, MonitorConfig};
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes as scenes;

#[derive(Parser)]
#[command(about = "The DIKU scene's CPU time per simulated second, against its limit")]
struct Args {
    /// Spheres dropped on the plane.
    #[arg(long, default_value_t = 1200)]
    spheres: usize,
    /// Steps (dt = 0.01 s; 100 steps are one simulated second).
    #[arg(long, default_value_t = 1000)]
    steps: usize,
    /// The scene's jitter seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Layered configurations, as `CTRZDSF` labels (repeatable).
    #[arg(long = "config", default_values_t = ["------F".to_string(), "C----SF".to_string()])]
    configs: Vec<String>,
    /// cargo passes `--bench` to benches without the default harness.
    #[arg(long, hide = true)]
    bench: bool,
}

/// One world of the lockstep run.
struct Runner {
    name: String,
    world: PhysicsWorld,
    layer: Option<ContactLayer>,
    /// A standalone monitor on the layered worlds, outside the timed step (it reads
    /// what it needs from Rapier under the layer's default touching tracking; its
    /// reading is not timed).
    monitor: Option<Monitor>,
    /// Per-step CPU seconds and bodies Rapier integrated after the step.
    cpu: Vec<f64>,
    moving: Vec<usize>,
}

impl Runner {
    /// A world stepped by plain Rapier (no layer, no monitor).
    fn plain(name: &str, world: PhysicsWorld) -> Self {
        Runner {
            name: name.into(),
            world,
            layer: None,
            monitor: None,
            cpu: Vec::new(),
            moving: Vec::new(),
        }
    }

    fn step(&mut self) {
        let t0 = ThreadTime::now();
        match &mut self.layer {
            Some(layer) => {
                layer.step(&mut self.world);
            }
            None => self.world.step(),
        }
        self.cpu.push(t0.elapsed().as_secs_f64());
        if let (Some(layer), Some(monitor)) = (&self.layer, &mut self.monitor) {
            let held = |h| layer.analysis().holds(&self.world.bodies, h);
            monitor.check(layer, &WorldView::from(&self.world), &held, &|_| false);
        }
        let moving = self
            .world
            .islands
            .active_bodies()
            .filter(|&h| self.world.bodies.get(h).is_some_and(|b| b.is_dynamic()))
            .count();
        self.moving.push(moving);
    }
}

fn scene(args: &Args) -> PhysicsWorld {
    scenes::diku(&scenes::DikuParams {
        spheres: args.spheres,
        seed: args.seed,
        ..Default::default()
    })
    .world
}

fn main() {
    let args = Args::parse();
    if args.steps == 0 {
        eprintln!("diku_cost: --steps must be at least 1");
        std::process::exit(2);
    }
    let mut brute = scene(&args);
    scenes::plain_solver(&mut brute, 4);
    let mut runners = vec![
        Runner::plain("stock Rapier", scene(&args)),
        Runner::plain("brute force", brute),
    ];
    for label in &args.configs {
        let Some(bits) = rcg_lab::table5::combination_bits(label) else {
            eprintln!("diku_cost: {label:?} is not a CTRZDSF label or a number below 128");
            std::process::exit(2);
        };
        let mut layer = ContactLayer::new();
        if let Err(e) = layer
            .speedups_mut()
            .set(Some(rcg_lab::table5::combination(bits)))
        {
            eprintln!("diku_cost: {label}: {e}");
            std::process::exit(2);
        }
        let world = scene(&args);
        let mut monitor = Monitor::new(MonitorConfig::default()).expect("default monitor");
        monitor.prime(&WorldView::from(&world));
        runners.push(Runner {
            layer: Some(layer),
            monitor: Some(monitor),
            ..Runner::plain(&format!("`{label}`"), world)
        });
    }
    let n = runners.len();
    for i in 0..args.steps {
        for k in 0..n {
            runners[(i + k) % n].step();
        }
    }

    // Per simulated second (100 steps): CPU time and mean integrated bodies.
    let per_second = |r: &Runner| -> Vec<(f64, f64)> {
        r.cpu
            .chunks(100)
            .zip(r.moving.chunks(100))
            .map(|(c, m)| {
                let mean = m.iter().sum::<usize>() as f64 / m.len() as f64;
                (c.iter().sum(), mean)
            })
            .collect()
    };
    let stock = per_second(&runners[0]);
    println!(
        "DIKU, {} spheres, {} steps, seed {}, thread CPU time, worlds in lockstep (order rotating)",
        args.spheres, args.steps, args.seed
    );
    println!("| world | CPU s, whole run | per simulated s: first · last | / stock | moving-bodies-only limit, s | / limit | integrated bodies, mean · at the end | violations |");
    println!("|---|---|---|---|---|---|---|---|");
    let stock_total: f64 = stock.iter().map(|s| s.0).sum();
    for r in &runners {
        let secs = per_second(r);
        let total: f64 = secs.iter().map(|s| s.0).sum();
        // Stock's cost per awake body in that second, times this world's moving bodies.
        let limit: f64 = secs
            .iter()
            .zip(&stock)
            .map(|(&(_, m), &(c, a))| if a > 0.0 { c * m / a } else { 0.0 })
            .sum();
        let mean_moving = r.moving.iter().sum::<usize>() as f64 / r.moving.len() as f64;
        let violations = r
            .monitor
            .as_ref()
            .map_or("-".to_string(), |m| m.totals().total().to_string());
        println!(
            "| {} | {:.3} | {:.3} · {:.3} | {:.2} | {:.3} | {:.2} | {:.0} · {} | {} |",
            r.name,
            total,
            secs.first().map_or(0.0, |s| s.0),
            secs.last().map_or(0.0, |s| s.0),
            total / stock_total,
            limit,
            if limit > 0.0 { total / limit } else { f64::NAN },
            mean_moving,
            r.moving.last().copied().unwrap_or(0),
            violations,
        );
    }
}
