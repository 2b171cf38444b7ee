//! PNG frames of a scene coloured as the paper's Fig. 17: purple sleepy, red moving,
//! blue absolute rest, green fixed — and amber for bodies in a plausibility violation.
//!
//! The scene is the stability suite's hanging sleeper
//! (`rcg_scenes::stability::hanging_sleeper`): a sphere resting on another sphere that a
//! striker knocks away from under it. With the speed-ups on (sleepy + fixate), the
//! upper sphere turns sleepy, then fixated (held immovable: green), and stays in the
//! air when its support leaves — the failure of Fig. 17.
//!
//! Bodies are amber when the layer's plausibility monitor reports them (its last
//! violations and the held bodies it is timing as unsupported): the hanging sphere
//! turns amber once its support has gone. With `--repair` the monitor repairs instead:
//! the sphere is released the step after its support leaves and falls.
//!
//! ```text
//! cargo run --release --example frames -- [--out DIR] [--every K] [--steps N]
//!                                         [--view side|tilted] [--size WxH] [--repair]
//! ```
//! Writes `frame_0000.png`, … every `K` steps (default 10) of `N` steps (default 240)
//! into `DIR` (default `target/frames`) and prints each path with the body counts per
//! colour.

use std::path::PathBuf;
use std::time::Instant;

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rcg_lab::report::frames::{violating_bodies, Camera, Classifier, Renderer, Shade, View};

use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldView};

const USAGE: &str =
    "usage: frames [--out DIR] [--every K] [--steps N] [--view side|tilted] [--size WxH] [--repair]";

struct Args {
    out: PathBuf,
    every: u64,
    steps: u64,
    view: View,
    size: (u32, u32),
    repair: bool,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        out: PathBuf::from("target/frames"),
        every: 10,
        steps: 400,
        view: View::SIDE,
        size: (800, 480),
        repair: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        match flag.as_str() {
            "--out" => a.out = PathBuf::from(value()?),
            "--every" => a.every = value()?.parse().map_err(|e| format!("--every: {e}"))?,
            "--steps" => a.steps = value()?.parse().map_err(|e| format!("--steps: {e}"))?,
            "--view" => {
                a.view = match value()?.as_str() {
                    "side" => View::SIDE,
                    "tilted" => View::tilted(25.0, 25.0).map_err(|e| e.to_string())?,
                    other => return Err(format!("--view: `{other}` is not side or tilted")),
                }
            }
            "--size" => {
                let v = value()?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or(format!("--size: `{v}` is not WxH"))?;
                a.size = (
                    w.parse().map_err(|e| format!("--size: {e}"))?,
                    h.parse().map_err(|e| format!("--size: {e}"))?,
                );
            }
            "--repair" => a.repair = true,
            "-h" | "--help" => return Err(String::new()),
            other => return Err(format!("unknown option `{other}`")),
        }
    }
    if a.every == 0 {
        return Err("--every must be positive".into());
    }
    Ok(a)
}

fn main() -> std::io::Result<()> {
    let args = match parse_args() {
        Ok(a) => a,
        Err(msg) => {
            if !msg.is_empty() {
                eprintln!("error: {msg}");
            }
            eprintln!("{USAGE}");
            std::process::exit(2);
        }
    };
    std::fs::create_dir_all(&args.out)?;

    // The scene: the shared stability scene.
    let mut scene = rcg_scenes::stability::hanging_sleeper::hanging_sleeper();

    let speedups = SpeedUps {
        fixate: true,
        ..SpeedUps::contact_graph()
    };
    let label = speedups.label();
    let mut layer = ContactLayer::new();
    layer.set_speedups(Some(speedups)).expect("valid speed-ups");
    let mode = if args.repair {
        MonitorMode::Repair
    } else {
        MonitorMode::Report
    };
    layer
        .set_monitor(mode, MonitorConfig::default(), RepairConfig::default())
        .expect("valid monitor config");
    layer.prime_monitor(&WorldView::from(&scene.world));

    let camera = Camera::new(args.size.0, args.size.1)
        .with_view(args.view)
        .with_bounds(Vector::new(-3.0, -0.5, -1.0), Vector::new(4.0, 3.5, 1.0))
        .expect("finite bounds");
    // Before the first step: the fixated bodies turn fixed later and stay coloured.
    let renderer = Renderer::new(camera).with_fixed_as_scenery(&scene.world);

    let dt = scene.world.integration_parameters.dt;
    let started = Instant::now();
    let (mut render_time, mut write_time) = (0.0, 0.0);
    let mut written = 0;
    for step in 0..=args.steps {
        if step > 0 {
            scene.before_step(step - 1);
            layer.step(&mut scene.world);
        }
        let monitor = layer.monitor().expect("the monitor is on").monitor();
        if step % args.every != 0 {
            continue;
        }
        let t0 = Instant::now();
        let violating = violating_bodies(monitor);
        let classes = Classifier::new(&scene.world.bodies, &layer).violating(&violating);
        let caption = format!(
            "{}   t = {:.2} s   step {step}   speed-ups {label}",
            scene.name,
            step as Real * dt
        );
        let frame = renderer.render(&scene.world, &|h| classes.shade(h), &caption);
        let t1 = Instant::now();
        let path = args.out.join(format!("frame_{:04}.png", step / args.every));
        frame.write_png(&path)?;
        render_time += (t1 - t0).as_secs_f64();
        write_time += t1.elapsed().as_secs_f64();
        written += 1;
        let counts: Vec<String> = Shade::ALL
            .iter()
            .filter(|&&s| frame.count(s) > 0)
            .map(|&s| format!("{} {}", s.name(), frame.count(s)))
            .collect();
        println!("{}  ({})", path.display(), counts.join(", "));
    }
    let m = layer.monitor().expect("the monitor is on");
    let totals = m.monitor().totals();
    println!(
        "{written} frames in {:.2} s (per frame: {:.1} ms to render, {:.1} ms to write); \
         violations: {} hanging sleeper, {} launch, {} deep penetration, {} escape; \
         repairs: {} groups woken",
        started.elapsed().as_secs_f64(),
        1e3 * render_time / f64::from(written.max(1)),
        1e3 * write_time / f64::from(written.max(1)),
        totals.hanging_sleeper,
        totals.launch,
        totals.deep_penetration,
        totals.escape,
        m.repairs().woken
    );
    Ok(())
}
