//! `--first-step N`: the first step of a world built in contact, alone. A run's worst
//! step on the pyramid is its first (stock Rapier pairs every body anew, the layer
//! reads the whole world for the first time), and one sample per run is at the
//! machine's mercy; here each scene is built `N` times, and each time a fresh stock
//! world and a fresh held world take their first step in turn (alternating which goes
//! first), so that the ratio is of neighbouring samples.

use super::StepClock;
use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::ContactLayer;

/// The first step of fresh worlds of `build`, `n` times, stock and held in turn: held's
/// time over stock's, each pair's ratio. Prints min / quartiles / max and the medians'
/// times.
pub fn run(
    name: &str,
    n: usize,
    build: impl Fn() -> PhysicsWorld,
    layer: impl Fn() -> ContactLayer,
) {
    let first = |w: &mut PhysicsWorld, l: Option<&mut ContactLayer>| {
        let t = StepClock::now();
        match l {
            Some(l) => {
                l.step(w);
            }
            None => w.step(),
        }
        t.elapsed().as_secs_f64()
    };
    let (mut ratios, mut stock_t, mut held_t) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        let (mut stock, mut held, mut l) = (build(), build(), layer());
        let (s, h) = if i % 2 == 0 {
            let s = first(&mut stock, None);
            (s, first(&mut held, Some(&mut l)))
        } else {
            let h = first(&mut held, Some(&mut l));
            (first(&mut stock, None), h)
        };
        ratios.push(h / s);
        stock_t.push(s * 1e3);
        held_t.push(h * 1e3);
    }
    let q = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        let at = |f: f64| v[((v.len() - 1) as f64 * f).round() as usize];
        [at(0.0), at(0.25), at(0.5), at(0.75), at(1.0)]
    };
    let [lo, q1, med, q3, hi] = q(ratios);
    println!("\n{name}, first step of a fresh world, {n} pairs:");
    println!("  held/stock  min {lo:.3}  q1 {q1:.3}  median {med:.3}  q3 {q3:.3}  max {hi:.3}");
    println!(
        "  median ms   stock {:.3}   held {:.3}",
        super::median(stock_t),
        super::median(held_t)
    );
}
