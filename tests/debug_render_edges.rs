//! The contact graph as a debug-render overlay, its edges: touching edges in their
//! contact group's colour, trigger edges and structural edges, as
//! `debug_render::GraphOverlay` draws them into a Rapier `DebugRenderBackend` on small
//! scenes built in `tests/common/overlay.rs`. Every step is followed by
//! `layer.validate(&world)`.

#![cfg(feature = "debug-render")]

#[path = "common/overlay.rs"]
mod overlay;

use rapier3d::prelude::*;
use rapier_contact_graph::debug_render::{group_key, OverlayStyle};
use rapier_contact_graph::{ContactLayer, EdgeKind, NodeKind};

use overlay::*;

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
        let n = layer.graph().try_node_of_body(h).unwrap();
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
fn group_colours_stay_when_a_group_grows() {
    // A third ball lands on pile a: the contact that begins merges the ball's group
    // into the pile's, which keeps its id; its smallest member, and so its colour, stay.
    let Balls { mut world, a, .. } = balls();
    let dropped = ball(&mut world, 0.0, 4.0, 0.5);
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 5);
    let style = OverlayStyle {
        touching_edges: true,
        ..nothing()
    };
    let group_of = |layer: &ContactLayer| {
        let n = layer.graph().try_node_of_body(a[0]).unwrap();
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
        layer.graph().try_node_of_body(a[1]).unwrap(),
        layer.graph().try_node_of_body(dropped).unwrap(),
    );
    assert!(layer.graph().touching(na).any(|n| n == nd), "it landed");
    assert_eq!(
        group_of(&layer),
        g1,
        "the merge keeps the larger group's id"
    );
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
