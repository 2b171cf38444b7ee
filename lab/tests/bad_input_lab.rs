//! The laboratory's share of the bad-input audit (`docs/audit.md`): the measurement
//! runner (`measure::run`, `measure::deviation`), the charts (`report`) and the frames
//! (`report::frames`) fed NaN, empty, huge and degenerate input. Each call runs under
//! `no_panic`, so a panic is reported as what it is.

use std::panic::{catch_unwind, AssertUnwindSafe};

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::MonitorConfig;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::Error;
use rcg_lab::measure::{self, Mode, RunOptions, RunSpec, Trajectory};
use rcg_lab::report::{self, ChartPoint, ChartSpec, PointKind};
use rcg_scenes as scenes;

#[path = "../../tests/common/mod.rs"]
mod common;

use common::audit::*;

#[test]
fn deviation_with_empty_mismatched_and_bad_radius() {
    let empty = Trajectory::default();
    let a = Trajectory {
        frames: vec![vec![Vector::ZERO, Vector::X]],
    };
    let b = Trajectory {
        frames: vec![vec![Vector::X], vec![Vector::Y]],
    };
    let nan = Trajectory {
        frames: vec![vec![Vector::splat(Real::NAN)]],
    };
    assert!(
        measure::deviation(&empty, &empty, 1.0).is_nan(),
        "nothing comparable"
    );
    assert!(measure::deviation(&a, &empty, 1.0).is_nan());
    assert_eq!(
        measure::deviation(&a, &b, 1.0),
        1.0,
        "extra frames and bodies skipped"
    );
    assert!(
        measure::deviation(&nan, &b, 1.0).is_nan(),
        "non-finite positions skipped"
    );
    // The radius is not checked (no error channel): 0 gives inf, NaN gives NaN, and a
    // negative radius acts as its absolute value.
    assert!(measure::deviation(&a, &b, 0.0).is_infinite());
    assert!(measure::deviation(&a, &b, Real::NAN).is_nan());
    assert_eq!(measure::deviation(&a, &b, -1.0), 1.0);
}

fn options<'a>(bodies: &'a [RigidBodyHandle], reference: Option<&'a Trajectory>) -> RunOptions<'a> {
    RunOptions {
        steps: 3,
        sample_every: 1,
        radius: 0.5,
        bodies,
        reference,
        inside: &|_| true,
        monitor: MonitorConfig::default(),
    }
}

#[test]
fn measure_run_refuses_bad_configs() {
    let bad_monitor = RunOptions {
        monitor: MonitorConfig {
            hang_time: Real::NAN,
            ..MonitorConfig::default()
        },
        ..options(&[], None)
    };
    assert!(matches!(
        measure::run(&RunSpec::stock(), scenes::ball_on_box(), &bad_monitor),
        Err(Error::InvalidParameter {
            name: "hang_time",
            ..
        })
    ));
    let bad_speedups = RunSpec {
        name: "bad".into(),
        mode: Mode::Layer(SpeedUps {
            damping: -1.0,
            ..SpeedUps::none()
        }),
        repair: false,
    };
    assert!(matches!(
        measure::run(&bad_speedups, scenes::ball_on_box(), &options(&[], None)),
        Err(Error::InvalidParameter {
            name: "damping",
            ..
        })
    ));
    // Foreign bodies are sampled as NaN and count as having left the region; a reference
    // of another shape is compared where it overlaps.
    let ghosts = [RigidBodyHandle::from_raw_parts(99, 0)];
    let reference = Trajectory {
        frames: vec![vec![Vector::ZERO; 3]; 1],
    };
    let (r, t) = no_panic("run with foreign bodies", || {
        measure::run(
            &RunSpec::stock(),
            scenes::ball_on_box(),
            &options(&ghosts, Some(&reference)),
        )
    })
    .unwrap();
    assert_eq!(r.left_region, 1);
    assert!(r.deviation.is_nan());
    assert_eq!(t.frames.len(), 3);
    // Zero steps.
    let zero = RunOptions {
        steps: 0,
        ..options(&[], None)
    };
    let (r, _) = measure::run(&RunSpec::contact_graph(), scenes::ball_on_box(), &zero).unwrap();
    assert_eq!(r.mean_awake, 0.0);
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_measure_run_sample_every_zero_panics() {
    let o = RunOptions {
        sample_every: 0,
        ..options(&[], None)
    };
    let r = no_panic("run(sample_every = 0)", || {
        measure::run(&RunSpec::stock(), scenes::ball_on_box(), &o).map(|_| ())
    });
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_measure_run_huge_step_count_panics() {
    let o = RunOptions {
        steps: u64::MAX,
        ..options(&[], None)
    };
    // With the bug fixed this would run for ever: stop it from inside the scene.
    let mut scene = scenes::ball_on_box();
    scene.script = Some(|_, step| {
        if step >= 3 {
            panic!("reached step 3: the run started, it did not panic up front");
        }
    });
    let r = catch_unwind(AssertUnwindSafe(|| {
        measure::run(&RunSpec::stock(), scene, &o).map(|_| ())
    }));
    let msg = r
        .err()
        .and_then(|e| e.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default();
    assert!(
        msg.starts_with("reached step 3"),
        "panicked up front: {msg:?}"
    );
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_measure_run_plain_zero_iterations_accepted() {
    let spec = RunSpec {
        name: "zero".into(),
        mode: Mode::Plain { iterations: 0 },
        repair: false,
    };
    assert!(matches!(
        measure::run(
            &RunSpec::stock().with_repair(),
            scenes::ball_on_box(),
            &options(&[], None)
        ),
        Err(Error::InvalidParameter { name: "repair", .. })
    ));
    assert!(matches!(
        measure::run(&spec, scenes::ball_on_box(), &options(&[], None)),
        Err(Error::InvalidParameter { .. })
    ));
}

#[test]
fn pareto_front_with_nan_and_empty() {
    assert!(report::pareto_front(&[], true).is_empty());
    let pts = vec![
        ChartPoint::new("nan", f64::NAN, 2.0, 0, PointKind::Combination),
        ChartPoint::new("inf", 0.1, f64::INFINITY, 0, PointKind::Combination),
        ChartPoint::new("ok", 0.5, 1.0, 0, PointKind::Combination),
        ChartPoint::new("violating", 0.0, 9.0, u64::MAX, PointKind::Combination),
        ChartPoint::new("twin", 0.5, 1.0, 0, PointKind::Combination),
    ];
    assert_eq!(report::pareto_front(&pts, true), vec![2, 4]);
    assert_eq!(report::pareto_front(&pts, false), vec![3]);
}

#[test]
fn charts_with_nan_empty_and_extreme_input() {
    let odd = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
        0.0,
        -0.0,
        1e-300,
        1e300,
        -1.0,
    ];
    let spec = ChartSpec::default();
    assert!(report::svg(&[], &spec).contains("no data"));
    assert!(!report::png(&[], &spec).is_empty());
    for log_y in [true, false] {
        for &d in &odd {
            for &s in &odd {
                let pts = vec![
                    ChartPoint::new("a\u{0}<&\"", d, s, 0, PointKind::Reference),
                    ChartPoint::new("b", 0.1, 1.0, u64::MAX, PointKind::Repaired),
                ];
                let spec = ChartSpec {
                    log_y,
                    width: 320,
                    height: 240,
                    ..ChartSpec::default()
                };
                no_panic(&format!("chart d={d:e} s={s:e} log_y={log_y}"), || {
                    assert!(report::svg(&pts, &spec).starts_with("<svg"));
                    assert!(!report::png(&pts, &spec).is_empty());
                });
            }
        }
    }
    // Sizes out of range are clamped; odd titles are escaped.
    let huge = "x".repeat(10_000);
    let odd_spec = ChartSpec {
        width: 0,
        height: u32::MAX,
        title: "",
        x_label: "\u{0}\u{202e}<&>",
        y_label: &huge,
        log_y: true,
        band: Some(f64::NAN),
    };
    let svg = no_panic("chart with odd spec", || report::svg(&[], &odd_spec));
    assert!(svg.contains("height=\"8192\"") && !svg.contains("<&>"));
}

#[test]
fn frames_with_bad_bounds_views_handles_and_geometry() {
    use rcg_lab::report::frames::{Camera, Classifier, Renderer, Shade, View};
    // Out-of-range and non-finite parameters: clamped sizes, errors for the rest.
    assert_eq!(Camera::new(0, u32::MAX).size(), (160, 8192));
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert!(matches!(View::tilted(bad, 0.0), Err(Error::NonFinite(_))));
        assert!(matches!(View::tilted(0.0, bad), Err(Error::NonFinite(_))));
        let corner = Vector::new(0.0, bad, 0.0);
        assert!(matches!(
            Camera::new(200, 200).with_bounds(corner, Vector::ONE),
            Err(Error::NonFinite(_))
        ));
    }
    assert!(matches!(
        Camera::new(200, 200).with_bounds(Vector::ONE, Vector::ZERO),
        Err(Error::InvalidParameter { .. })
    ));
    let (mut world, ground, ball, layer) = stepped(3);
    for bad in [-1.0, f32::NAN, f32::INFINITY] {
        assert!(matches!(
            Classifier::new(&world.bodies, &layer).with_rest_speed(bad),
            Err(Error::InvalidParameter { .. })
        ));
    }
    // Stale and foreign handles: the classifier calls them fixed, scenery ignores them.
    world.remove_body(ball);
    {
        let classes = Classifier::new(&world.bodies, &layer);
        assert_eq!(classes.shade(ball), Shade::Fixed);
        for h in foreign_bodies(ground) {
            assert_eq!(classes.shade(h), Shade::Fixed);
        }
    }
    // Odd geometry: NaN and huge poses, tiny and huge bounds, a half-space, views at
    // odd angles.
    world.insert_collider(ColliderBuilder::ball(0.5).translation(Vector::NAN), None);
    world.insert_collider(
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).translation(Vector::splat(f32::MAX)),
        None,
    );
    world.insert_collider(
        ColliderBuilder::ball(1e30).translation(Vector::splat(1e30)),
        None,
    );
    world.insert_collider(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Y)),
        None,
    );
    let (far, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1e20, 0.0)),
        ColliderBuilder::capsule_y(0.5, 0.2),
    );
    let cameras = [
        Camera::new(200, 160),
        Camera::new(200, 160)
            .with_bounds(Vector::ZERO, Vector::splat(1e-30))
            .unwrap(),
        Camera::new(200, 160)
            .with_bounds(Vector::splat(-f32::MAX), Vector::splat(f32::MAX))
            .unwrap(),
        Camera::new(200, 160).with_view(View::tilted(1e30, -1e30).unwrap()),
    ];
    let classes = Classifier::new(&world.bodies, &layer);
    for (i, camera) in cameras.into_iter().enumerate() {
        let renderer = Renderer::new(camera).with_scenery(foreign_bodies(ground));
        let frame = no_panic(&format!("frame {i}"), || {
            renderer.render(&world, &|h| classes.shade(h), &"\u{0}é".repeat(300))
        });
        // The NaN ball is left out and counted; the half-space is drawn as Rapier's
        // debug render draws it (two 10 km lines, clipped to the picture).
        assert!(frame.skipped() >= 1, "the NaN ball");
        assert_eq!(frame.rgb().len(), 200 * 160 * 3);
        assert_eq!(frame.pixel(200, 0), None);
        let _ = far;
    }
    // Writing where no directory is: an I/O error.
    let frame = Renderer::new(Camera::new(160, 160)).render(&world, &|_| Shade::Moving, "");
    assert!(frame
        .write_png(std::env::temp_dir().join("no/such/dir/frame.png"))
        .is_err());
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_chart_negative_subnormal_panics() {
    for (d, s, log_y) in [
        (-5e-324, 2.0, true),
        (-5e-324, 2.0, false),
        (1.0, -5e-324, false),
    ] {
        let pts = vec![ChartPoint::new("p", d, s, 0, PointKind::Combination)];
        let spec = ChartSpec {
            log_y,
            ..ChartSpec::default()
        };
        no_panic(&format!("svg d={d:e} s={s:e} log_y={log_y}"), || {
            report::svg(&pts, &spec)
        });
        no_panic(&format!("png d={d:e} s={s:e} log_y={log_y}"), || {
            report::png(&pts, &spec)
        });
    }
}
