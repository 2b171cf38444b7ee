//! The contact graph as a debug-render overlay : what
//! `debug_render::GraphOverlay` draws into a Rapier `DebugRenderBackend`, on small
//! scenes built here. Every step is followed by `layer.validate(&world)`.

#![cfg(feature = "debug-render")]

use rapier3d::prelude::*;
use rapier_contact_graph::debug_render::{
    group_key, BodyState, GraphOverlay, MarkerShape, OverlayStats, OverlayStyle,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, EdgeKind, NodeKind, WorldView};

// ── A recording backend ────────────────────────────────────────────────────

/// The object a line was drawn for, without its borrow.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Obj {
    Body(RigidBodyHandle),
    Collider(ColliderHandle),
    Other,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Line {
    obj: Obj,
    a: Vector,
    b: Vector,
    color: DebugColor,
}

impl Line {
    /// Bit patterns, for exact comparisons.
    fn bits(&self) -> (Obj, [u32; 10]) {
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
struct Recorder {
    lines: Vec<Line>,
    hide_bodies: Vec<RigidBodyHandle>,
    hide_colliders: Vec<ColliderHandle>,
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

fn run(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(world).unwrap();
    }
}

/// A style drawing nothing; tests switch on the one layer they look at.
fn nothing() -> OverlayStyle {
    OverlayStyle {
        touching_edges: false,
        proximity_edges: false,
        trigger_edges: false,
        structural_edges: false,
        state_markers: false,
        ..OverlayStyle::default()
    }
}

fn render_with(
    style: OverlayStyle,
    backend: &mut Recorder,
    layer: &ContactLayer,
    world: &PhysicsWorld,
) -> OverlayStats {
    GraphOverlay::new(style).render(backend, layer, &world.bodies, &world.colliders)
}

fn render(
    style: OverlayStyle,
    layer: &ContactLayer,
    world: &PhysicsWorld,
) -> (Recorder, OverlayStats) {
    let mut rec = Recorder::default();
    let stats = render_with(style, &mut rec, layer, world);
    (rec, stats)
}

fn close(a: Vector, b: Vector) -> bool {
    (a - b).length() < 1e-4
}

fn com(world: &PhysicsWorld, h: RigidBodyHandle) -> Vector {
    world.bodies[h].center_of_mass()
}

fn ground(world: &mut PhysicsWorld) -> RigidBodyHandle {
    // Top face at y = 0.
    world
        .insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
            ColliderBuilder::cuboid(10.0, 0.5, 10.0),
        )
        .0
}

fn ball(world: &mut PhysicsWorld, x: f32, y: f32, r: f32) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0)),
            ColliderBuilder::ball(r),
        )
        .0
}

fn new_world() -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world
}

/// Ground, a pile of two balls at x = 0 (`a0` under `a1`), a lone ball at x = 3 and a
/// pile at x = −3 (`c0` under `c1`): three contact groups, five touching pairs.
struct Balls {
    world: PhysicsWorld,
    ground: RigidBodyHandle,
    a: [RigidBodyHandle; 2],
    lone: RigidBodyHandle,
    c: [RigidBodyHandle; 2],
}

fn balls() -> Balls {
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
fn line_between(lines: &[Line], p: Vector, q: Vector) -> Line {
    let found: Vec<&Line> = lines
        .iter()
        .filter(|l| (close(l.a, p) && close(l.b, q)) || (close(l.a, q) && close(l.b, p)))
        .collect();
    assert_eq!(found.len(), 1, "lines between {p:?} and {q:?}: {found:?}");
    *found[0]
}

/// The point under a ball's centre on the ground's top face.
fn below(p: Vector) -> Vector {
    Vector::new(p.x, 0.0, p.z)
}

// ── Touching edges and groups ──────────────────────────────────────────────

#[test]
fn one_touching_line_per_touching_pair_in_its_group_colour() {
    let Balls {
        mut world,
        ground,
        a,
        lone,
        c,
    } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 20);

    let style = OverlayStyle {
        touching_edges: true,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    let touching = layer
        .graph()
        .edges()
        .filter(|(_, e)| e.kind() == EdgeKind::Physical && e.is_touching())
        .count();
    assert_eq!(
        touching, 5,
        "ground–a0, a0–a1, ground–lone, ground–c0, c0–c1"
    );
    assert_eq!(stats.touching, touching);
    assert_eq!(rec.lines.len(), touching, "one line per touching edge");
    assert_eq!(stats.lines, rec.lines.len());
    assert_eq!(
        (stats.unplaced_nodes, stats.skipped_edges, stats.filtered),
        (0, 0, 0)
    );

    // Between the balls' centres of mass; on the ground, from the point under the ball.
    let p = |h| com(&world, h);
    let a_top = line_between(&rec.lines, p(a[0]), p(a[1]));
    let a_low = line_between(&rec.lines, below(p(a[0])), p(a[0]));
    let lone_l = line_between(&rec.lines, below(p(lone)), p(lone));
    let c_top = line_between(&rec.lines, p(c[0]), p(c[1]));
    let c_low = line_between(&rec.lines, below(p(c[0])), p(c[0]));

    // Each in the colour keyed by its group's smallest member.
    let color_of = |h| {
        let n = layer.node_of_body(h).unwrap();
        let g = layer.graph().node(n).unwrap().group().unwrap();
        style.group_color(group_key(layer.groups().get(g).unwrap()).unwrap())
    };
    assert_eq!(a_top.color, color_of(a[0]));
    assert_eq!(a_low.color, color_of(a[0]));
    assert_eq!(lone_l.color, color_of(lone));
    assert_eq!(c_top.color, color_of(c[0]));
    assert_eq!(c_low.color, color_of(c[0]));
    // Equal within a group, different across groups.
    assert_eq!(a_top.color, a_low.color);
    assert_eq!(c_top.color, c_low.color);
    assert_ne!(a_top.color, lone_l.color);
    assert_ne!(a_top.color, c_top.color);
    assert_ne!(lone_l.color, c_top.color);

    // Every line is drawn for a dynamic ball, never for the ground.
    for l in &rec.lines {
        assert!(
            matches!(l.obj, Obj::Body(h) if h != ground),
            "line for {:?}",
            l.obj
        );
    }
}

#[test]
fn group_colours_stay_when_a_group_is_rebuilt() {
    // A third ball lands on pile a: the contact that begins rebuilds the group, under a
    // new id; its smallest member, and so its colour, stay.
    let Balls { mut world, a, .. } = balls();
    let dropped = ball(&mut world, 0.0, 4.0, 0.5);
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let style = OverlayStyle {
        touching_edges: true,
        ..nothing()
    };
    let group_of = |layer: &ContactLayer| {
        let n = layer.node_of_body(a[0]).unwrap();
        layer.graph().node(n).unwrap().group().unwrap()
    };
    let pile_color = |layer: &ContactLayer, world: &PhysicsWorld| {
        let (rec, _) = render(style, layer, world);
        let p = |h| com(world, h);
        line_between(&rec.lines, p(a[0]), p(a[1])).color
    };
    let (g1, c1) = (group_of(&layer), pile_color(&layer, &world));
    for _ in 0..100 {
        run(&mut layer, &mut world, 1);
        assert_eq!(
            pile_color(&layer, &world),
            c1,
            "same colour, step after step"
        );
    }
    let (na, nd) = (
        layer.node_of_body(a[1]).unwrap(),
        layer.node_of_body(dropped).unwrap(),
    );
    assert!(layer.graph().touching(na).any(|n| n == nd), "it landed");
    assert_ne!(group_of(&layer), g1, "the group was rebuilt under a new id");
}

#[test]
fn touching_edges_without_group_colours_take_the_plain_colour() {
    let Balls { mut world, .. } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let style = OverlayStyle {
        touching_edges: true,
        group_colors: false,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(stats.touching, 5);
    assert!(rec.lines.iter().all(|l| l.color == style.touching_color));
}

#[test]
fn an_edge_on_a_half_space_ends_on_its_plane() {
    let mut world = new_world();
    world.insert_collider(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Y)),
        None,
    );
    let b = ball(&mut world, 1.0, 0.5, 0.5);
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 10);

    let (rec, stats) = render(OverlayStyle::default(), &layer, &world);
    assert_eq!(stats.touching, 1);
    assert_eq!(stats.unplaced_nodes, 1, "a half-space has no centre");
    assert_eq!(stats.markers, 1, "only the ball's");
    assert_eq!(stats.skipped_edges, 0);
    let p = com(&world, b);
    let l = line_between(&rec.lines, below(p), p);
    assert_eq!(l.obj, Obj::Body(b));
}

#[test]
fn scenery_anchoring_can_be_switched_off() {
    let Balls {
        mut world,
        ground,
        lone,
        ..
    } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let style = OverlayStyle {
        touching_edges: true,
        anchor_on_scenery: false,
        ..nothing()
    };
    let (rec, _) = render(style, &layer, &world);
    line_between(&rec.lines, com(&world, ground), com(&world, lone));
}

// ── Trigger edges ──────────────────────────────────────────────────────────

/// Ground, a sensor box (y from 0.2 to 1.8, not touching the ground) with a ball resting
/// inside, and a ball outside.
fn sensor_scene() -> (
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

#[test]
fn a_trigger_edge_is_a_dashed_line_from_the_sensor_to_the_body_inside() {
    let (mut world, sensor, inside, _) = sensor_scene();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 10);
    let geometric = layer
        .graph()
        .edges()
        .filter(|(_, e)| e.kind() == EdgeKind::Geometric)
        .count();
    assert_eq!(geometric, 1);

    let style = OverlayStyle {
        trigger_edges: true,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(stats.trigger, 1);
    let dashes = style.trigger_dashes as usize;
    assert_eq!(rec.lines.len(), dashes);
    assert_eq!(stats.lines, dashes);
    let centre = Vector::new(0.0, 1.0, 0.0);
    let p = com(&world, inside);
    assert!(close(rec.lines[0].a, centre), "from the sensor's centre");
    assert!(
        close(rec.lines[dashes - 1].b, p),
        "to the body's centre of mass"
    );
    let dir = (p - centre).normalize();
    for (i, l) in rec.lines.iter().enumerate() {
        assert_eq!(l.color, style.trigger_color);
        assert_eq!(l.obj, Obj::Body(inside), "drawn for the body inside");
        // On the segment, in order, with gaps between the dashes.
        for q in [l.a, l.b] {
            assert!(((q - centre) - dir * (q - centre).dot(dir)).length() < 1e-4);
        }
        if i > 0 {
            let gap = (l.a - rec.lines[i - 1].b).length();
            assert!(gap > 0.05, "a gap before dash {i}");
        }
    }

    // One dash: a solid line.
    let (rec, _) = render(
        OverlayStyle {
            trigger_dashes: 1,
            ..style
        },
        &layer,
        &world,
    );
    assert_eq!(rec.lines.len(), 1);
    assert!(close(rec.lines[0].a, centre) && close(rec.lines[0].b, p));

    // A backend hiding the sensor hides its trigger lines.
    let mut rec = Recorder {
        hide_colliders: vec![sensor],
        ..Recorder::default()
    };
    let stats = render_with(style, &mut rec, &layer, &world);
    assert!(rec.lines.is_empty());
    assert_eq!((stats.trigger, stats.filtered), (0, 1));
}

// ── Structural edges ───────────────────────────────────────────────────────

#[test]
fn structural_edges_run_from_a_container_hub_to_each_member() {
    let mut world = new_world();
    ground(&mut world);
    // A composite: two boxes welded by a fixed joint.
    let (b1, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let (b2, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(6.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    world.insert_impulse_joint(
        b1,
        b2,
        FixedJointBuilder::new().local_anchor2(Vector::new(-1.0, 0.0, 0.0)),
    );
    // A multibody: two balls hinged together, lying on the ground.
    let m1 = ball(&mut world, -3.5, 0.5, 0.5);
    let m2 = ball(&mut world, -2.5, 0.5, 0.5);
    let hinge = RevoluteJointBuilder::new(Vector::Z)
        .local_anchor1(Vector::new(0.5, 0.0, 0.0))
        .local_anchor2(Vector::new(-0.5, 0.0, 0.0));
    world.insert_multibody_joint(m1, m2, hinge).unwrap();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 10);

    let graph = layer.graph();
    assert_eq!(graph.count_of_kind(NodeKind::Composite), 1);
    assert_eq!(graph.count_of_kind(NodeKind::Multibody), 1);
    let structural = graph
        .edges()
        .filter(|(_, e)| e.kind() == EdgeKind::Structural)
        .count();
    assert_eq!(structural, 4);

    let style = OverlayStyle {
        structural_edges: true,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(stats.structural, 4);
    assert_eq!(rec.lines.len(), 4);
    for (x, y) in [(b1, b2), (m1, m2)] {
        let (p, q) = (com(&world, x), com(&world, y));
        let hub = (p + q) * 0.5;
        for (h, c) in [(x, p), (y, q)] {
            let l = line_between(&rec.lines, hub, c);
            assert_eq!(l.color, style.structural_color);
            assert_eq!(l.obj, Obj::Body(h), "drawn for the member");
        }
    }
}

// ── Body states ────────────────────────────────────────────────────────────

/// The marker lines drawn for `h` (12 for an octahedron) and their centre.
fn marker_of(rec: &Recorder, h: RigidBodyHandle) -> (Vec<Line>, Vector) {
    let lines: Vec<Line> = rec
        .lines
        .iter()
        .filter(|l| l.obj == Obj::Body(h))
        .copied()
        .collect();
    let sum = lines.iter().fold(Vector::ZERO, |s, l| s + l.a + l.b);
    let centre = sum / (2 * lines.len().max(1)) as f32;
    (lines, centre)
}

fn assert_marker(
    rec: &Recorder,
    style: &OverlayStyle,
    world: &PhysicsWorld,
    h: RigidBodyHandle,
    state: BodyState,
) {
    let (lines, centre) = marker_of(rec, h);
    assert_eq!(lines.len(), style.marker.lines(), "{state:?}");
    assert!(
        close(centre, com(world, h)),
        "{state:?}: centred on the body"
    );
    for l in &lines {
        assert_eq!(l.color, style.states.get(state), "{state:?}");
        assert!((l.a - l.b).length() <= 2.0 * style.marker_size + 1e-5);
    }
}

#[test]
fn markers_show_asleep_resting_moving_passive_and_insulator() {
    let mut world = new_world();
    let g = ground(&mut world);
    let resting = ball(&mut world, 0.0, 0.5, 0.5);
    let falling = ball(&mut world, 3.0, 100.0, 0.5);
    let passive = ball(&mut world, -3.0, 0.5, 0.5);
    let (platform, _) = world.insert(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(6.0, 2.0, 0.0))
            .linvel(Vector::new(0.0, 0.0, 0.1)),
        ColliderBuilder::cuboid(1.0, 0.1, 1.0),
    );
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 1);
    layer.set_passive(passive, true).unwrap();
    run(&mut layer, &mut world, 19);
    assert!(!world.bodies[resting].is_sleeping(), "awake after 0.2 s");

    let style = OverlayStyle {
        state_markers: true,
        ..nothing()
    };
    let state = |layer: &ContactLayer, world: &PhysicsWorld, h| {
        BodyState::of(
            layer,
            &world.bodies,
            layer.node_of_body(h).unwrap(),
            style.rest_speed,
        )
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(stats.markers, 5);
    assert_eq!(rec.lines.len(), 5 * 12);
    for (h, s) in [
        (g, BodyState::Insulator),
        (platform, BodyState::Insulator),
        (resting, BodyState::Resting),
        (falling, BodyState::Moving),
        (passive, BodyState::Passive),
    ] {
        assert_eq!(state(&layer, &world, h), Some(s));
        assert_marker(&rec, &style, &world, h, s);
    }

    // Rapier puts the resting ball to sleep.
    run(&mut layer, &mut world, 300);
    assert!(world.bodies[resting].is_sleeping());
    assert!(layer.holds(&world.bodies, resting));
    let style = OverlayStyle {
        marker: MarkerShape::Cross,
        ..style
    };
    let (rec, _) = render(style, &layer, &world);
    assert_eq!(state(&layer, &world, resting), Some(BodyState::Asleep));
    assert_marker(&rec, &style, &world, resting, BodyState::Asleep);
    assert_marker(&rec, &style, &world, falling, BodyState::Moving);
}

#[test]
fn markers_show_bodies_held_by_fixation() {
    let mut world = new_world();
    let g = ground(&mut world);
    let (bx, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let falling = ball(&mut world, 5.0, 200.0, 0.5);
    let mut layer = ContactLayer::new();
    layer
        .set_speedups(Some(SpeedUps {
            fixate: true,
            subgroup: true,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    let mut held_at = None;
    for step in 0..300 {
        run(&mut layer, &mut world, 1);
        if layer.speedups().unwrap().is_fixated(bx) {
            held_at = Some(step);
            break;
        }
    }
    assert!(held_at.is_some(), "the resting box was fixated");
    run(&mut layer, &mut world, 5);
    assert!(layer.speedups().unwrap().is_fixated(bx));

    let style = OverlayStyle {
        state_markers: true,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(stats.markers, 3);
    for (h, s) in [
        (bx, BodyState::Held),
        (g, BodyState::Insulator),
        (falling, BodyState::Moving),
    ] {
        let n = layer.node_of_body(h).unwrap();
        assert_eq!(
            BodyState::of(&layer, &world.bodies, n, style.rest_speed),
            Some(s)
        );
        assert_marker(&rec, &style, &world, h, s);
    }
    // A held body is not scenery: a ball set down on the held box gets a line to the
    // box's centre of mass, not to the point of the box under it.
    let top = ball(&mut world, 0.0, 1.5, 0.5);
    run(&mut layer, &mut world, 2);
    assert!(layer.speedups().unwrap().is_fixated(bx), "still held");
    let style = OverlayStyle {
        touching_edges: true,
        ..nothing()
    };
    let (rec, stats) = render(style, &layer, &world);
    assert_eq!(
        stats.touching, 1,
        "ball–box (the held box no longer touches the ground)"
    );
    let l = line_between(&rec.lines, com(&world, bx), com(&world, top));
    assert_eq!(l.obj, Obj::Body(top), "drawn for the dynamic end");
}

#[test]
fn markers_show_sleepy_bodies_in_an_awake_island() {
    // A box at rest (sleepy) carrying a frictionless ball that spins in place (never
    // sleepy): the island stays awake, so the box is sleepy but awake.
    let mut world = new_world();
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(20.0, 0.5, 20.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let (bx, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.0),
    );
    let (spinner, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 1.3, 0.0))
            .angvel(Vector::new(0.0, 10.0, 0.0)),
        ColliderBuilder::ball(0.3).friction(0.0),
    );
    let mut layer = ContactLayer::new();
    layer
        .set_speedups(Some(SpeedUps {
            sleepy_steps: 5,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    run(&mut layer, &mut world, 60);
    assert!(layer.speedups().unwrap().is_sleepy(bx));
    assert!(!world.bodies[bx].is_sleeping());

    let style = OverlayStyle {
        state_markers: true,
        ..nothing()
    };
    let (rec, _) = render(style, &layer, &world);
    assert_marker(&rec, &style, &world, bx, BodyState::Sleepy);
    assert_marker(&rec, &style, &world, spinner, BodyState::Moving);
}

// ── Determinism, robustness, composition ───────────────────────────────────

/// Balls, a sensor and a welded pair, stepped `steps` times, drawn with every layer on.
fn everything(steps: usize) -> (Vec<(Obj, [u32; 10])>, OverlayStats) {
    let Balls { mut world, .. } = balls();
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.8, 1.0)
            .sensor(true)
            .translation(Vector::new(3.0, 1.0, 0.0)),
        None,
    );
    let (b1, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(6.0, 2.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let (b2, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(7.0, 2.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    world.insert_impulse_joint(
        b1,
        b2,
        FixedJointBuilder::new().local_anchor2(Vector::new(-1.0, 0.0, 0.0)),
    );
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, steps);
    let style = OverlayStyle {
        proximity_edges: true,
        ..OverlayStyle::default()
    };
    let mut overlay = GraphOverlay::new(style);
    let mut rec = Recorder::default();
    let stats = overlay.render_view(&mut rec, &layer, &WorldView::from(&world));
    // A second call with the same overlay (reused buffers) draws the same.
    let mut again = Recorder::default();
    assert_eq!(
        overlay.render_view(&mut again, &layer, &WorldView::from(&world)),
        stats
    );
    assert_eq!(again.lines, rec.lines);
    (rec.lines.iter().map(Line::bits).collect(), stats)
}

#[test]
fn same_inputs_give_the_same_lines_in_the_same_order() {
    let (first, s1) = everything(40);
    let (second, s2) = everything(40);
    assert_eq!(s1, s2);
    assert_eq!(first, second, "bit for bit, in order");
    assert!(s1.touching > 0 && s1.trigger > 0 && s1.structural > 0 && s1.markers > 0);
    assert_eq!(first.len(), s1.lines);
}

#[test]
fn stale_removed_and_non_finite_bodies_are_skipped_without_panic() {
    let Balls {
        mut world, a, lone, ..
    } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 20);
    let before = render(OverlayStyle::default(), &layer, &world).1;
    assert_eq!(before.markers, 6);

    // Removed from the world, not yet analysed: the layer still has its node.
    world.remove_body(a[1]);
    let (rec, stats) = render(OverlayStyle::default(), &layer, &world);
    assert!(rec.lines.iter().all(|l| l.obj != Obj::Body(a[1])));
    assert_eq!(stats.unplaced_nodes, 1);
    assert_eq!(stats.skipped_edges, 1, "a0–a1");
    assert_eq!(stats.markers, 5);
    assert_eq!(stats.touching, before.touching - 1);

    // A non-finite pose: its marker and its edge go.
    world.bodies[lone].set_translation(Vector::new(f32::NAN, 0.5, 0.0), false);
    let (rec, stats) = render(OverlayStyle::default(), &layer, &world);
    assert!(rec.lines.iter().all(|l| l.obj != Obj::Body(lone)));
    assert!(rec
        .lines
        .iter()
        .all(|l| l.a.is_finite() && l.b.is_finite() && l.color.iter().all(|c| c.is_finite())));
    assert_eq!(stats.unplaced_nodes, 2);
    assert_eq!(stats.skipped_edges, 2);
    assert_eq!(stats.markers, 4);

    // Foreign (empty) sets: nothing placed, nothing drawn.
    let mut rec = Recorder::default();
    let stats =
        GraphOverlay::default().render(&mut rec, &layer, &RigidBodySet::new(), &ColliderSet::new());
    assert!(rec.lines.is_empty());
    assert_eq!(stats.lines, 0);
    assert_eq!(stats.unplaced_nodes, layer.graph().node_count());

    // Back to a finite pose; the layer catches up with the removal.
    world.bodies[lone].set_translation(Vector::new(3.0, 0.5, 0.0), false);
    run(&mut layer, &mut world, 5);
    let (_, stats) = render(OverlayStyle::default(), &layer, &world);
    assert_eq!((stats.unplaced_nodes, stats.skipped_edges), (0, 0));
    assert_eq!(stats.markers, 5);
}

#[test]
fn a_backend_hiding_a_body_hides_its_marker_and_edges() {
    let Balls {
        mut world, a, lone, ..
    } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 20);
    let mut rec = Recorder {
        hide_bodies: vec![a[0]],
        ..Recorder::default()
    };
    let stats = render_with(OverlayStyle::default(), &mut rec, &layer, &world);
    assert_eq!(stats.filtered, 3, "its marker, a0–ground and a0–a1");
    let p0 = com(&world, a[0]);
    assert!(rec
        .lines
        .iter()
        .all(|l| l.obj != Obj::Body(a[0]) && !close(l.a, p0) && !close(l.b, p0)));
    // a1's marker and the other edges are still there.
    assert_eq!(marker_of(&rec, a[1]).0.len(), 12);
    assert_eq!(stats.touching, 3);
    line_between(&rec.lines, below(com(&world, lone)), com(&world, lone));
}

#[test]
fn composes_with_rapiers_debug_render_pipeline_on_one_backend() {
    let Balls { mut world, .. } = balls();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 20);

    let mut rec = Recorder::default();
    let mut pipeline = DebugRenderPipeline::render_all(DebugRenderStyle::default());
    pipeline.render(
        &mut rec,
        &world.bodies,
        &world.colliders,
        &world.impulse_joints,
        &world.multibody_joints,
        &world.narrow_phase,
        &world.soft_bodies,
    );
    let rapier = rec.lines.len();
    assert!(rapier > 0);
    let mut overlay = GraphOverlay::default();
    let stats = overlay.render(&mut rec, &layer, &world.bodies, &world.colliders);
    assert_eq!(rec.lines.len(), rapier + stats.lines);

    // The overlay's lines follow Rapier's, as drawn alone.
    let (alone, _) = render(OverlayStyle::default(), &layer, &world);
    assert_eq!(&rec.lines[rapier..], &alone.lines[..]);

    // A `dyn` backend works as well.
    let dyn_backend: &mut dyn DebugRenderBackend = &mut Recorder::default();
    assert_eq!(
        overlay.render(dyn_backend, &layer, &world.bodies, &world.colliders),
        stats
    );
}

#[test]
fn group_hues_of_neighbouring_keys_are_far_apart() {
    let style = OverlayStyle::default();
    let hues: Vec<f32> = (0..16).map(|k| style.group_color(k)[0]).collect();
    for (i, h) in hues.iter().enumerate() {
        assert!((0.0..360.0).contains(h));
        for g in &hues[i + 1..] {
            let d = (h - g).abs().min(360.0 - (h - g).abs());
            assert!(d > 10.0, "hues {h} and {g}");
        }
        if i > 0 {
            let d = (h - hues[i - 1]).abs();
            assert!(d.min(360.0 - d) > 90.0, "consecutive keys {i}");
        }
    }
}

#[test]
fn extreme_style_values_draw_only_finite_lines_without_panic() {
    let (mut world, _, _, _) = sensor_scene();
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 10);
    let finite = |rec: &Recorder| rec.lines.iter().all(|l| l.a.is_finite() && l.b.is_finite());

    let huge = OverlayStyle {
        trigger_dashes: u32::MAX,
        marker_size: f32::MAX,
        rest_speed: f32::NAN,
        ..OverlayStyle::default()
    };
    let (rec, stats) = render(huge, &layer, &world);
    assert!(finite(&rec));
    assert_eq!(stats.lines, rec.lines.len());
    assert_eq!(stats.trigger, 1);
    assert_eq!(
        rec.lines
            .iter()
            .filter(|l| l.color == huge.trigger_color)
            .count(),
        64
    );

    for size in [f32::NAN, f32::INFINITY, 0.0, -1.0] {
        let (rec, stats) = render(
            OverlayStyle {
                marker_size: size,
                ..OverlayStyle::default()
            },
            &layer,
            &world,
        );
        assert!(finite(&rec));
        assert_eq!(stats.markers, 0, "no markers at size {size}");
    }
}
