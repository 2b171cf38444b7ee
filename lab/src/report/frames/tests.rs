//! Pixel tests of the frame renderer: colours where bodies are, background where they
//! are not, painter's order, outlines by shape, legend and caption, the PNG checked by
//! the decoder of the chart tests, bad geometry, and the monitor's violators.

use std::f32::consts::FRAC_PI_4;

use rapier3d::prelude::*;

use super::*;
use crate::report::png::decode_checked;

const BACKGROUND: [u8; 3] = [255, 255, 255];

/// A 400 × 400 side-view renderer of the box (-2, -2, -2)..(2, 2, 2), without
/// caption and legend unless a test adds them: 38 px per metre around (200, 200).
fn renderer() -> Renderer {
    let camera = Camera::new(400, 400)
        .with_bounds(Vector::splat(-2.0), Vector::splat(2.0))
        .unwrap();
    Renderer::new(camera).with_legend(false)
}

fn pixel_at(frame: &Frame, p: (f64, f64)) -> [u8; 3] {
    frame.pixel(p.0 as u32, p.1 as u32).expect("on the frame")
}

fn ball(world: &mut PhysicsWorld, at: Vector, r: Real) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::dynamic().translation(at),
            ColliderBuilder::ball(r),
        )
        .0
}

#[test]
fn a_ball_is_its_shade_at_its_centre_and_background_outside() {
    let mut world = PhysicsWorld::new();
    let at = Vector::new(0.5, -0.5, 0.0);
    let h = ball(&mut world, at, 0.5);
    let frame = renderer().render(&world, &|_| Shade::Moving, "");
    let p = frame.projection();
    let c = p.to_pixel(at);
    assert_eq!(p.scale(), 380.0 / 4.0);
    assert_eq!(c, (200.0 + 0.5 * p.scale(), 200.0 + 0.5 * p.scale()));
    assert_eq!(pixel_at(&frame, c), Shade::Moving.rgb());
    // The outline, at the rim, is darker: between the outline colour (its pixels are
    // partly covered, the rim falling between pixel centres) and the fill.
    let r = 0.5 * p.scale();
    let rim = pixel_at(&frame, (c.0 + r - 0.5, c.1));
    let (fill, dark) = (Shade::Moving.rgb(), Shade::Moving.outline_rgb());
    for k in 0..3 {
        assert!(dark[k] <= rim[k] && rim[k] < fill[k], "{rim:?}");
    }
    // Outside the disc (the bounding square's corner, and beyond the rim): background.
    assert_eq!(pixel_at(&frame, (c.0 + 0.8 * r, c.1 + 0.8 * r)), BACKGROUND);
    assert_eq!(pixel_at(&frame, (c.0 + r + 3.0, c.1)), BACKGROUND);
    assert_eq!(pixel_at(&frame, (100.0, 100.0)), BACKGROUND);
    assert_eq!(frame.count(Shade::Moving), 1);
    assert_eq!(frame.skipped(), 0);
    // Each shade is its own colour.
    for s in Shade::ALL {
        let frame = renderer().render(&world, &|b| if b == h { s } else { Shade::Moving }, "");
        assert_eq!(pixel_at(&frame, c), s.rgb(), "{s:?}");
        assert_eq!(frame.count(s), 1);
    }
}

#[test]
fn nearer_bodies_are_painted_over_farther_ones_whatever_the_insertion_order() {
    for near_first in [true, false] {
        let mut world = PhysicsWorld::new();
        let (near_at, far_at) = (Vector::new(0.0, 0.0, 1.0), Vector::new(0.3, 0.0, -1.0));
        let (near, far) = if near_first {
            let n = ball(&mut world, near_at, 0.5);
            (n, ball(&mut world, far_at, 0.5))
        } else {
            let f = ball(&mut world, far_at, 0.5);
            (ball(&mut world, near_at, 0.5), f)
        };
        let classify = |b: RigidBodyHandle| {
            assert!(b == near || b == far);
            if b == near {
                Shade::AtRest
            } else {
                Shade::Moving
            }
        };
        let frame = renderer().render(&world, &classify, "");
        let p = frame.projection();
        // Where they overlap, the near (z = +1, the viewer's side) ball shows.
        assert_eq!(pixel_at(&frame, p.to_pixel(near_at)), Shade::AtRest.rgb());
        // The far ball shows where the near one does not cover it.
        let beyond = p.to_pixel(Vector::new(0.7, 0.0, -1.0));
        assert_eq!(pixel_at(&frame, beyond), Shade::Moving.rgb());
    }
}

#[test]
fn a_tilted_view_keeps_bodies_on_the_far_end_of_a_slab_visible() {
    // Looking down at 35°: the slab's centre is nearer than a ball on its far half,
    // but its farthest point is farther, so the ball is painted after it.
    let mut world = PhysicsWorld::new();
    let (slab, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.25, 0.0)),
        ColliderBuilder::cuboid(1.8, 0.25, 1.8),
    );
    let at = Vector::new(0.0, 0.3, -1.4);
    let b = ball(&mut world, at, 0.3);
    let camera = Camera::new(400, 400)
        .with_view(View::tilted(0.0, 35.0).unwrap())
        .with_bounds(Vector::splat(-2.0), Vector::splat(2.0))
        .unwrap();
    let frame = Renderer::new(camera).with_legend(false).render(
        &world,
        &|h| if h == b { Shade::Moving } else { Shade::Fixed },
        "",
    );
    let p = frame.projection();
    assert!(p.depth(at) > p.depth(Vector::new(0.0, -0.25, 0.0)));
    assert_eq!(pixel_at(&frame, p.to_pixel(at)), Shade::Moving.rgb());
    // The slab's top face, lightened as a face turned up; its front face darker.
    let [_, _, forward] = p.basis();
    let top = tinted(rgb(Shade::Fixed.rgb()), face_tint([0.0, 1.0, 0.0], forward));
    let front = tinted(rgb(Shade::Fixed.rgb()), face_tint([0.0, 0.0, 1.0], forward));
    assert!(top.g > Shade::Fixed.rgb()[1] && front.g < Shade::Fixed.rgb()[1]);
    let seen = |at: Vector| rgb(pixel_at(&frame, p.to_pixel(at)));
    assert_eq!(seen(Vector::new(0.0, 0.0, 0.5)), top);
    assert_eq!(seen(Vector::new(0.0, -0.25, 1.8)), front);
    let _ = slab;
}

#[test]
fn cuboids_are_their_projected_hull_and_other_shapes_their_silhouette() {
    let mut world = PhysicsWorld::new();
    // A square turned 45° about z: a diamond in the side view.
    let (diamond, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-1.0, 1.0, 0.0))
            .rotation(Vector::new(0.0, 0.0, FRAC_PI_4)),
        ColliderBuilder::cuboid(0.4, 0.4, 0.4),
    );
    // A capsule along y (support map), a compound of two balls, a triangle mesh
    // (drawn as its bounding box).
    let (capsule, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 1.0, 0.0)),
        ColliderBuilder::capsule_y(0.4, 0.2),
    );
    let parts = vec![
        (
            Pose::from_translation(Vector::new(-0.4, 0.0, 0.0)),
            SharedShape::ball(0.2),
        ),
        (
            Pose::from_translation(Vector::new(0.4, 0.0, 0.0)),
            SharedShape::ball(0.2),
        ),
    ];
    let (compound, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(-1.0, -1.0, 0.0)),
        ColliderBuilder::compound(parts),
    );
    let mesh = ColliderBuilder::trimesh(
        vec![
            Vector::new(-0.5, -0.2, 0.0),
            Vector::new(0.5, -0.2, 0.0),
            Vector::new(0.0, 0.2, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let (trimesh, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(1.0, -1.0, 0.0)),
        mesh,
    );
    let shades = [
        (diamond, Shade::Moving),
        (capsule, Shade::AtRest),
        (compound, Shade::Sleepy),
        (trimesh, Shade::Fixed),
    ];
    let classify = |h| shades.iter().find(|(b, _)| *b == h).unwrap().1;
    let frame = renderer().render(&world, &classify, "");
    let p = frame.projection();
    let at = |x, y| pixel_at(&frame, p.to_pixel(Vector::new(x, y, 0.0)));
    // Diamond: inside along the diagonals, outside in the corners of its bounding box.
    assert_eq!(at(-1.0, 1.0), Shade::Moving.rgb());
    assert_eq!(at(-1.0, 1.5), Shade::Moving.rgb());
    assert_eq!(at(-0.6, 1.4), BACKGROUND);
    // Capsule: its caps reach 0.6 up, its sides only 0.2 across.
    assert_eq!(at(1.0, 1.55), Shade::AtRest.rgb());
    assert_eq!(at(1.0, 1.0), Shade::AtRest.rgb());
    assert_eq!(at(1.3, 1.0), BACKGROUND);
    assert_eq!(at(1.18, 1.55), BACKGROUND);
    // Compound: both balls, nothing between them.
    assert_eq!(at(-1.4, -1.0), Shade::Sleepy.rgb());
    assert_eq!(at(-0.6, -1.0), Shade::Sleepy.rgb());
    assert_eq!(at(-1.0, -0.9), BACKGROUND);
    // Trimesh: its bounding box, corners included.
    assert_eq!(at(0.6, -1.15), Shade::Fixed.rgb());
    assert_eq!(frame.count(Shade::Fixed), 1);
    assert_eq!(frame.skipped(), 0);
}

#[test]
fn scenery_is_grey_sensors_are_outlines_and_legend_and_caption_are_drawn() {
    let mut scene = rcg_scenes::sphere_stack(2);
    let ground = scene.body("ground").unwrap();
    let s0 = scene.body("s0").unwrap();
    let sensor_at = Vector::new(2.0, 1.0, 0.0);
    scene.world.insert(
        RigidBodyBuilder::fixed().translation(sensor_at),
        ColliderBuilder::ball(0.4).sensor(true),
    );
    let camera = Camera::new(640, 480)
        .with_bounds(Vector::new(-3.0, -1.0, -1.0), Vector::new(3.0, 2.5, 1.0))
        .unwrap();
    let classify = |h| if h == s0 { Shade::Sleepy } else { Shade::Fixed };
    let plain =
        Renderer::new(camera.clone())
            .with_legend(false)
            .render(&scene.world, &classify, "");
    let framed = Renderer::new(camera)
        .with_fixed_as_scenery(&scene.world)
        .render(&scene.world, &classify, "sphere_stack  t = 0.00 s");
    for frame in [&plain, &framed] {
        let p = frame.projection();
        let mid = pixel_at(frame, p.to_pixel(Vector::new(0.0, -0.5, 0.0)));
        // Grey scenery, or the classifier's green without scenery.
        if std::ptr::eq(frame, &plain) {
            assert_eq!(mid, Shade::Fixed.rgb());
        } else {
            assert_eq!(mid, [0xC9, 0xC9, 0xC9]);
        }
        // A sensor is an outline: its inside is background.
        assert_eq!(pixel_at(frame, p.to_pixel(sensor_at)), BACKGROUND);
    }
    assert_eq!(plain.count(Shade::Fixed), 3, "ground, s1, sensor body");
    assert_eq!(framed.count(Shade::Fixed), 1, "s1 only");
    assert_eq!(framed.count(Shade::Sleepy), 1);
    let _ = ground;

    // The legend: every shade's colour appears in the bottom band, and only there
    // (no body of most shades is drawn).
    let band = |frame: &Frame, rows: std::ops::Range<u32>, colour: [u8; 3]| {
        rows.flat_map(|y| (0..frame.width()).map(move |x| (x, y)))
            .any(|(x, y)| frame.pixel(x, y) == Some(colour))
    };
    let h = framed.height();
    for s in Shade::ALL {
        assert!(band(&framed, h - 34..h, s.rgb()), "{s:?} in the legend");
        assert!(band(&framed, h - 34..h, s.outline_rgb()), "{s:?} outline");
    }
    assert!(!band(&plain, h - 34..h, Shade::Violating.rgb()));
    // The caption: ink in the top band, none without a caption.
    let ink = [0x22, 0x22, 0x22];
    assert!(band(&framed, 0..34, ink));
    assert!(!band(&plain, 0..34, ink));
    assert!(!band(&framed, 40..h - 40, ink), "no text over the scene");
}

#[test]
fn long_captions_shrink_then_are_cut_and_never_panic() {
    let world = PhysicsWorld::new();
    let r = Renderer::new(Camera::new(160, 160));
    for caption in ["short", &"x".repeat(20), &"y".repeat(500), "ünïcødé ✓"] {
        let frame = r.render(&world, &|_| Shade::Moving, caption);
        assert_eq!((frame.width(), frame.height()), (160, 160));
    }
    assert_eq!(text_line("abc", 0.0, 0.0, 100.0).map(scale_of), Some(2));
    assert_eq!(
        text_line(&"a".repeat(12), 0.0, 0.0, 100.0).map(scale_of),
        Some(1)
    );
    match text_line(&"a".repeat(40), 0.0, 0.0, 100.0) {
        Some(Item::Text { text, .. }) => {
            assert!(text.ends_with("...") && font::text_width(&text) <= 100)
        }
        other => panic!("{other:?}"),
    }
}

fn scale_of(item: Item) -> u32 {
    match item {
        Item::Text { scale, .. } => scale,
        _ => 0,
    }
}

#[test]
fn the_png_decodes_to_the_pixels_and_is_written_to_disk() {
    let mut scene = rcg_scenes::sphere_stack(3);
    scene.world.step();
    let renderer = Renderer::new(Camera::new(300, 240)).with_fixed_as_scenery(&scene.world);
    let frame = renderer.render(&scene.world, &|_| Shade::Moving, "stack");
    let png = frame.png();
    let (w, h, rgb) = decode_checked(&png).unwrap();
    assert_eq!((w, h), (300, 240));
    assert_eq!(rgb, frame.rgb());
    let path = std::env::temp_dir().join(format!("frames_test_{}.png", std::process::id()));
    frame.write_png(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), png);
    std::fs::remove_file(&path).unwrap();
    // A missing directory is an I/O error, not a panic.
    assert!(frame
        .write_png(std::env::temp_dir().join("no such dir/x/y.png"))
        .is_err());
    // Deterministic: the same world gives the same bytes.
    assert_eq!(
        renderer
            .render(&scene.world, &|_| Shade::Moving, "stack")
            .png(),
        png
    );
    let svg = frame.svg();
    assert!(svg.starts_with("<svg") && svg.contains("<circle") && svg.contains("<polygon"));
}

#[test]
fn auto_fit_covers_the_world_and_bad_geometry_is_skipped() {
    let mut world = PhysicsWorld::new();
    let far = Vector::new(30.0, 5.0, 0.0);
    ball(&mut world, Vector::ZERO, 0.5);
    ball(&mut world, far, 0.5);
    world.insert_collider(ColliderBuilder::ball(0.5).translation(Vector::NAN), None);
    world.insert_collider(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Y)),
        None,
    );
    let frame = Renderer::new(Camera::new(400, 300))
        .with_legend(false)
        .render(&world, &|_| Shade::AtRest, "");
    let p = frame.projection();
    for at in [Vector::ZERO, far] {
        let (x, y) = p.to_pixel(at);
        assert!((10.0..390.0).contains(&x) && (10.0..290.0).contains(&y));
        assert_eq!(pixel_at(&frame, (x, y)), Shade::AtRest.rgb());
    }
    assert_eq!(frame.skipped(), 2, "the NaN ball and the half-space");
    // An empty world: a blank frame with a border.
    let empty =
        Renderer::new(Camera::new(200, 200)).render(&PhysicsWorld::new(), &|_| Shade::Moving, "");
    assert_eq!(empty.count(Shade::Moving), 0);
    assert_eq!(empty.pixel(100, 80), Some(BACKGROUND));
    assert_eq!(empty.pixel(200, 0), None);
}

#[test]
fn convex_hull_drops_inner_and_collinear_points() {
    let hull = convex_hull(vec![
        (0.0, 0.0),
        (2.0, 0.0),
        (1.0, 0.0),
        (2.0, 2.0),
        (0.0, 2.0),
        (1.0, 1.0),
        (0.0, 0.0),
    ]);
    assert_eq!(hull.len(), 4);
    for corner in [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)] {
        assert!(hull.contains(&corner));
    }
    assert_eq!(convex_hull(vec![(1.0, 1.0), (1.0, 1.0)]), vec![(1.0, 1.0)]);
}

#[test]
fn violating_bodies_lists_the_monitors_hanging_body_while_it_hangs() {
    use rapier_contact_graph::monitor::{Monitor, MonitorConfig};
    use rapier_contact_graph::{ContactLayer, WorldView};
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let lower = ball(&mut world, Vector::new(0.0, 0.5, 0.0), 0.5);
    let upper = ball(&mut world, Vector::new(0.0, 1.5, 0.0), 0.5);
    let mut layer = ContactLayer::new();
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let held = move |h: RigidBodyHandle| h == upper;
    let no_one = |_: RigidBodyHandle| false;
    for _ in 0..30 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        monitor.check(&layer, &WorldView::from(&world), &held, &no_one);
        assert!(violating_bodies(&monitor).is_empty());
    }
    // Hold the upper ball in place and take the lower one away: it hangs.
    let rb = &mut world.bodies[upper];
    rb.set_locked_axes(LockedAxes::all(), true);
    rb.set_linvel(Vector::ZERO, true);
    rb.set_angvel(Vector::ZERO, true);
    world.remove_body(lower);
    let mut reported = false;
    for _ in 0..30 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        let found = monitor.check(&layer, &WorldView::from(&world), &held, &no_one);
        reported |= !found.is_empty();
        assert_eq!(violating_bodies(&monitor), vec![upper]);
        let c = Classifier::new(&world.bodies, &layer);
        let list = violating_bodies(&monitor);
        assert_eq!(c.violating(&list).shade(upper), Shade::Violating);
    }
    assert!(reported, "the monitor counted the hang");
}
