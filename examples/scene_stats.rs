//! Runs a settling sphere pile with the contact-graph layer and prints the graph and
//! contact-group statistics the paper plots (Figs. 13–14), every 50 steps.
//!
//! ```text
//! cargo run --release --example scene_stats -- [--spheres N] [--steps K] [--no-details]
//! ```

use std::time::{Duration, Instant};

use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes as scenes;

fn usage() -> ! {
    eprintln!(
        "usage: scene_stats [--spheres N (default 1000)] [--steps K (default 500)] [--no-details]"
    );
    std::process::exit(2)
}

fn main() {
    let mut spheres = 1000usize;
    let mut steps = 500u64;
    let mut details = true;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || {
            args.next()
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or_else(|| usage())
        };
        match a.as_str() {
            "--spheres" => spheres = value() as usize,
            "--steps" => steps = value(),
            "--no-details" => details = false,
            _ => usage(),
        }
    }
    let mut scene = scenes::sphere_pile(spheres, 1);
    let mut layer = ContactLayer::new();
    layer.analysis_mut().set_contact_details(details);
    let (mut rapier_t, mut layer_t) = (Duration::ZERO, Duration::ZERO);
    println!(
        "{:>5} {:>6} {:>6} {:>6} {:>6} {:>7} {:>8} {:>8} {:>7} {:>7}",
        "step",
        "nodes",
        "edges",
        "groups",
        "awake",
        "largest",
        "vars/max",
        "vars/mean",
        "walked",
        "pairs"
    );
    for step in 0..steps {
        scene.before_step(step);
        let t0 = Instant::now();
        scene.world.step();
        let t1 = Instant::now();
        let s = layer.analyze(WorldView::from(&scene.world));
        let t2 = Instant::now();
        rapier_t += t1 - t0;
        layer_t += t2 - t1;
        if (step + 1) % 50 == 0 {
            println!(
                "{:>5} {:>6} {:>6} {:>6} {:>6} {:>7} {:>8} {:>8.1} {:>7} {:>7}",
                s.step,
                s.nodes,
                s.edges,
                s.groups.count,
                s.groups.awake_groups,
                s.groups.largest_bodies,
                s.groups.largest_variables,
                s.groups.mean_variables(),
                s.walk.bodies,
                s.walk.collider_pairs,
            );
        }
    }
    println!(
        "\n{spheres} spheres, {steps} steps: Rapier {:.3} s, analysis {:.3} s, analysis / Rapier = {:.3}",
        rapier_t.as_secs_f64(),
        layer_t.as_secs_f64(),
        layer_t.as_secs_f64() / rapier_t.as_secs_f64()
    );
}
