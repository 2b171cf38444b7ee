//! Pixel tests of the frame renderer on Rapier's debug lines: shade colours where the
//! bodies' outlines are, background elsewhere, nearer objects over farther ones, the
//! outlines Rapier draws per shape, scenery and sensors, legend and caption, the
//! overlay pass, the PNG checked by the `png` crate's decoder, bad geometry, and the
//! monitor's violators.

use std::f32::consts::FRAC_PI_4;

use rapier3d::prelude::*;

use super::lines::*;
use super::paint::*;
use super::*;
use crate::report::tests::decode_checked;

const BACKGROUND: [u8; 3] = [255, 255, 255];

/// A 400 × 400 side-view renderer of the box (-2, -2, -2)..(2, 2, 2), without
/// caption and legend unless a test adds them: 95 px per metre around (200, 200).
fn renderer() -> Renderer {
    let camera = Camera::new(400, 400)
        .with_bounds(Vector::splat(-2.0), Vector::splat(2.0))
        .unwrap();
    Renderer::new(camera).with_legend(false)
}

fn pixel_at(frame: &Frame, p: (f64, f64)) -> [u8; 3] {
    frame.pixel(p.0 as u32, p.1 as u32).expect("on the frame")
}

/// Whether a pixel within `r` pixels (a square) of `p` has exactly `colour`.
fn near(frame: &Frame, p: (f64, f64), colour: [u8; 3], r: i64) -> bool {
    let (x, y) = (p.0 as i64, p.1 as i64);
    (y - r..=y + r).any(|j| {
        (x - r..=x + r).any(|i| i >= 0 && j >= 0 && frame.pixel(i as u32, j as u32) == Some(colour))
    })
}

/// Pixels of exactly `colour` in the square of half-side `r` around `p`.
fn count_near(frame: &Frame, p: (f64, f64), colour: [u8; 3], r: i64) -> usize {
    let (x, y) = (p.0 as i64, p.1 as i64);
    (y - r..=y + r)
        .flat_map(|j| (x - r..=x + r).map(move |i| (i, j)))
        .filter(|&(i, j)| i >= 0 && j >= 0 && frame.pixel(i as u32, j as u32) == Some(colour))
        .count()
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
fn a_ball_is_its_shade_on_its_outline_and_background_elsewhere() {
    let mut world = PhysicsWorld::new();
    let at = Vector::new(0.5, -0.5, 0.0);
    let h = ball(&mut world, at, 0.5);
    let frame = renderer().render(&world, &|_| Shade::Moving, "");
    let p = frame.projection();
    let c = p.to_pixel(at);
    assert_eq!(p.scale(), 380.0 / 4.0);
    assert_eq!(c, (200.0 + 0.5 * p.scale(), 200.0 + 0.5 * p.scale()));
    // Rapier draws a ball as three great circles: side on, its silhouette and a cross
    // through the centre, whose pixel the 2 px lines cover fully.
    assert_eq!(pixel_at(&frame, c), Shade::Moving.rgb());
    let r = 0.5 * p.scale();
    for rim in [
        (c.0 + r, c.1),
        (c.0, c.1 - r),
        (c.0 - r * 0.6, c.1 + r * 0.8),
    ] {
        assert!(near(&frame, rim, Shade::Moving.rgb(), 1), "{rim:?}");
    }
    // A wireframe: inside, off the lines, is background; so is outside the circle.
    assert_eq!(pixel_at(&frame, (c.0 + 0.4 * r, c.1 + 0.4 * r)), BACKGROUND);
    assert_eq!(pixel_at(&frame, (c.0 + 0.8 * r, c.1 + 0.8 * r)), BACKGROUND);
    assert_eq!(pixel_at(&frame, (c.0 + r + 3.0, c.1)), BACKGROUND);
    assert_eq!(pixel_at(&frame, (100.0, 100.0)), BACKGROUND);
    assert_eq!(frame.count(Shade::Moving), 1);
    assert_eq!(frame.skipped(), 0);
    // Each shade is its own colour; a violating body's amber lies on a dark casing.
    for s in Shade::ALL {
        let frame = renderer().render(&world, &|b| if b == h { s } else { Shade::Moving }, "");
        assert_eq!(pixel_at(&frame, c), s.rgb(), "{s:?}");
        assert_eq!(frame.count(s), 1);
        let casing = near(&frame, c, Shade::Violating.outline_rgb(), 4);
        assert_eq!(casing, s == Shade::Violating, "{s:?}");
    }
}

#[test]
fn nearer_bodies_are_painted_over_farther_ones_whatever_the_insertion_order() {
    for near_first in [true, false] {
        let mut world = PhysicsWorld::new();
        let (near_at, far_at) = (Vector::new(0.0, 0.0, 1.0), Vector::new(0.3, 0.0, -1.0));
        let (near_ball, far_ball) = if near_first {
            let n = ball(&mut world, near_at, 0.5);
            (n, ball(&mut world, far_at, 0.5))
        } else {
            let f = ball(&mut world, far_at, 0.5);
            (ball(&mut world, near_at, 0.5), f)
        };
        let classify = |b: RigidBodyHandle| {
            assert!(b == near_ball || b == far_ball);
            if b == near_ball {
                Shade::AtRest
            } else {
                Shade::Moving
            }
        };
        let frame = renderer().render(&world, &classify, "");
        let p = frame.projection();
        // The far ball's horizontal line runs through the near ball's centre: the
        // near ball's cross is painted over it.
        assert_eq!(pixel_at(&frame, p.to_pixel(near_at)), Shade::AtRest.rgb());
        // The far ball shows where the near one has no line.
        let beyond = p.to_pixel(Vector::new(0.7, 0.0, -1.0));
        assert_eq!(pixel_at(&frame, beyond), Shade::Moving.rgb());
    }
}

#[test]
fn a_tilted_view_keeps_bodies_on_the_far_end_of_a_slab_visible() {
    // Looking down at 35°: the slab's centre is nearer than a ball on its far half,
    // but its farthest point is farther, so the ball is painted after it; the slab's
    // far top edge runs right behind the ball's centre.
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
    let far_edge = p.to_pixel(Vector::new(0.0, 0.0, -1.8));
    assert!((far_edge.1 - p.to_pixel(at).1).abs() < 3.0, "{far_edge:?}");
    assert_eq!(pixel_at(&frame, p.to_pixel(at)), Shade::Moving.rgb());
    // The slab is its twelve edges in its shade: the near top edge, a near corner's
    // vertical edge; its faces are empty.
    let seen = |at: Vector| near(&frame, p.to_pixel(at), Shade::Fixed.rgb(), 1);
    assert!(seen(Vector::new(0.0, 0.0, 1.8)));
    assert!(seen(Vector::new(1.8, -0.25, 1.8)));
    assert!(seen(Vector::new(-1.0, 0.0, -1.8)));
    assert_eq!(
        pixel_at(&frame, p.to_pixel(Vector::new(0.9, 0.0, 0.5))),
        BACKGROUND
    );
    let _ = slab;
}

#[test]
fn shapes_are_drawn_as_rapiers_debug_outlines() {
    let mut world = PhysicsWorld::new();
    // A cube turned 45° about z: a diamond in the side view.
    let (diamond, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-1.0, 1.0, 0.0))
            .rotation(Vector::new(0.0, 0.0, FRAC_PI_4)),
        ColliderBuilder::cuboid(0.4, 0.4, 0.4),
    );
    // A capsule along y, a compound of two balls, a triangle mesh.
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
    let px = |x, y| p.to_pixel(Vector::new(x, y, 0.0));
    let at = |x, y| pixel_at(&frame, px(x, y));
    let on = |x, y, s: Shade| near(&frame, px(x, y), s.rgb(), 1);
    // Diamond: its corners and edges; nothing at its centre (a cube's edges along the
    // view project to points) nor in the corners of its bounding box.
    let d = 0.4 * std::f32::consts::SQRT_2;
    assert!(on(-1.0, 1.0 + d, Shade::Moving) && on(-1.0 - d, 1.0, Shade::Moving));
    assert!(on(-1.0 + d / 2.0, 1.0 + d / 2.0, Shade::Moving));
    assert_eq!(at(-1.0, 1.0), BACKGROUND);
    assert_eq!(at(-0.6, 1.4), BACKGROUND);
    // Capsule: its caps reach 0.6 up, its sides only 0.2 across.
    assert!(on(1.0, 1.6, Shade::AtRest) && on(1.2, 1.0, Shade::AtRest));
    assert_eq!(at(1.3, 1.0), BACKGROUND);
    assert_eq!(at(1.18, 1.55), BACKGROUND);
    // Compound: both balls (their crosses at the centres), nothing between them.
    assert_eq!(at(-1.4, -1.0), Shade::Sleepy.rgb());
    assert_eq!(at(-0.6, -1.0), Shade::Sleepy.rgb());
    assert_eq!(at(-1.0, -0.9), BACKGROUND);
    // Trimesh: its triangle's edges, not its bounding box.
    assert!(on(1.0, -1.2, Shade::Fixed) && on(1.25, -1.0, Shade::Fixed));
    assert_eq!(at(1.45, -0.85), BACKGROUND);
    assert_eq!(frame.count(Shade::Fixed), 1);
    assert_eq!(frame.skipped(), 0);
}

#[test]
fn scenery_is_grey_sensors_are_dashed_and_legend_and_caption_are_drawn() {
    let mut scene = rcg_scenes::sphere_stack(2);
    let ground = scene.body("ground").unwrap();
    let s0 = scene.body("s0").unwrap();
    let sensor_at = Vector::new(2.0, 1.0, 0.0);
    let solid_at = Vector::new(-2.0, 1.0, 0.0);
    scene.world.insert(
        RigidBodyBuilder::fixed().translation(sensor_at),
        ColliderBuilder::ball(0.4).sensor(true),
    );
    scene.world.insert(
        RigidBodyBuilder::fixed().translation(solid_at),
        ColliderBuilder::ball(0.4),
    );
    let top = {
        let co = scene.world.bodies[ground].colliders()[0];
        let aabb = scene.world.colliders[co].compute_aabb();
        aabb.maxs.y
    };
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
        let edge = p.to_pixel(Vector::new(0.7, top, 0.0));
        // Grey scenery, or the classifier's green without scenery.
        let colour = if std::ptr::eq(frame, &plain) {
            Shade::Fixed.rgb()
        } else {
            SCENERY
        };
        assert!(near(frame, edge, colour, 1), "ground's top edge");
        // A sensor's lines are dashed: fewer pixels than a solid ball of its size.
        let c = if std::ptr::eq(frame, &plain) {
            Shade::Fixed.rgb()
        } else {
            SCENERY
        };
        let r = (0.45 * p.scale()) as i64;
        let dashed = count_near(frame, p.to_pixel(sensor_at), c, r);
        let solid = count_near(frame, p.to_pixel(solid_at), c, r);
        assert!(
            dashed > 0 && (dashed as f64) < 0.8 * solid as f64,
            "{dashed} {solid}"
        );
    }
    assert_eq!(
        plain.count(Shade::Fixed),
        4,
        "ground, s1, sensor body, solid ball"
    );
    assert_eq!(framed.count(Shade::Fixed), 1, "s1 only");
    assert_eq!(framed.count(Shade::Sleepy), 1);

    // The legend: every shade's colour appears in the bottom band, and only there
    // (no body of most shades is drawn).
    let band = |frame: &Frame, rows: std::ops::Range<u32>, colour: [u8; 3]| {
        rows.flat_map(|y| (0..frame.width()).map(move |x| (x, y)))
            .any(|(x, y)| frame.pixel(x, y) == Some(colour))
    };
    let h = framed.height();
    for s in Shade::ALL {
        assert!(band(&framed, h - 34..h, s.rgb()), "{s:?} in the legend");
    }
    assert!(band(&framed, h - 34..h, Shade::Violating.outline_rgb()));
    assert!(!band(&plain, h - 34..h, Shade::Violating.rgb()));
    // Text in the top band (the caption) and the bottom one (the legend), none
    // without a caption, none over the scene.
    let ink = [0x22, 0x22, 0x22];
    assert!(band(&framed, 0..34, ink));
    assert!(band(&framed, h - 34..h, ink));
    assert!(!band(&plain, 0..34, ink));
    assert!(!band(&framed, 40..h - 40, ink), "no text over the scene");
}

#[test]
fn long_captions_shrink_then_are_cut_and_never_panic() {
    let world = PhysicsWorld::new();
    let r = Renderer::new(Camera::new(160, 160));
    for caption in ["short", &"x".repeat(20), &"y".repeat(500), "ünïcødé ✓\u{0}"] {
        let frame = r.render(&world, &|_| Shade::Moving, caption);
        assert_eq!((frame.width(), frame.height()), (160, 160));
    }
    assert_eq!(fit_caption("abc", 100.0), ("abc".to_string(), CAPTION_SIZE));
    let (t, size) = fit_caption(&"a".repeat(12), 100.0);
    assert!(
        t.len() == 12 && (MIN_SIZE..CAPTION_SIZE).contains(&size),
        "{size}"
    );
    let (t, size) = fit_caption(&"a".repeat(40), 100.0);
    assert!(t.ends_with("...") && text::width(&t, size) <= 100.0, "{t}");
    assert_eq!(fit_caption("a\u{0}b", 100.0).0, "a\u{FFFD}b");
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
    // Compressed: far below the 3 bytes a pixel of the raw frame.
    assert!(png.len() < rgb.len() / 10, "{} bytes", png.len());
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
    // The half-space is Rapier's two long lines, in the plane: one across the whole
    // picture (clipped), under the ball drawn over it.
    assert_eq!(frame.skipped(), 1, "the NaN ball");
    for x in [5.0, 15.0, 25.0] {
        assert!(near(
            &frame,
            p.to_pixel(Vector::new(x, 0.0, 0.0)),
            SCENERY,
            1
        ));
    }
    // An empty world: a blank frame with a border.
    let empty =
        Renderer::new(Camera::new(200, 200)).render(&PhysicsWorld::new(), &|_| Shade::Moving, "");
    assert_eq!(empty.count(Shade::Moving), 0);
    assert_eq!(empty.pixel(100, 80), Some(BACKGROUND));
    let border = (8..12)
        .filter_map(|x| empty.pixel(x, 80))
        .min_by_key(|p| p[0]);
    assert_eq!(
        border,
        Some(BORDER),
        "{:?}",
        (8..12).map(|x| empty.pixel(x, 80)).collect::<Vec<_>>()
    );
    assert_eq!(empty.pixel(200, 0), None);
}

#[test]
fn an_overlay_pass_draws_over_the_bodies_in_its_own_colours() {
    let mut world = PhysicsWorld::new();
    let h = ball(&mut world, Vector::ZERO, 0.5);
    let (_, disabled) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(1.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.3).enabled(false),
    );
    let co = world.bodies[h].colliders()[0];
    let mut calls = 0;
    let frame = renderer().render_with(&world, &|_| Shade::Moving, "", |backend| {
        calls += 1;
        // Everything is accepted in this pass, disabled colliders too.
        let object = DebugRenderObject::Collider(disabled, &world.colliders[disabled]);
        assert!(backend.filter_object(object));
        let object = DebugRenderObject::Collider(co, &world.colliders[co]);
        // Opaque blue (hue 240), then half-transparent black, across the ball.
        backend.draw_line(
            object,
            Vector::new(-1.0, 0.0, 0.0),
            Vector::new(1.0, 0.0, 0.0),
            [240.0, 1.0, 0.5, 1.0],
        );
        backend.draw_line(
            object,
            Vector::new(-1.0, -1.0, 0.0),
            Vector::new(-1.0, 1.0, 0.0),
            [0.0, 0.0, 0.0, 0.5],
        );
        // A non-finite line leaves out its object's overlay lines, not the ball.
        let other = DebugRenderObject::Collider(disabled, &world.colliders[disabled]);
        backend.draw_line(
            other,
            Vector::ZERO,
            Vector::new(1.0, 1.0, 0.0),
            [0.0, 1.0, 0.5, 1.0],
        );
        backend.draw_line(other, Vector::NAN, Vector::ZERO, [0.0, 1.0, 0.5, 1.0]);
    });
    assert_eq!(calls, 1);
    let p = frame.projection();
    // The ball's centre is under the overlay's line now.
    assert_eq!(pixel_at(&frame, p.to_pixel(Vector::ZERO)), [0, 0, 255]);
    assert_eq!(
        pixel_at(&frame, p.to_pixel(Vector::new(0.8, 0.0, 0.0))),
        [0, 0, 255]
    );
    let grey = pixel_at(&frame, p.to_pixel(Vector::new(-1.0, 0.5, 0.0)));
    assert!(grey.iter().all(|&c| (120..=135).contains(&c)), "{grey:?}");
    // The disabled collider is not drawn by Rapier's pass, nor (broken) its overlay
    // line; the ball is, and nothing counts as skipped.
    assert_eq!(frame.count(Shade::Moving), 1);
    assert!(near(
        &frame,
        p.to_pixel(Vector::new(0.0, 0.5, 0.0)),
        Shade::Moving.rgb(),
        1
    ));
    let disabled_at = p.to_pixel(Vector::new(1.0, 1.0, 0.0));
    assert!(!near(&frame, disabled_at, Shade::Moving.rgb(), 3));
    assert!(!near(&frame, disabled_at, [255, 0, 0], 3));
    assert_eq!(frame.skipped(), 0);
}

#[test]
fn segments_are_clipped_to_the_picture() {
    let r = [0.0, 0.0, 100.0, 50.0];
    assert_eq!(
        clip((10.0, 10.0), (20.0, 20.0), r),
        Some([(10.0, 10.0), (20.0, 20.0)])
    );
    assert_eq!(
        clip((-100.0, 25.0), (200.0, 25.0), r),
        Some([(0.0, 25.0), (100.0, 25.0)])
    );
    assert_eq!(
        clip((-1e7, -1e7), (1e7, 1e7), r),
        Some([(0.0, 0.0), (50.0, 50.0)])
    );
    assert_eq!(clip((-10.0, 60.0), (200.0, 60.0), r), None);
    assert_eq!(clip((150.0, 10.0), (120.0, 40.0), r), None);
    assert_eq!(
        clip((5.0, 5.0), (5.0, 5.0), r),
        Some([(5.0, 5.0), (5.0, 5.0)])
    );
}

#[test]
fn rapiers_hsla_colours_become_rgba() {
    assert_eq!(hsla_to_rgba([0.0, 1.0, 0.5, 1.0]), [255, 0, 0, 255]);
    assert_eq!(hsla_to_rgba([120.0, 1.0, 0.5, 1.0]), [0, 255, 0, 255]);
    assert_eq!(hsla_to_rgba([240.0, 1.0, 0.25, 0.5]), [0, 0, 128, 128]);
    assert_eq!(hsla_to_rgba([0.0, 0.0, 1.0, 1.0]), [255, 255, 255, 255]);
    assert_eq!(hsla_to_rgba([420.0, 1.0, 0.5, 1.0]), [255, 255, 0, 255]);
    assert_eq!(
        hsla_to_rgba([f32::NAN, 2.0, -1.0, f32::INFINITY]),
        [0, 0, 0, 255]
    );
    // Rapier's default style gives joints and contacts colours that convert.
    let style = DebugRenderStyle::default();
    assert_eq!(hsla_to_rgba(style.collider_fixed_color)[3], 255);
}

#[test]
fn violating_bodies_lists_the_monitors_hanging_body_while_it_hangs() {
    use rapier_contact_graph::coherence::Tracking;
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
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
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
