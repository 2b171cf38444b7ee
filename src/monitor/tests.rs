//! Unit tests of the monitor's configuration and counts.

use super::*;
use crate::Error;

#[test]
fn default_config_is_valid_and_matches_design() {
    let c = MonitorConfig::default();
    c.validate().unwrap();
    assert_eq!(c.hang_time, 0.1);
    assert_eq!(c.penetration_fraction, 0.1);
    assert_eq!(c.unresponsive_push, 2.0);
    assert!(Monitor::new(c).is_ok());
}

#[test]
fn bad_configs_are_refused_by_name() {
    type Edit = fn(&mut MonitorConfig);
    let cases: [(&str, Edit); 9] = [
        ("hang_time", |c| c.hang_time = Real::NAN),
        ("hang_time", |c| c.hang_time = -0.1),
        ("penetration_fraction", |c| {
            c.penetration_fraction = Real::INFINITY
        }),
        ("launch_relative", |c| c.launch_relative = -1.0),
        ("launch_per_kg", |c| c.launch_per_kg = Real::NAN),
        ("min_support_cos", |c| c.min_support_cos = -0.5),
        ("min_support_cos", |c| c.min_support_cos = 1.0),
        ("unresponsive_push", |c| c.unresponsive_push = -1.0),
        ("unresponsive_push", |c| {
            c.unresponsive_push = Real::INFINITY
        }),
    ];
    for (want, edit) in cases {
        let mut c = MonitorConfig::default();
        edit(&mut c);
        match c.validate() {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, want),
            other => panic!("{c:?}: expected an error on {want}, got {other:?}"),
        }
        assert!(Monitor::new(c).is_err());
    }
    let zero = MonitorConfig {
        hang_time: 0.0,
        penetration_fraction: 0.0,
        launch_relative: 0.0,
        launch_per_kg: 0.0,
        min_support_cos: 0.0,
        unresponsive_push: 0.0,
    };
    zero.validate().unwrap();
}

#[test]
fn counts_by_kind() {
    let mut c = ViolationCounts::default();
    c.add(ViolationKind::Launch);
    c.add(ViolationKind::Launch);
    c.add(ViolationKind::Escape);
    c.add(ViolationKind::Unresponsive);
    assert_eq!(c.get(ViolationKind::Launch), 2);
    assert_eq!(c.get(ViolationKind::Escape), 1);
    assert_eq!(c.get(ViolationKind::Unresponsive), 1);
    assert_eq!(c.unresponsive, 1);
    assert_eq!(c.get(ViolationKind::HangingSleeper), 0);
    assert_eq!(c.total(), 4);
    let names: Vec<_> = ViolationKind::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(
        names,
        [
            "hanging_sleeper",
            "launch",
            "deep_penetration",
            "escape",
            "unresponsive"
        ]
    );
}
