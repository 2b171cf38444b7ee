//! The debug-render overlay tests' recording backend and scenes (`tests/debug_render_*.rs`).
#![allow(dead_code)]

use rapier3d::prelude::*;
use rapier_contact_graph::debug_render::{GraphOverlay, OverlayStats, OverlayStyle};
use rapier_contact_graph::ContactLayer;

// ── A recording backend ────────────────────────────────────────────────────

/// The object a line was drawn for, without its borrow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obj {
    Body(RigidBodyHandle),
    Collider(ColliderHandle),
    Other,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    pub obj: Obj,
    pub a: Vector,
    pub b: Vector,
    pub color: DebugColor,
}

impl Line {
    /// Bit patterns, for exact comparisons.
    pub fn bits(&self) -> (Obj, [u32; 10]) {
        let (a, b, c) = (self.a, self.b, self.color);
        (
            self.obj,
            [
                a.x.to_bits(),
                a.y.to_bits(),
                a.z.to_bits(),
                b.x.to_bits(),
                b.y.to_bits(),
                b.z.to_bits(),
                c[0].to_bits(),
                c[1].to_bits(),
                c[2].to_bits(),
                c[3].to_bits(),
            ],
        )
    }
}

/// Stores every line; hides the listed objects through `filter_object`.
#[derive(Default)]
pub struct Recorder {
    pub lines: Vec<Line>,
    pub hide_bodies: Vec<RigidBodyHandle>,
    pub hide_colliders: Vec<ColliderHandle>,
}

impl DebugRenderBackend for Recorder {
    fn filter_object(&self, object: DebugRenderObject) -> bool {
        match object {
            DebugRenderObject::RigidBody(h, _) => !self.hide_bodies.contains(&h),
            DebugRenderObject::Collider(h, _) => !self.hide_colliders.contains(&h),
            _ => true,
        }
    }

    fn draw_line(&mut self, object: DebugRenderObject, a: Vector, b: Vector, color: DebugColor) {
        let obj = match object {
            DebugRenderObject::RigidBody(h, _) => Obj::Body(h),
            DebugRenderObject::Collider(h, _) => Obj::Collider(h),
            _ => Obj::Other,
        };
        self.lines.push(Line { obj, a, b, color });
    }
}

// ── Helpers ────────────────────────────────────────────────────────────────

pub fn run(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

/// A style drawing nothing; tests switch on the one layer they look at.
pub fn nothing() -> OverlayStyle {
    OverlayStyle {
        touching_edges: false,
        proximity_edges: false,
        trigger_edges: false,
        structural_edges: false,
        state_markers: false,
        ..OverlayStyle::default()
    }
}

pub fn render_with(
    style: OverlayStyle,
    backend: &mut Recorder,
    layer: &ContactLayer,
    world: &PhysicsWorld,
) -> OverlayStats {
    GraphOverlay::new(style).render(backend, layer, &world.bodies, &world.colliders)
}

pub fn render(
    style: OverlayStyle,
    layer: &ContactLayer,
    world: &PhysicsWorld,
) -> (Recorder, OverlayStats) {
    let mut rec = Recorder::default();
    let stats = render_with(style, &mut rec, layer, world);
    (rec, stats)
}

pub fn close(a: Vector, b: Vector) -> bool {
    (a - b).length() < 1e-4
}

pub fn com(world: &PhysicsWorld, h: RigidBodyHandle) -> Vector {
    world.bodies[h].center_of_mass()
}

pub fn ground(world: &mut PhysicsWorld) -> RigidBodyHandle {
    // Top face at y = 0.
    world
        .insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
            ColliderBuilder::cuboid(10.0, 0.5, 10.0),
        )
        .0
}

pub fn ball(world: &mut PhysicsWorld, x: f32, y: f32, r: f32) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0)),
            ColliderBuilder::ball(r),
        )
        .0
}

pub fn new_world() -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world
}

/// Ground, a pile of two balls at x = 0 (`a0` under `a1`), a lone ball at x = 3 and a
/// pile at x = −3 (`c0` under `c1`): three contact groups, five touching pairs.
pub struct Balls {
    pub world: PhysicsWorld,
    pub ground: RigidBodyHandle,
    pub a: [RigidBodyHandle; 2],
    pub lone: RigidBodyHandle,
    pub c: [RigidBodyHandle; 2],
}

pub fn balls() -> Balls {
    let mut world = new_world();
    let ground = ground(&mut world);
    let a = [
        ball(&mut world, 0.0, 0.5, 0.5),
        ball(&mut world, 0.0, 1.5, 0.5),
    ];
    let lone = ball(&mut world, 3.0, 0.5, 0.5);
    let c = [
        ball(&mut world, -3.0, 0.5, 0.5),
        ball(&mut world, -3.0, 1.5, 0.5),
    ];
    Balls {
        world,
        ground,
        a,
        lone,
        c,
    }
}

/// The one line with these two ends (either order); panics if there is not exactly one.
pub fn line_between(lines: &[Line], p: Vector, q: Vector) -> Line {
    let found: Vec<&Line> = lines
        .iter()
        .filter(|l| (close(l.a, p) && close(l.b, q)) || (close(l.a, q) && close(l.b, p)))
        .collect();
    assert_eq!(found.len(), 1, "lines between {p:?} and {q:?}: {found:?}");
    *found[0]
}

/// The point under a ball's centre on the ground's top face.
pub fn below(p: Vector) -> Vector {
    Vector::new(p.x, 0.0, p.z)
}

/// Ground, a sensor box (y from 0.2 to 1.8, not touching the ground) with a ball resting
/// inside, and a ball outside.
pub fn sensor_scene() -> (
    PhysicsWorld,
    ColliderHandle,
    RigidBodyHandle,
    RigidBodyHandle,
) {
    let mut world = new_world();
    ground(&mut world);
    let sensor = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.8, 1.0)
            .sensor(true)
            .translation(Vector::new(0.0, 1.0, 0.0)),
        None,
    );
    let inside = ball(&mut world, 0.0, 0.5, 0.5);
    let outside = ball(&mut world, 4.0, 0.5, 0.5);
    (world, sensor, inside, outside)
}
