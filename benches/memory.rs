//! What the layer holds in memory beside Rapier's own world (`docs/results.md`,
//! "Memory").
//!
//! A counting global allocator keeps the bytes live (requested sizes, without the
//! allocator's own overhead). For each size of the sphere pile (`scenes::sphere_pile`)
//! two worlds are built and stepped `--steps` steps, one after the other in one
//! process:
//! - *plain*: `world.step()` only; its live bytes after the steps are Rapier's own
//!   (bodies, colliders, broad and narrow phase, islands, the pipeline's buffers);
//! - *layered*: `ContactLayer::step` with the preset (`observe`: the observe-only
//!   layer, the default; `reliable`: `SpeedUps::reliable_sleep()`), subscribed to the
//!   contact events (drained every step). The layer's bytes are the live bytes just
//!   before dropping it less those just after (the world stays).
//!
//! Reported per body and per touching pair (Rapier's contact pairs with an active
//! contact at the end), and split by what holds them: clones of the layer's graph,
//! groups, analysis state (`Coherence`) and speed-ups are measured the same way (a
//! clone allocates a vector's length, not its capacity: the rest, "other", is spare
//! capacity and what the clones do not reach: the logic layer, the event bus, the
//! step's buffers); within the graph, the node and edge structs themselves
//! (`size_of` × count).
//!
//! ```text
//! cargo bench --bench memory                            # 1,000, 5,000 and 20,000 spheres
//! cargo bench --bench memory -- 5000 --preset reliable  # with SpeedUps::reliable_sleep()
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

use clap::Parser;
use rapier3d::prelude::PhysicsWorld;
use rapier_contact_graph::events::{Filter, KindSet};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Edge, Node};
use rcg_scenes as scenes;

/// The system allocator, counting the bytes live.
struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded to the system allocator with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator with `layout`.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: `ptr` was allocated by this allocator with `layout`.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_add(
                new_size as isize - layout.size() as isize,
                Ordering::Relaxed,
            );
        }
        p
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn live() -> isize {
    LIVE.load(Ordering::Relaxed)
}

/// The live bytes `f`'s result holds (allocated while making it, kept by it).
fn held_by<T>(f: impl FnOnce() -> T) -> isize {
    let before = live();
    let out = f();
    let after = live();
    drop(out);
    after - before
}

const SEED: u64 = 1;

#[derive(Parser)]
#[command(about = "Bytes the layer holds beside Rapier's own world")]
struct Args {
    /// Pile sizes (spheres).
    #[arg(default_values_t = [1000, 5000, 20000])]
    sizes: Vec<usize>,
    /// Steps before measuring (dt = 0.01 s): the fall and most of the settling.
    #[arg(long, default_value_t = 400)]
    steps: usize,
    /// The layer: observe (no speed-ups) or reliable (`SpeedUps::reliable_sleep()`).
    #[arg(long, default_value = "observe")]
    preset: String,
    /// cargo passes `--bench` to benches without the default harness.
    #[arg(long, hide = true)]
    bench: bool,
}

/// Rapier's contact pairs with an active contact.
fn touching_pairs(world: &PhysicsWorld) -> usize {
    world
        .narrow_phase
        .contact_pairs()
        .filter(|p| p.has_any_active_contact())
        .count()
}

struct Measure {
    bodies: usize,
    touching: usize,
    rapier: isize,
    rapier_layered: isize,
    layer: isize,
    graph: isize,
    node_structs: isize,
    edge_structs: isize,
    groups: isize,
    coherence: isize,
    speedups: isize,
    nodes: usize,
    edges: usize,
}

fn measure(n: usize, args: &Args) -> Measure {
    // Rapier alone.
    let base = live();
    let mut plain = scenes::sphere_pile(n, SEED).world;
    for _ in 0..args.steps {
        plain.step();
    }
    let rapier = live() - base;
    let bodies = plain.bodies.len();
    let touching = touching_pairs(&plain);
    drop(plain);

    // The layer.
    let base = live();
    let mut world = scenes::sphere_pile(n, SEED).world;
    let mut layer = ContactLayer::new();
    if args.preset == "reliable" {
        layer
            .speedups_mut()
            .set(Some(SpeedUps::reliable_sleep()))
            .expect("the preset is valid");
    }
    let rx = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS));
    for _ in 0..args.steps {
        layer.step(&mut world);
        rx.try_iter().for_each(drop);
    }
    let graph = held_by(|| layer.graph().clone());
    let groups = held_by(|| layer.groups().clone());
    let coherence = held_by(|| layer.analysis().coherence().clone());
    let speedups = held_by(|| layer.speedups().cloned());
    let nodes = layer.graph().node_count();
    let edges = layer.graph().edge_count();
    let with_layer = live() - base;
    drop(rx);
    drop(layer);
    let rapier_layered = live() - base;
    Measure {
        bodies,
        touching,
        rapier,
        rapier_layered,
        layer: with_layer - rapier_layered,
        graph,
        node_structs: (nodes * std::mem::size_of::<Node>()) as isize,
        edge_structs: (edges * std::mem::size_of::<Edge>()) as isize,
        groups,
        coherence,
        speedups,
        nodes,
        edges,
    }
}

fn main() {
    let args = Args::parse();
    if !matches!(args.preset.as_str(), "observe" | "reliable") {
        eprintln!("memory: --preset is observe or reliable");
        std::process::exit(2);
    }
    println!(
        "live bytes after {} steps of the sphere pile, layer ({}) beside Rapier's own world; \
         size_of::<Node>() = {}, size_of::<Edge>() = {}",
        args.steps,
        args.preset,
        std::mem::size_of::<Node>(),
        std::mem::size_of::<Edge>()
    );
    println!(
        "| N | touching pairs | Rapier, bytes per body | layer, bytes per body | layer / Rapier \
         | layer, bytes per touching pair | nodes · edges | graph (node structs · edge structs · \
         rest) | groups | coherence | speed-ups | other |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &n in &args.sizes {
        eprintln!("memory: N = {n} ...");
        let m = measure(n, &args);
        let kib = |b: isize| format!("{:.0} KiB", b as f64 / 1024.0);
        let per_body = |b: isize| b as f64 / m.bodies as f64;
        let other = m.layer - m.graph - m.groups - m.coherence - m.speedups;
        println!(
            "| {n} | {} | {:.0} (layered world: {:.0}) | {:.0} | {:.2} | {:.0} | {} · {} \
             | {} ({} · {} · {}) | {} | {} | {} | {} |",
            m.touching,
            per_body(m.rapier),
            per_body(m.rapier_layered),
            per_body(m.layer),
            m.layer as f64 / m.rapier as f64,
            m.layer as f64 / m.touching.max(1) as f64,
            m.nodes,
            m.edges,
            kib(m.graph),
            kib(m.node_structs),
            kib(m.edge_structs),
            kib(m.graph - m.node_structs - m.edge_structs),
            kib(m.groups),
            kib(m.coherence),
            kib(m.speedups),
            kib(other),
        );
    }
}
