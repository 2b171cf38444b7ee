//! Scale and memory: 100,000 bodies, most of them asleep, plus
//! 10,000 trigger and timer nodes, churned for 10,000 steps.
//!
//! # The scene (built here, deterministic)
//! - a ground: one fixed body with one large cuboid, top face at y = 0;
//! - `--bodies` (100,000) resting bodies on a square-ish grid, 1 m apart, alternately
//!   cubes (half extent 0.25) and balls (radius 0.25), created asleep with
//!   `RigidBodyBuilder::sleeping(true)` and resting exactly on the ground;
//! - `--sensors` (5,000) trigger volumes: sensor cuboids (2 × 1 × 2 m) on fixed bodies
//!   scattered over the field, each holding a few resting bodies;
//! - `--timers` (5,000) timers with periods 0.10 … 1.08 s (`LayerLogicMut::add_timer`);
//! - the movers that keep the scene churning:
//!   - `--balls` (100) dynamic balls, re-launched every 2.5 s from 3 m above a random
//!     point of the field with a random horizontal speed: they land on resting
//!     bodies, wake and knock them, roll on, and leave them behind;
//!   - `--sweepers` (200) kinematic balls flying just above the resting bodies on
//!     straight lines that bounce off the field's edges, crossing trigger volumes and
//!     brushing whatever was knocked over.
//!
//! One all-kinds event subscription is drained every step (outside the timings).
//!
//! Rapier 0.36.1 wakes a sleeping body whenever one of its contacts *starts*
//! (`geometry/narrow_phase/contacts.rs`: "starts wake unconditionally"), and a body
//! resting on the ground starts its contact with it at the first step. So the bodies
//! built asleep are all awake after step 1 and fall asleep again about 0.7 s later;
//! `--warmup` steps (300) let that settle and are reported apart from the churn.
//!
//! # What is measured (one run, one process)
//! Every step is `pre_step` (timed with the layer), Rapier's `step_with_events` with
//! the layer's hooks (timed as Rapier) and `analyze` (timed with the layer): exactly
//! `ContactLayer::step`, split as in `benches/overhead.rs`. Printed:
//! - step 1, the warm-up, then every `--every` (1,000) churn steps: awake bodies,
//!   Rapier and layer time per step and their ratio, nodes, Rapier's contact pairs,
//!   edges, the largest and mean number of neighbour edges of a dynamic body,
//!   touching edges, lingering edges (proximity vanished, kept by the §3.1 rule while
//!   the two AABBs are near) and how many of those are already far enough to go
//!   (waiting for their staggered test, or frozen between two sleeping bodies),
//!   edges created and removed, events;
//! - memory: `size_of` of `Node`, `Edge` and `EdgeId`; the adjacency entries counted
//!   from the graph (the sum of `node.edges().len()` × `size_of::<EdgeId>()`:
//!   lengths, as the capacities are not public); an itemised estimate of the graph's
//!   bytes per node and per edge; the groups' bytes (their member `Vec`s'
//!   capacities are public); and the layer's and Rapier's real heap, measured
//!   exactly by a counting global allocator when each is dropped at the end;
//! - that edges stay O(n), asserted at every report (exit code 1 otherwise): edges
//!   ≤ `EDGES_PER_NODE_BOUND` × nodes, no dynamic body with more than
//!   `NEIGHBOURS_BOUND` neighbour edges, and lingering edges already far enough to be
//!   obsolete ≤ `FAR_LINGERING_PER_MOVER_BOUND` × movers (the obsolete test doing
//!   its job).
//!
//! Usage (the full run takes 7–10 minutes on a 2-core machine):
//! ```text
//! cargo bench --bench scale                          # 100,000 bodies, 10,000 steps
//! cargo bench --bench scale -- --steps 2000          # shorter churn
//! cargo bench --bench scale -- --bodies 20000 --sensors 1000 --timers 1000
//! cargo bench --bench scale -- --no-events --no-details   # leaner analysis
//! ```
//! Options: `--bodies`, `--sensors`, `--timers`, `--balls`, `--sweepers`, `--steps`,
//! `--warmup`, `--every` (numbers), `--no-events` (no subscription), `--no-details`
//! (`LayerAnalysisMut::set_contact_details(false)`).

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

use rapier3d::math::{Real, Vector};
use rapier3d::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d::prelude::*;
use rapier_contact_graph::coherence::aabbs_obsolete;
use rapier_contact_graph::events::{EventKind, Filter};
use rapier_contact_graph::logic::WorldMut;
use rapier_contact_graph::{
    ContactLayer, Edge, EdgeId, EdgeKind, Group, Node, NodeId, NodeKind, NodeSource, PairKey,
    StepStats, WorldView,
};
use rcg_scenes as scenes;

// ── A counting allocator: exact live heap bytes ────────────────────────

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Relaxed) + layout.size();
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Relaxed) + layout.size();
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                let now =
                    LIVE.fetch_add(new_size - layout.size(), Relaxed) + new_size - layout.size();
                PEAK.fetch_max(now, Relaxed);
            } else {
                LIVE.fetch_sub(layout.size() - new_size, Relaxed);
            }
        }
        p
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn live() -> usize {
    LIVE.load(Relaxed)
}

// ── Options ────────────────────────────────────────────────────────────

/// Edges may not exceed this many per node: a bound linear in the scene's size, from
/// the geometry. A resting body has one edge with the ground; once knocked about it
/// can keep edges with the neighbours within the §3.1 range (an AABB gap of at most
/// twice the largest AABB edge: the 8 grid neighbours, so at most 4 edges per body);
/// a trigger holds a handful of bodies. Without the obsolete test the edges of the
/// movers alone would grow with the distance they travel, without bound.
const EDGES_PER_NODE_BOUND: f64 = 5.0;
/// Lingering edges that the §3.1 test would already remove may not exceed this many
/// per mover (they wait at most `OBSOLETE_EVERY` steps for their test, unless both
/// ends sleep).
const FAR_LINGERING_PER_MOVER_BOUND: f64 = 10.0;
/// No dynamic body may have more physical edges than this with other non-fixed
/// bodies: an edge outlives proximity only while the two AABBs are within the §3.1
/// range (a gap of at most twice the largest AABB edge: 1.7 m for a tilted cube), and
/// about 20 bodies of the 1 m grid fit in that range around a body.
const NEIGHBOURS_BOUND: usize = 40;

struct Args {
    bodies: usize,
    sensors: usize,
    timers: usize,
    balls: usize,
    sweepers: usize,
    steps: usize,
    every: usize,
    warmup: usize,
    events: bool,
    details: bool,
}

fn parse_args() -> Args {
    let mut a = Args {
        bodies: 100_000,
        sensors: 5_000,
        timers: 5_000,
        balls: 100,
        sweepers: 200,
        steps: 10_000,
        every: 1_000,
        warmup: 300,
        events: true,
        details: true,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let (key, inline) = match arg.split_once('=') {
            Some((k, v)) => (k.to_string(), Some(v.to_string())),
            None => (arg.clone(), None),
        };
        let slot = match key.as_str() {
            // cargo passes `--bench` to harness = false benches.
            "--bench" => continue,
            "--no-events" => {
                a.events = false;
                continue;
            }
            "--no-details" => {
                a.details = false;
                continue;
            }
            "--bodies" => &mut a.bodies,
            "--sensors" => &mut a.sensors,
            "--timers" => &mut a.timers,
            "--balls" => &mut a.balls,
            "--sweepers" => &mut a.sweepers,
            "--steps" => &mut a.steps,
            "--every" => &mut a.every,
            "--warmup" => &mut a.warmup,
            other => {
                eprintln!("scale: ignoring argument {other:?}");
                continue;
            }
        };
        let v = inline
            .or_else(|| it.next())
            .unwrap_or_else(|| panic!("{key} needs a value"));
        *slot = v
            .replace('_', "")
            .parse()
            .unwrap_or_else(|_| panic!("{key}: not a number: {v}"));
    }
    assert!(a.bodies > 0 && a.steps > 0 && a.every > 0);
    a
}

// ── The scene ──────────────────────────────────────────────────────────

/// A seeded xorshift64* generator (no `rand` dependency): uniform in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> Real {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (x >> 40) as Real / (1u64 << 24) as Real
    }
    fn range(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * self.next()
    }
}

const SPACING: Real = 1.0;
const HALF: Real = 0.25;
const RELAUNCH_EVERY: usize = 250;
const SWEEPER_RADIUS: Real = 0.2;
/// Sweeper centres fly this high: their bottom is 0.05 m above the resting bodies.
const SWEEPER_Y: Real = 2.0 * HALF + 0.05 + SWEEPER_RADIUS;
const SWEEPER_SPEED: Real = 3.0;

struct Scene {
    world: PhysicsWorld,
    /// Half extents of the field (x, z) holding the resting bodies.
    half_x: Real,
    half_z: Real,
    balls: Vec<RigidBodyHandle>,
    sweepers: Vec<(RigidBodyHandle, Vector, Vector)>,
    rng: Rng,
}

fn build(args: &Args) -> Scene {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, scenes::GRAVITY_Y, 0.0);
    world.integration_parameters.dt = scenes::DT;
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);

    let cols = ((args.bodies as f64 * 1.6).sqrt().ceil() as usize).max(1);
    let rows = args.bodies.div_ceil(cols);
    let half_x = cols as Real * SPACING / 2.0;
    let half_z = rows as Real * SPACING / 2.0;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(half_x + 5.0, 0.5, half_z + 5.0),
    );

    for i in 0..args.bodies {
        let (c, r) = (i % cols, i / cols);
        let x = -half_x + (c as Real + 0.5) * SPACING;
        let z = -half_z + (r as Real + 0.5) * SPACING;
        let shape = if (c + r) % 2 == 0 {
            ColliderBuilder::cuboid(HALF, HALF, HALF)
        } else {
            ColliderBuilder::ball(HALF)
        };
        world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, HALF, z))
                .sleeping(true),
            shape,
        );
    }

    for _ in 0..args.sensors {
        let x = rng.range(-half_x + 1.0, half_x - 1.0);
        let z = rng.range(-half_z + 1.0, half_z - 1.0);
        world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(x, 0.55, z)),
            ColliderBuilder::cuboid(1.0, 0.5, 1.0).sensor(true),
        );
    }

    let mut balls = Vec::with_capacity(args.balls);
    for _ in 0..args.balls {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0, 0.0)),
            ColliderBuilder::ball(0.3).density(2.0),
        );
        balls.push(h);
    }

    let mut sweepers = Vec::with_capacity(args.sweepers);
    for _ in 0..args.sweepers {
        let p = Vector::new(
            rng.range(-half_x + 1.0, half_x - 1.0),
            SWEEPER_Y,
            rng.range(-half_z + 1.0, half_z - 1.0),
        );
        let a = rng.range(0.0, std::f32::consts::TAU);
        let v = Vector::new(a.cos(), 0.0, a.sin()) * SWEEPER_SPEED;
        let (h, _) = world.insert(
            RigidBodyBuilder::kinematic_position_based().translation(p),
            ColliderBuilder::ball(SWEEPER_RADIUS),
        );
        sweepers.push((h, p, v));
    }

    let mut scene = Scene {
        world,
        half_x,
        half_z,
        balls,
        sweepers,
        rng,
    };
    scene.launch_balls();
    scene
}

impl Scene {
    /// Every ball to 3 m above a random point of the field, with a random horizontal
    /// velocity of 1–4 m/s, awake.
    fn launch_balls(&mut self) {
        for &h in &self.balls {
            let x = self.rng.range(-self.half_x + 2.0, self.half_x - 2.0);
            let z = self.rng.range(-self.half_z + 2.0, self.half_z - 2.0);
            let a = self.rng.range(0.0, std::f32::consts::TAU);
            let s = self.rng.range(1.0, 4.0);
            let rb = &mut self.world.bodies[h];
            rb.set_translation(Vector::new(x, 3.0, z), true);
            rb.set_linvel(Vector::new(a.cos() * s, 0.0, a.sin() * s), true);
            rb.set_angvel(Vector::ZERO, true);
        }
    }

    /// Called before each step: sweepers move on, balls are re-launched periodically.
    fn before_step(&mut self, step: usize) {
        if step > 0 && step % RELAUNCH_EVERY == 0 {
            self.launch_balls();
        }
        let dt = self.world.integration_parameters.dt;
        let (hx, hz) = (self.half_x - 0.5, self.half_z - 0.5);
        for (h, p, v) in &mut self.sweepers {
            *p += *v * dt;
            if p.x.abs() > hx {
                v.x = -v.x;
                p.x = p.x.clamp(-hx, hx);
            }
            if p.z.abs() > hz {
                v.z = -v.z;
                p.z = p.z.clamp(-hz, hz);
            }
            self.world.bodies[*h].set_next_kinematic_translation(*p);
        }
    }
}

// ── Measurement ────────────────────────────────────────────────────────

/// One step as `ContactLayer::step` does it, with Rapier's part and the layer's
/// (pre-step + analysis) timed apart.
fn timed_step(scene: &mut Scene, layer: &mut ContactLayer, step: usize) -> (f64, f64, StepStats) {
    scene.before_step(step);
    let t0 = Instant::now();
    layer.pre_step(WorldMut::from(&mut scene.world));
    let t1 = Instant::now();
    scene.world.step_with_events(&layer.hooks(), &());
    let t2 = Instant::now();
    let stats = black_box(layer.analyze(WorldView::from(&scene.world)));
    let t3 = Instant::now();
    (
        (t2 - t1).as_secs_f64(),
        (t1 - t0).as_secs_f64() + (t3 - t2).as_secs_f64(),
        stats,
    )
}

/// Per-window sums.
#[derive(Default, Clone)]
struct Window {
    first: usize,
    last: usize,
    rapier: Vec<f64>,
    layer: Vec<f64>,
    awake_sum: usize,
    created: usize,
    events: usize,
}

impl Window {
    fn steps(&self) -> usize {
        self.rapier.len()
    }
    fn rapier(&self) -> f64 {
        self.rapier.iter().sum()
    }
    fn layer(&self) -> f64 {
        self.layer.iter().sum()
    }
    fn absorb(&mut self, o: &Window) {
        self.rapier.extend_from_slice(&o.rapier);
        self.layer.extend_from_slice(&o.layer);
        self.awake_sum += o.awake_sum;
        self.created += o.created;
        self.events += o.events;
    }
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

#[derive(Clone, Copy)]
struct GraphCounts {
    nodes: usize,
    edges: usize,
    physical: usize,
    geometric: usize,
    touching: usize,
    /// Physical edges whose proximity vanished, kept for a quick return (§3.1).
    lingering: usize,
    /// Of those, the ones the §3.1 test would remove now (AABB gap > 2 × largest
    /// edge), waiting for their next test or frozen between two sleeping bodies.
    lingering_far: usize,
    adjacency_entries: usize,
    max_degree: usize,
    triggers: usize,
    timers: usize,
    /// Rapier's contact pairs (collider pairs in the narrow phase, sleeping included).
    rapier_pairs: usize,
    /// Physical edges of a dynamic body with other non-fixed bodies (its neighbours;
    /// the ground and triggers left out): the largest and the mean over dynamic bodies.
    max_neighbours: usize,
    mean_neighbours: f64,
}

/// A node's AABB as the §3.1 test sees it: the union of a body's enabled non-sensor
/// colliders, or a sensor's own.
fn node_aabb(world: &PhysicsWorld, node: &Node) -> Option<Aabb> {
    match node.source() {
        NodeSource::Body(h) => {
            let rb = world.bodies.get(h)?;
            rb.colliders()
                .iter()
                .filter_map(|&c| world.colliders.get(c))
                .filter(|c| c.is_enabled() && !c.is_sensor())
                .map(|c| c.compute_aabb())
                .reduce(|a, b| a.merged(&b))
        }
        NodeSource::Sensor(c) | NodeSource::StaticCollider(c) => {
            world.colliders.get(c).map(|c| c.compute_aabb())
        }
        _ => None,
    }
}

fn count_graph(layer: &ContactLayer, world: &PhysicsWorld) -> GraphCounts {
    let g = layer.graph();
    let mut c = GraphCounts {
        nodes: g.node_count(),
        edges: g.edge_count(),
        physical: 0,
        geometric: 0,
        touching: 0,
        lingering: 0,
        lingering_far: 0,
        adjacency_entries: 0,
        max_degree: 0,
        triggers: g.count_of_kind(NodeKind::Sensor),
        timers: g.count_of_kind(NodeKind::Timer),
        rapier_pairs: world.narrow_phase.contact_pairs().count(),
        max_neighbours: 0,
        mean_neighbours: 0.0,
    };
    let (mut sum, mut rigid) = (0usize, 0usize);
    for (id, _) in g.nodes_of_kind(NodeKind::Dynamic) {
        let k = g
            .neighbors(id)
            .filter(|(m, _, e)| {
                e.kind() == EdgeKind::Physical
                    && g.node(*m).is_some_and(|m| m.kind() != NodeKind::Fixed)
            })
            .count();
        c.max_neighbours = c.max_neighbours.max(k);
        sum += k;
        rigid += 1;
    }
    c.mean_neighbours = sum as f64 / rigid.max(1) as f64;
    for (_, e) in g.edges() {
        match e.kind() {
            EdgeKind::Physical => c.physical += 1,
            EdgeKind::Geometric => c.geometric += 1,
            _ => {}
        }
        if e.is_touching() {
            c.touching += 1;
        }
        if e.kind() == EdgeKind::Physical && !e.is_proximate() {
            c.lingering += 1;
            let aabb = |n| g.node(n).and_then(|n| node_aabb(world, n));
            if let (Some(a), Some(b)) = (aabb(e.a()), aabb(e.b())) {
                if aabbs_obsolete(&a, &b) {
                    c.lingering_far += 1;
                }
            }
        }
    }
    for (_, n) in g.nodes() {
        c.adjacency_entries += n.edges().len();
        c.max_degree = c.max_degree.max(n.degree());
    }
    c
}

fn mib(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

fn row(label: &str, w: &Window, c: &GraphCounts, removed: Option<isize>) {
    let steps = w.steps().max(1) as f64;
    println!(
        "| {label} | {:.0} | {:.2} | {:.3} | {:.2} % | {} | {} | {} | {:.3} | {} / {:.2} | {} | {} | {} | {} | {} | {} |",
        w.awake_sum as f64 / steps,
        w.rapier() / steps * 1e3,
        w.layer() / steps * 1e3,
        w.layer() / w.rapier() * 100.0,
        c.nodes,
        c.rapier_pairs,
        c.edges,
        c.edges as f64 / c.nodes as f64,
        c.max_neighbours,
        c.mean_neighbours,
        c.touching,
        c.lingering,
        c.lingering_far,
        w.created,
        removed.map_or("-".to_string(), |r| r.to_string()),
        w.events
    );
}

fn main() {
    let args = parse_args();
    if cfg!(debug_assertions) {
        eprintln!("scale: warning, debug assertions are on; use `cargo bench`");
    }
    let wall = Instant::now();
    let heap0 = live();
    let mut scene = build(&args);
    let world_built_heap = live() - heap0;
    let build_time = wall.elapsed().as_secs_f64();
    let movers = args.balls + args.sweepers;
    eprintln!(
        "scale: built {} bodies, {} colliders in {build_time:.1} s",
        scene.world.bodies.len(),
        scene.world.colliders.len()
    );

    let mut layer = ContactLayer::new();
    layer.analysis_mut().set_contact_details(args.details);
    for i in 0..args.timers {
        layer
            .logic_mut()
            .add_timer(0.10 + (i % 50) as f64 * 0.02)
            .unwrap();
    }
    let rx = args.events.then(|| layer.subscribe(Filter::all()));
    let mut kinds = [0usize; EventKind::ALL.len()];
    let mut drain = |w: &mut Window| {
        if let Some(rx) = &rx {
            for e in rx.try_iter() {
                kinds[e.kind as usize] += 1;
                w.events += 1;
            }
        }
    };
    let created_now = |layer: &ContactLayer| {
        let now = layer.analysis().current_step();
        layer
            .analysis()
            .touched_edges()
            .filter(|(_, e)| e.created_step() == now)
            .count()
    };

    // Step 1 alone: everything is new to Rapier and to the layer (full sync).
    let heap_before = live();
    let (r, l, stats) = timed_step(&mut scene, &mut layer, 0);
    let first_step_heap = live() as isize - heap_before as isize;
    let mut first = Window {
        first: 1,
        last: 1,
        rapier: vec![r],
        layer: vec![l],
        awake_sum: stats.awake_bodies,
        created: created_now(&layer),
        ..Window::default()
    };
    drain(&mut first);
    let first_counts = count_graph(&layer, &scene.world);
    eprintln!(
        "scale: step 1: rapier {:.1} ms, layer {:.1} ms, {} nodes, {} edges",
        r * 1e3,
        l * 1e3,
        first_counts.nodes,
        first_counts.edges
    );

    // Warm-up (reported, not part of the churn figures).
    let mut warm = Window {
        first: 2,
        last: args.warmup.max(1),
        ..Window::default()
    };
    for step in 1..args.warmup.max(1) {
        let (r, l, stats) = timed_step(&mut scene, &mut layer, step);
        warm.rapier.push(r);
        warm.layer.push(l);
        warm.awake_sum += stats.awake_bodies;
        warm.created += created_now(&layer);
        drain(&mut warm);
    }
    let warm_counts = count_graph(&layer, &scene.world);
    eprintln!(
        "scale: warm-up to step {}: {} awake, {} edges",
        args.warmup.max(1),
        scene.world.islands.num_active_bodies(),
        warm_counts.edges
    );
    let churn_start = args.warmup.max(1);

    // The churn.
    let mut windows: Vec<(Window, GraphCounts)> = Vec::new();
    let mut w = Window {
        first: churn_start + 1,
        ..Window::default()
    };
    let mut bound_failures = Vec::new();
    let mut max_edges_per_node: f64 = 0.0;
    let mut max_far: usize = 0;
    let mut max_neighbours: usize = 0;
    for i in 1..=args.steps {
        let step = churn_start + i;
        let (r, l, stats) = timed_step(&mut scene, &mut layer, step - 1);
        w.rapier.push(r);
        w.layer.push(l);
        w.awake_sum += stats.awake_bodies;
        w.created += created_now(&layer);
        drain(&mut w);
        if i % args.every == 0 || i == args.steps {
            let c = count_graph(&layer, &scene.world);
            let per_node = c.edges as f64 / c.nodes as f64;
            max_edges_per_node = max_edges_per_node.max(per_node);
            max_far = max_far.max(c.lingering_far);
            max_neighbours = max_neighbours.max(c.max_neighbours);
            if per_node > EDGES_PER_NODE_BOUND {
                bound_failures.push(format!(
                    "step {step}: {} edges > {EDGES_PER_NODE_BOUND} x {} nodes",
                    c.edges, c.nodes
                ));
            }
            if c.max_neighbours > NEIGHBOURS_BOUND {
                bound_failures.push(format!(
                    "step {step}: a body has {} neighbour edges > {NEIGHBOURS_BOUND}",
                    c.max_neighbours
                ));
            }
            if c.lingering_far as f64 > FAR_LINGERING_PER_MOVER_BOUND * movers.max(1) as f64 {
                bound_failures.push(format!(
                    "step {step}: {} lingering edges already obsolete > {FAR_LINGERING_PER_MOVER_BOUND} x {movers} movers",
                    c.lingering_far
                ));
            }
            eprintln!(
                "scale: step {step:>6}: {:>7} edges ({:>6} lingering, {:>4} of them far), {:>5} awake, rapier {:.2} ms/step, layer {:.3} ms/step",
                c.edges,
                c.lingering,
                c.lingering_far,
                scene.world.islands.num_active_bodies(),
                w.rapier() / w.steps() as f64 * 1e3,
                w.layer() / w.steps() as f64 * 1e3
            );
            w.last = step;
            let next = Window {
                first: step + 1,
                ..Window::default()
            };
            windows.push((std::mem::replace(&mut w, next), c));
        }
    }
    let last = windows.last().map(|(_, c)| *c).unwrap_or(warm_counts);
    let t = Instant::now();
    layer
        .validate(&scene.world)
        .expect("validate() after the run");
    let validate_time = t.elapsed().as_secs_f64();
    let mut total = Window::default();
    for (w, _) in &windows {
        total.absorb(w);
    }

    // Memory: drop the layer, then the world, and see what each freed.
    let heap_end = live();
    let peak = PEAK.load(Relaxed);
    let group_count = layer.groups().len();
    let group_heap: usize = layer
        .groups()
        .iter()
        .map(|(_, g)| {
            std::mem::size_of::<(u32, Option<Group>)>()
                + (g.bodies.capacity() + g.insulators.capacity()) * std::mem::size_of::<NodeId>()
                + g.edges.capacity() * std::mem::size_of::<EdgeId>()
        })
        .sum();
    let body_count = scene.world.bodies.len();
    let collider_count = scene.world.colliders.len();
    drop(rx);
    let before = live();
    drop(layer);
    let layer_heap = before - live();
    let before = live();
    drop(scene);
    let world_heap = before - live();

    // ── Report ─────────────────────────────────────────────────────────
    println!();
    println!(
        "scale: {} resting bodies (created asleep) + {} balls + {} sweepers, {} sensors, {} timers; {} churn steps after {} warm-up steps (dt = {}); events {}",
        args.bodies,
        args.balls,
        args.sweepers,
        args.sensors,
        args.timers,
        args.steps,
        churn_start,
        scenes::DT,
        if args.events { "subscribed (all kinds, drained every step)" } else { "not subscribed" }
    );
    println!(
        "contact details {}",
        if args.details {
            "on (the default)"
        } else {
            "off (--no-details)"
        }
    );
    println!(
        "Rapier bodies {body_count}, colliders {collider_count}; wall time {:.1} s (build {build_time:.1} s)",
        wall.elapsed().as_secs_f64()
    );
    println!();
    println!("| steps | awake (mean) | Rapier ms/step | layer ms/step | layer/Rapier | nodes | Rapier pairs | edges | edges/node | neighbours max / mean | touching | lingering | of which far | created | removed | events |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    row("1 (first)", &first, &first_counts, None);
    let removed = (first_counts.edges + warm.created) as isize - warm_counts.edges as isize;
    row(
        &format!("{}–{} (warm-up)", warm.first, warm.last),
        &warm,
        &warm_counts,
        Some(removed),
    );
    let mut prev_edges = warm_counts.edges;
    for (w, c) in &windows {
        let removed = (prev_edges + w.created) as isize - c.edges as isize;
        row(&format!("{}–{}", w.first, w.last), w, c, Some(removed));
        prev_edges = c.edges;
    }
    let ratios: Vec<f64> = total
        .layer
        .iter()
        .zip(&total.rapier)
        .map(|(l, r)| l / r)
        .collect();
    println!();
    println!(
        "| churn, steps {}–{} | value |",
        churn_start + 1,
        churn_start + args.steps
    );
    println!("|---|---|");
    println!("| Rapier total | {:.2} s |", total.rapier());
    println!(
        "| layer total (pre-step + analysis) | {:.2} s |",
        total.layer()
    );
    println!(
        "| layer / Rapier (sums) | {:.2} % |",
        total.layer() / total.rapier() * 100.0
    );
    println!(
        "| layer / Rapier (median per step) | {:.2} % |",
        median(&ratios) * 100.0
    );
    println!(
        "| Rapier per step (median) | {:.3} ms |",
        median(&total.rapier) * 1e3
    );
    println!(
        "| layer per step (median) | {:.3} ms |",
        median(&total.layer) * 1e3
    );
    println!(
        "| awake bodies (mean) | {:.0} |",
        total.awake_sum as f64 / total.steps() as f64
    );
    println!(
        "| layer per awake body and step (sums) | {:.2} µs (Rapier {:.2} µs) |",
        total.layer() / total.awake_sum as f64 * 1e6,
        total.rapier() / total.awake_sum as f64 * 1e6
    );
    println!("| one `validate()` at the end (not in the figures above) | {validate_time:.2} s |");
    println!();

    let (nodes, edges) = (last.nodes, last.edges);
    let node_sz = std::mem::size_of::<Node>();
    let edge_sz = std::mem::size_of::<Edge>();
    let id_sz = std::mem::size_of::<EdgeId>();
    // Arena slot: a u32 generation plus Option<T> (estimated with a tuple of the same
    // fields); pair map: key + value + 1 control byte at hashbrown's 7/8 load factor.
    let node_slot = std::mem::size_of::<(u32, Option<Node>)>();
    let edge_slot = std::mem::size_of::<(u32, Option<Edge>)>();
    let map_entry = (std::mem::size_of::<PairKey>() + id_sz + 1) as f64 / 0.875;
    let adjacency_bytes = last.adjacency_entries * id_sz;
    let body_map = body_count * std::mem::size_of::<Option<NodeId>>();
    let per_node = node_slot as f64 + (adjacency_bytes + body_map) as f64 / nodes as f64;
    let per_edge = edge_slot as f64 + map_entry + 2.0 * id_sz as f64;
    let estimate = nodes * node_slot
        + edges * edge_slot
        + (edges as f64 * map_entry) as usize
        + adjacency_bytes
        + body_map;
    println!(
        "| memory (after step {}) | value |",
        churn_start + args.steps
    );
    println!("|---|---|");
    println!(
        "| nodes / edges | {nodes} ({} triggers, {} timers) / {edges} ({} physical, {} geometric) |",
        last.triggers, last.timers, last.physical, last.geometric
    );
    println!("| size_of::<Node>() / arena slot | {node_sz} B / {node_slot} B |");
    println!("| size_of::<Edge>() / arena slot | {edge_sz} B / {edge_slot} B |");
    println!("| size_of::<EdgeId>() (one adjacency entry) | {id_sz} B |");
    println!(
        "| pair map entry (PairKey + EdgeId + 1 ctrl byte, / 0.875 load) | {map_entry:.1} B |"
    );
    println!(
        "| adjacency entries, sum of node.edges().len() | {} (= 2 × edges), {} B = {:.1} B/node; max degree {} |",
        last.adjacency_entries,
        adjacency_bytes,
        adjacency_bytes as f64 / nodes as f64,
        last.max_degree
    );
    println!("| per node: slot + adjacency lengths × 8 B + body map entry | {per_node:.1} B |");
    println!("| per edge: slot + pair map entry + 2 adjacency entries | {per_edge:.1} B |");
    println!(
        "| graph estimate from the above (lengths, not capacities) | {} |",
        mib(estimate)
    );
    println!(
        "| contact groups: {group_count}, arena slots + member Vec capacities | {} = {:.1} B/group |",
        mib(group_heap),
        group_heap as f64 / group_count.max(1) as f64
    );
    println!(
        "| rest of the layer (measured − graph estimate − groups): capacity slack, analysis scratch, Rapier-pair and collider tables, timers, events | {} |",
        mib(layer_heap.saturating_sub(estimate + group_heap))
    );
    println!(
        "| layer heap, measured exactly (freed when dropped at the end) | {} = {:.1} B/node, {:.1} B per (node + edge) |",
        mib(layer_heap),
        layer_heap as f64 / nodes as f64,
        layer_heap as f64 / (nodes + edges) as f64
    );
    println!(
        "| heap growth in step 1 (Rapier's first step + the layer's first analysis) | {} |",
        mib(first_step_heap.max(0) as usize)
    );
    println!(
        "| Rapier world heap, measured exactly (freed when dropped at the end) | {} = {:.1} B/body |",
        mib(world_heap),
        world_heap as f64 / body_count as f64
    );
    println!(
        "| Rapier world heap when built, before any step | {} |",
        mib(world_built_heap)
    );
    println!(
        "| process heap at the end / peak | {} / {} |",
        mib(heap_end),
        mib(peak)
    );
    println!();
    println!("| edges stay O(n) | value |");
    println!("|---|---|");
    println!(
        "| edges after step 1 / after warm-up / at the end | {} / {} / {} |",
        first_counts.edges, warm_counts.edges, last.edges
    );
    println!(
        "| edges created / removed during the churn | {} / {} |",
        total.created,
        (warm_counts.edges + total.created) as isize - last.edges as isize
    );
    println!("| max edges per node at a report | {max_edges_per_node:.3} (bound {EDGES_PER_NODE_BOUND}) |");
    println!("| max neighbour edges of a dynamic body at a report | {max_neighbours} (bound {NEIGHBOURS_BOUND}) |");
    println!(
        "| max lingering edges already obsolete at a report | {max_far} (bound {FAR_LINGERING_PER_MOVER_BOUND} × {movers} movers = {}) |",
        (FAR_LINGERING_PER_MOVER_BOUND * movers as f64) as usize
    );
    if args.events {
        let kinds_line: Vec<String> = EventKind::ALL
            .iter()
            .map(|&k| format!("{k:?} {}", kinds[k as usize]))
            .collect();
        println!("| events, all steps | {} |", kinds_line.join(", "));
    }
    if !bound_failures.is_empty() {
        eprintln!("scale: edge bound violated:\n{}", bound_failures.join("\n"));
        std::process::exit(1);
    }
    println!("edge bounds held at every report");
}
