//! `rcg-lab frames`: PNG frames of a scene coloured as the paper's Fig. 17: purple
//! sleepy, red moving, blue absolute rest, green fixed — and amber for bodies in a
//! plausibility violation.
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
//! Over the bodies, the contact graph is drawn as the plugin's `GraphOverlay` draws it
//! into any Rapier debug renderer: touching edges between bodies in their contact
//! group's colour, dashed trigger edges, and a state marker per body (`--no-graph`
//! leaves it out).
//!
//! ```text
//! cargo lab frames [--out DIR] [--every K] [--steps N] [--view side|tilted] [--size WxH] [--repair] [--no-graph]
//! ```
//! Writes `frame_0000.png`, … every `K` steps (default 10) of `N` steps (default 400)
//! into `DIR` (default `target/frames`) and prints each path with the body counts per
//! colour.

use std::path::PathBuf;
use std::time::Instant;

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, GraphOverlay, WorldView};

use crate::report::frames::{violating_bodies, Camera, Classifier, Renderer, Shade, View};

/// Options of `rcg-lab frames`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Directory for the frames.
    #[arg(long, value_name = "DIR", default_value = "target/frames")]
    pub out: PathBuf,
    /// A frame every K steps.
    #[arg(long, value_name = "K", default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..))]
    pub every: u64,
    /// Steps to simulate (0.01 s each).
    #[arg(long, value_name = "N", default_value_t = 400)]
    pub steps: u64,
    /// The camera: the side view of the paper's figures, or tilted 25° round and 25°
    /// down.
    #[arg(long, value_enum, default_value_t = ViewArg::Side)]
    pub view: ViewArg,
    /// Picture size in pixels, e.g. 800x480 (each side clamped to 160..=8192).
    #[arg(long, value_name = "WxH", default_value = "800x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Let the monitor repair (release the hanging sphere) instead of only reporting.
    #[arg(long)]
    pub repair: bool,
    /// Leave out the contact graph drawn over the bodies (the plugin's
    /// `GraphOverlay`: touching and trigger edges, contact groups by colour, a state
    /// marker per body).
    #[arg(long)]
    pub no_graph: bool,
}

/// `--view`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ViewArg {
    /// Looking along −z, x right, y up.
    Side,
    /// The side view turned 25° about y and pitched 25° down.
    Tilted,
}

/// `WxH` as `(W, H)`.
pub fn parse_size(v: &str) -> Result<(u32, u32), String> {
    let (w, h) = v.split_once('x').ok_or(format!("`{v}` is not WxH"))?;
    Ok((
        w.trim().parse().map_err(|e| format!("width: {e}"))?,
        h.trim().parse().map_err(|e| format!("height: {e}"))?,
    ))
}

/// Runs `rcg-lab frames`.
// Long: a runner: arguments, steps, frames and files, in order.
pub fn run(args: &Args) -> Result<(), String> {
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;

    // The scene: the shared stability scene.
    let mut scene = rcg_scenes::stability::hanging_sleeper::hanging_sleeper();

    let speedups = SpeedUps {
        hold: true,
        ..SpeedUps::contact_graph()
    };
    let label = crate::table5::label(&speedups);
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(speedups))
        .map_err(|e| e.to_string())?;
    let mode = if args.repair {
        MonitorMode::Repair
    } else {
        MonitorMode::Report
    };
    layer
        .monitor_mut()
        .set(mode, MonitorConfig::default(), RepairConfig::default())
        .map_err(|e| e.to_string())?;
    layer.monitor_mut().prime(&WorldView::from(&scene.world));

    let view = match args.view {
        ViewArg::Side => View::SIDE,
        ViewArg::Tilted => View::tilted(25.0, 25.0).map_err(|e| e.to_string())?,
    };
    let camera = Camera::new(args.size.0, args.size.1)
        .with_view(view)
        .with_bounds(Vector::new(-3.0, -0.5, -1.0), Vector::new(4.0, 3.5, 1.0))
        .map_err(|e| e.to_string())?;
    // Before the first step: the fixated bodies turn fixed later and stay coloured.
    let renderer = Renderer::new(camera).with_fixed_as_scenery(&scene.world);

    let mut overlay = (!args.no_graph).then(GraphOverlay::default);
    let dt = scene.world.integration_parameters.dt;
    let started = Instant::now();
    let (mut render_time, mut write_time, mut bytes) = (0.0, 0.0, 0usize);
    let mut written = 0;
    for step in 0..=args.steps {
        if step > 0 {
            scene.before_step(step - 1);
            layer.step(&mut scene.world);
        }
        if step % args.every != 0 {
            continue;
        }
        let monitor = layer.monitor().ok_or("the monitor is off")?.monitor();
        let t0 = Instant::now();
        let violating = violating_bodies(monitor);
        let classes = Classifier::new(&scene.world.bodies, &layer).violating(&violating);
        let caption = format!(
            "{}   t = {:.2} s   step {step}   speed-ups {label}",
            scene.name,
            step as Real * dt
        );
        let frame =
            renderer.render_with(&scene.world, &|h| classes.shade(h), &caption, |backend| {
                // The second pass into the same DebugRenderBackend: the contact graph
                // as the plugin draws it into any Rapier debug renderer.
                if let Some(overlay) = overlay.as_mut() {
                    overlay.render(backend, &layer, &scene.world.bodies, &scene.world.colliders);
                }
            });
        let t1 = Instant::now();
        let path = args.out.join(format!("frame_{:04}.png", step / args.every));
        let png = frame.png();
        std::fs::write(&path, &png).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        bytes += png.len();
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
    let m = layer.monitor().ok_or("the monitor is off")?;
    let totals = m.monitor().totals();
    println!(
        "{written} frames ({:.0} KB) in {:.2} s (per frame: {:.1} ms to render, {:.1} ms to encode and write); \
         violations: {} hanging sleeper, {} launch, {} deep penetration, {} escape; \
         repairs: {} groups woken",
        bytes as f64 / 1024.0,
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
