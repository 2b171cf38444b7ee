//! PNG frames of a scene coloured as the paper's Fig. 17: purple sleepy, red moving,
//! blue absolute rest, green fixed — and amber for bodies in a plausibility violation.
//!
//! The scene is a hanging sleeper: a sphere resting on another sphere that slides away
//! from under it. With the speed-ups on (sleepy + fixate), the upper sphere turns
//! sleepy, then fixated (held immovable: green), and stays in the air when its support
//! leaves — the failure of Fig. 17. Beside it, a small stack of boxes settles and is
//! fixated, and a ball is dropped on it later.
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
use rapier_contact_graph::report::frames::{
    violating_bodies, Camera, Classifier, Renderer, Shade, View,
};
use rapier_contact_graph::scenes::{self, Scene};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldView};

const USAGE: &str =
    "usage: frames [--out DIR] [--every K] [--steps N] [--view side|tilted] [--size WxH] [--repair]";

/// Radius of the hanging-sleeper spheres.
const R: Real = 0.5;
/// Marks the sphere that slides away (`user_data`), for the script.
const SLIDER: u128 = 1;
/// The step at which the lower sphere is sent sliding away.
const SLIDE_AT: u64 = 60;
/// The step at which the ball is dropped on the stack.
const DROP_AT: u64 = 120;

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
        steps: 240,
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

/// The hanging sleeper, built here until the shared stability scene exists.
///
/// The lower sphere is frictionless and spins about the vertical: the spin keeps its
/// kinetic energy above the sleepy threshold, so it is never fixated, and drags
/// nothing. The upper sphere therefore turns sleepy and is fixated on top of it. At
/// `SLIDE_AT` the script sends the lower sphere sliding away at 0.4 m/s, below the
/// speed that releases a fixated body it touches (0.5 m/s), and the upper sphere is
/// left hanging.
fn hanging_sleeper() -> Scene {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, scenes::GRAVITY_Y, 0.0);
    world.integration_parameters.dt = scenes::DT;
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.5, -0.25, 0.0)),
        ColliderBuilder::cuboid(3.5, 0.25, 1.0).friction(1.0),
    );
    let (lower, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-1.5, R, 0.0))
            .angvel(Vector::new(0.0, 6.0, 0.0))
            .user_data(SLIDER),
        ColliderBuilder::ball(R)
            .friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min),
    );
    let (upper, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(-1.5, 3.0 * R + 0.01, 0.0)),
        ColliderBuilder::ball(R).friction(1.0),
    );
    // A small stack of boxes that settles and is fixated, and a ball dropped on it.
    let mut bodies = vec![("ground", ground), ("lower", lower), ("upper", upper)];
    for (i, name) in ["box0", "box1", "box2"].into_iter().enumerate() {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(2.0, 0.3 + i as Real * 0.61, 0.0)),
            ColliderBuilder::cuboid(0.3, 0.3, 0.3).friction(1.0),
        );
        bodies.push((name, h));
    }

    fn script(world: &mut PhysicsWorld, step: u64) {
        if step == SLIDE_AT {
            for (_, rb) in world.bodies.iter_mut() {
                if rb.user_data == SLIDER {
                    rb.set_linvel(Vector::new(0.4, 0.0, 0.0), true);
                }
            }
        }
        if step == DROP_AT {
            world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(2.1, 3.2, 0.0)),
                ColliderBuilder::ball(0.25),
            );
        }
    }
    Scene {
        name: "hanging sleeper",
        world,
        bodies,
        script: Some(script),
    }
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

    // The scene: one line to switch.
    let mut scene = hanging_sleeper();

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
