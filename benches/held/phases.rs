//! `--phases N`: where the held world's slowest steps go. The held world is stepped
//! by hand (the layer's pre-step, Rapier's step with the layer's hooks and event
//! handler, the analysis), each call timed in thread CPU time (wall clock under `parallel`), in lockstep with the
//! stock world (alternating which goes first, as the table's run does). With
//! `--hit STEP` the ball is thrown into both worlds before that step (untimed).

use super::hit::Hit;
use super::StepClock;
use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};

/// One held step, split (seconds), with stock's step beside it and what the
/// pre-step applied.
struct Split {
    step: usize,
    pre: f64,
    rapier: f64,
    analyze: f64,
    stock: f64,
    /// Fixations and releases decided at the last analysis: this pre-step applies
    /// them.
    fixations: usize,
    releases: usize,
    /// Held bodies this pre-step disabled on their way out of Rapier's active set.
    parking: usize,
    /// Bodies Rapier integrates after this step.
    awake: usize,
}

impl Split {
    fn total(&self) -> f64 {
        self.pre + self.rapier + self.analyze
    }
}

/// Steps `stock` and `held` (with `layer`) `steps` times in lockstep and prints the
/// `top` slowest held steps, split, and stock's `top` slowest steps; `hit` throws its
/// ball into both before its step.
pub fn run(
    stock: &mut PhysicsWorld,
    held: &mut PhysicsWorld,
    layer: &mut ContactLayer,
    steps: usize,
    top: usize,
    mut hit: Option<Hit>,
) {
    let mut splits = Vec::with_capacity(steps);
    for step in 0..steps {
        if let Some(hit) = hit.as_mut() {
            hit.before_step(step, [&mut *stock, &mut *held]);
        }
        let time_stock = |w: &mut PhysicsWorld| {
            let t = StepClock::now();
            w.step();
            t.elapsed().as_secs_f64()
        };
        let (fixations, releases) = layer
            .speedups()
            .map_or((0, 0), |s| (s.stats().fixations, s.stats().releases));
        let time_held = |w: &mut PhysicsWorld, l: &mut ContactLayer| {
            let t = StepClock::now();
            l.pre_step(WorldMut::from(&mut *w));
            let pre = t.elapsed().as_secs_f64();
            let t = StepClock::now();
            w.step_with_events(&l.hooks(), l.event_handler());
            let rapier = t.elapsed().as_secs_f64();
            let parking = l.speedups().map_or(0, |s| s.parking().count());
            let t = StepClock::now();
            let awake = l.analyze(WorldView::from(&*w)).awake_bodies;
            (pre, rapier, t.elapsed().as_secs_f64(), parking, awake)
        };
        let (stock_s, (pre, rapier, analyze, parking, awake)) = if step % 2 == 0 {
            let s = time_stock(stock);
            (s, time_held(held, layer))
        } else {
            let h = time_held(held, layer);
            (time_stock(stock), h)
        };
        splits.push(Split {
            step,
            pre,
            rapier,
            analyze,
            stock: stock_s,
            fixations,
            releases,
            parking,
            awake,
        });
    }
    let mut stock_worst: Vec<f64> = splits.iter().map(|s| s.stock).collect();
    stock_worst.sort_by(|a, b| b.total_cmp(a));
    let ms: Vec<String> = stock_worst
        .iter()
        .take(top)
        .map(|t| format!("{:.3}", t * 1e3))
        .collect();
    println!("  stock's slowest steps, ms: {}", ms.join(" "));
    splits.sort_by(|a, b| b.total().total_cmp(&a.total()));
    println!("  held's slowest steps, ms (fixations and releases applied by the pre-step, bodies parked):");
    println!("     step    held     pre  rapier analyze   stock   fix   rel  park   awake");
    for s in splits.iter().take(top) {
        println!(
            "  {:7} {:7.3} {:7.3} {:7.3} {:7.3} {:7.3} {:5} {:5} {:5} {:7}",
            s.step,
            s.total() * 1e3,
            s.pre * 1e3,
            s.rapier * 1e3,
            s.analyze * 1e3,
            s.stock * 1e3,
            s.fixations,
            s.releases,
            s.parking,
            s.awake
        );
    }
}
