//! Bad-input audit (see `tests/common/audit.rs`): the layer's settings —
//! `speedups_mut().set` and `SpeedUps::validate`, the speed-up state queries, the coherence
//! settings (`set_contact_details`, `request_full_sync`, `set_trigger_widening`, the
//! scan policy), and the monitor: `MonitorConfig::validate`, `Monitor::check`, and the
//! layer's `monitor_mut()` (`set`, `mark_pushed`, `prime`) and `analysis().holds`.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, MonitorMode, RepairConfig, ViolationKind,
};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{coherence, ContactLayer, Error, WorldView};

use common::audit::*;

#[test]
fn set_speedups_refuses_bad_parameters() {
    let (mut world, _, _, mut layer) = stepped(3);
    let base = rcg_lab::table5::combination(127);
    let bad = [
        SpeedUps {
            sleepy_energy: Real::NAN,
            ..base.clone()
        },
        SpeedUps {
            sleepy_energy: -1.0,
            ..base.clone()
        },
        SpeedUps {
            deepest_contact_depth: Real::INFINITY,
            ..base.clone()
        },
        SpeedUps {
            damping: -0.5,
            ..base.clone()
        },
        SpeedUps {
            release_speed: Real::NAN,
            ..base.clone()
        },
        SpeedUps {
            sleepy_steps: 0,
            ..base.clone()
        },
        SpeedUps {
            iterations: Some(0),
            ..base.clone()
        },
        SpeedUps {
            fewer_iterations_count: 0,
            ..base.clone()
        },
    ];
    for config in bad {
        let before = fingerprint(&layer);
        assert!(matches!(
            layer.speedups_mut().set(Some(config.clone())),
            Err(Error::InvalidParameter { .. })
        ));
        assert!(layer.speedups().is_none(), "nothing switched on");
        assert_eq!(fingerprint(&layer), before);
    }
    // Zero thresholds and huge finite ones are in range and change nothing fatal.
    let edge = SpeedUps {
        sleepy_energy: 0.0,
        deepest_contact_depth: Real::MAX,
        damping: Real::MAX,
        release_speed: 0.0,
        sleepy_steps: u32::MAX,
        ..base.clone()
    };
    layer.speedups_mut().set(Some(edge)).unwrap();
    // A bad configuration while on keeps the one in force.
    assert!(layer
        .speedups_mut()
        .set(Some(SpeedUps {
            damping: Real::NAN,
            ..base
        }))
        .is_err());
    assert_eq!(layer.speedups().unwrap().config().damping, Real::MAX);
    no_panic("extreme speed-ups", || {
        for _ in 0..20 {
            layer.step(&mut world);
        }
    });
    layer.validate(&world).unwrap();
    // Off twice: no-op.
    layer.speedups_mut().set(None).unwrap();
    layer.speedups_mut().set(None).unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn settings_at_any_time() {
    let (mut world, _, ball, mut layer) = stepped(30);
    for policy in [
        coherence::ScanPolicy::Scan,
        coherence::ScanPolicy::Walk,
        coherence::ScanPolicy::Auto,
    ] {
        layer.analysis_mut().set_scan_policy(policy);
        layer.analysis_mut().set_contact_details(false);
        layer.analysis_mut().request_full_sync();
        layer.analysis_mut().request_full_sync();
        layer.logic_mut().set_trigger_widening(false);
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        layer.analysis_mut().set_contact_details(true);
        layer.logic_mut().set_trigger_widening(true);
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    // Contact details off from the start: support has no normals to go by, which the
    // node query says (documented on set_contact_details); the by-handle query reads
    // Rapier's.
    let (mut world, _, _) = ball_on_ground();
    let mut layer =
        ContactLayer::with_tracking(rapier_contact_graph::coherence::Tracking::Proximity);
    layer.analysis_mut().set_contact_details(false);
    for _ in 0..30 {
        layer.step(&mut world);
    }
    let n = layer.graph().try_node_of_body(ball).unwrap();
    assert_eq!(layer.graph().touching(n).count(), 1);
    assert_eq!(layer.analysis().is_supported(n), Err(Error::DetailsNotKept));
    assert_eq!(layer.supports_of_body(&world, ball, 0.0).unwrap().len(), 1);
}

#[test]
fn speedups_validate() {
    let ok = SpeedUps::contact_graph();
    ok.validate().unwrap();
    for bad in [
        SpeedUps {
            sleepy_energy: Real::NEG_INFINITY,
            ..ok.clone()
        },
        SpeedUps {
            deepest_contact_depth: -0.0001,
            ..ok.clone()
        },
        SpeedUps {
            damping: Real::NAN,
            ..ok.clone()
        },
        SpeedUps {
            release_speed: -1.0,
            ..ok.clone()
        },
        SpeedUps {
            sleepy_steps: 0,
            ..ok.clone()
        },
        SpeedUps {
            iterations: Some(0),
            ..ok.clone()
        },
        SpeedUps {
            fewer_iterations_count: 0,
            ..ok.clone()
        },
    ] {
        assert!(
            matches!(bad.validate(), Err(Error::InvalidParameter { .. })),
            "{bad:?}"
        );
    }
    // Bits above the seven switches are ignored.
    assert_eq!(
        rcg_lab::table5::combination(255),
        rcg_lab::table5::combination(127)
    );
}

#[test]
fn speedup_state_queries_with_foreign_handles() {
    let (mut world, _, ball, mut layer) = stepped(0);
    layer
        .speedups_mut()
        .set(Some(rcg_lab::table5::combination(127)))
        .unwrap();
    for _ in 0..200 {
        layer.step(&mut world);
    }
    let s = layer.speedups().unwrap();
    for f in foreign_bodies(ball) {
        assert!(!s.is_sleepy(f) && !s.is_fixated(f));
    }
    let _ = s.fixated().count();
    let _ = s.stats();
}

#[test]
fn monitor_config_validate() {
    let ok = MonitorConfig::default();
    for (name, bad) in [
        (
            "hang_time",
            MonitorConfig {
                hang_time: Real::NAN,
                ..ok
            },
        ),
        (
            "hang_time",
            MonitorConfig {
                hang_time: -1.0,
                ..ok
            },
        ),
        (
            "penetration_fraction",
            MonitorConfig {
                penetration_fraction: Real::INFINITY,
                ..ok
            },
        ),
        (
            "launch_relative",
            MonitorConfig {
                launch_relative: Real::NAN,
                ..ok
            },
        ),
        (
            "launch_per_kg",
            MonitorConfig {
                launch_per_kg: -0.1,
                ..ok
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: 1.0,
                ..ok
            },
        ),
        (
            "min_support_cos",
            MonitorConfig {
                min_support_cos: Real::NAN,
                ..ok
            },
        ),
    ] {
        match bad.validate() {
            Err(Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{bad:?}: {other:?}"),
        }
        assert!(Monitor::new(bad).is_err());
    }
}

#[test]
fn monitor_check_with_a_world_the_layer_never_saw() {
    let (mut world, _, ball, mut layer) = stepped(10);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    let empty = PhysicsWorld::new();
    let mut other = PhysicsWorld::new();
    other.gravity = Vector::splat(Real::NAN);
    for i in 0..4 {
        other.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(i as Real, Real::NAN, 0.0))
                .linvel(Vector::splat(Real::INFINITY)),
            ColliderBuilder::ball(0.6),
        );
    }
    for w in [&empty, &other, &world] {
        no_panic("check with a foreign world", || {
            monitor.check(&layer, &WorldView::from(w), &|_| true, &|_| true);
            monitor.check(&layer, &WorldView::from(w), &|_| false, &|_| false);
        });
    }
    // Quarantine reports of handles the world lacks are taken as given.
    let ghost = RigidBodyHandle::from_raw_parts(99, 0);
    layer.step(&mut world);
    let found = monitor
        .check_with_quarantine(
            &layer,
            &WorldView::from(&world),
            &|_| false,
            &|_| false,
            &[ghost],
        )
        .to_vec();
    assert!(found
        .iter()
        .any(|v| v.kind == ViolationKind::Escape && v.body == ghost && v.node.is_none()));
    // Priming foreign or removed handles is a no-op.
    for f in foreign_bodies(ball) {
        monitor.prime_body(&WorldView::from(&world), f);
    }
    monitor.prime(&WorldView::from(&empty));
    let _ = (
        monitor.totals(),
        monitor.peaks(),
        monitor.unsupported_held().count(),
    );
}

#[test]
fn monitor_entry_points_take_bad_input() {
    let (mut world, _, ball, mut layer) = stepped(5);
    // With the monitor off: priming and pushes are no-ops.
    layer.monitor_mut().prime(&WorldView::from(&world));
    layer.monitor_mut().mark_pushed(ball);
    assert!(layer.monitor().is_none());
    assert_eq!(
        layer.monitor().map(|m| m.monitor().totals()),
        None,
        "no totals with the monitor off"
    );
    common::monitor_in(&mut layer, MonitorMode::Off);
    assert!(layer.monitor().is_none(), "Off twice: no-op");
    common::monitor_in(&mut layer, MonitorMode::Repair);
    type Edit = fn(&mut RepairConfig);
    let bad_repairs: [(&str, Edit); 7] = [
        ("corrective_cap", |r| r.corrective_cap = 0.0),
        ("corrective_cap", |r| r.corrective_cap = Real::NAN),
        ("penetration_warning", |r| r.penetration_warning = 0.0),
        ("penetration_warning", |r| r.penetration_warning = 1.5),
        ("fast_travel", |r| r.fast_travel = -0.1),
        ("fast_travel", |r| r.fast_travel = Real::NAN),
        ("fast_travel", |r| r.fast_travel = Real::INFINITY),
    ];
    for (want, edit) in bad_repairs {
        let mut r = RepairConfig::default();
        edit(&mut r);
        match layer
            .monitor_mut()
            .set(MonitorMode::Report, MonitorConfig::default(), r)
        {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, want),
            other => panic!("{r:?}: expected an error on {want}, got {other:?}"),
        }
        assert_eq!(
            layer.monitor().unwrap().mode(),
            MonitorMode::Repair,
            "the monitor in force is kept"
        );
    }
    let bad_thresholds = MonitorConfig {
        hang_time: Real::INFINITY,
        ..MonitorConfig::default()
    };
    assert!(matches!(
        layer
            .monitor_mut()
            .set(MonitorMode::Report, bad_thresholds, RepairConfig::default()),
        Err(Error::InvalidParameter {
            name: "hang_time",
            ..
        })
    ));
    // A removed body: pushes are ignored, and it is not held.
    world.remove_body(ball);
    layer.monitor_mut().mark_pushed(ball);
    assert!(!layer.analysis().holds(&world.bodies, ball));
    no_panic("step after pushing a removed body", || {
        layer.step(&mut world)
    });
    layer.validate(&world).unwrap();
    assert_eq!(common::violation_totals(&layer).total(), 0);
}
