//! The DIKU scene (shared with `rcg-lab diku` and the tests) as a benchmark:
//! stock Rapier, brute force, the contact graph and the fastest zero-violation
//! combination of the last full run, measured in one process and printed as ratios.
//!
//! ```text
//! cargo bench --bench diku            # 1,200 spheres
//! cargo bench --bench diku -- 120     # another size
//! ```

use rapier3d::prelude::RigidBodyHandle;
use rapier_contact_graph::monitor::MonitorConfig;
use rcg_lab::measure::{self, RunOptions, RunSpec};
use rcg_scenes::diku::{diku, is_on_plane, DikuParams};

fn main() {
    let spheres = std::env::args()
        .skip(1)
        .find_map(|a| a.parse::<usize>().ok())
        .unwrap_or(1200);
    let params = DikuParams {
        spheres,
        ..DikuParams::default()
    };
    let bodies: Vec<RigidBodyHandle> = diku(&params).dynamic_bodies();
    let inside = |p| is_on_plane(&params, p);
    let specs = [
        RunSpec::brute_force(),
        RunSpec::stock(),
        RunSpec::contact_graph(),
        RunSpec::combination(0b100_0000), // fixate
        RunSpec::combination(0b101_0011), // cache, tweak, damp, fixate
    ];
    println!("DIKU, {spheres} spheres, 1,000 steps");
    let mut brute = None;
    for spec in &specs {
        let opts = RunOptions {
            steps: 1000,
            sample_every: 100,
            radius: params.radius,
            bodies: &bodies,
            reference: None,
            inside: &inside,
            monitor: MonitorConfig::default(),
        };
        let (r, _) = measure::run(spec, diku(&params), &opts).expect("valid configuration");
        let b = *brute.get_or_insert(r.time_s);
        println!(
            "{:<14} {:>7.3} s  x{:>5.2} over brute force  last second {:>6.3} s  violations {}",
            r.name,
            r.time_s,
            b / r.time_s,
            r.tail_time_s,
            r.violations.total()
        );
    }
}
