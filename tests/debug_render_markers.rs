//! The contact graph as a debug-render overlay, its body markers (asleep, resting,
//! moving, passive, insulator, held, sleepy), and the overlay's determinism, robustness
//! and composition with Rapier's own `DebugRenderPipeline`. Every step is followed by
//! `layer.validate(&world)`.

#![cfg(feature = "debug-render")]

#[path = "common/overlay.rs"]
mod overlay;

use rapier3d::prelude::*;
use rapier_contact_graph::debug_render::{
    BodyState, GraphOverlay, MarkerShape, OverlayStats, OverlayStyle,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldView};

use overlay::*;

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
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, passive, true)
        .unwrap();
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
            layer.graph().try_node_of_body(h).unwrap(),
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
        (passive, BodyState::Disabled),
    ] {
        assert_eq!(state(&layer, &world, h), Some(s));
        assert_marker(&rec, &style, &world, h, s);
    }

    // Rapier puts the resting ball to sleep.
    run(&mut layer, &mut world, 300);
    assert!(world.bodies[resting].is_sleeping());
    assert!(layer.analysis().holds(&world.bodies, resting));
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
        .speedups_mut()
        .set(Some(SpeedUps {
            hold: true,
            insulate_sleepy: true,
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
        let n = layer.graph().try_node_of_body(h).unwrap();
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
        stats.touching, 2,
        "ball–box, and the held box's contact with the ground (kept while held)"
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
        .speedups_mut()
        .set(Some(SpeedUps {
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
