//! The stability suite: the scenes of [`rcg_scenes::stability`], each with what it is
//! built against, the run that shows its failure, and the control that proves the
//! failure is the switch's. The failures the paper's Discussion shows by eye (a sleepy
//! sphere left hanging in the air, Fig. 17; objects flying up under fixation, Fig. 15)
//! are counted by the plugin's plausibility monitor (`rapier_contact_graph::monitor`)
//! or, where the failure is wrong motion rather than a violation, measured as the
//! deviation from a reference run. Shared by `tests/stability_failures.rs` and the
//! `stability` runner.
//!
//! # The scenes
//! One file per scene; [`suite`] lists them with what each is built against and what
//! it was measured to fail under ([`StabilityCase`]):
//!
//! | scene | built against | measured failure (this crate, Rapier 0.36) |
//! |---|---|---|
//! | `hanging_sleeper` | fixate | the upper sphere, released when its support rolls away, ends elsewhere |
//! | `fixated_pile` | fixate | fixate: one deep penetration more; tweak and reduce: deep penetrations |
//! | `face_to_face` | reduce | the column topples under reduce, and under tweak |
//! | `tower` | tweak | none under tweak once warm start is on; reduce drops it |
//! | `pyramid` | tweak | deep penetrations under tweak and reduce |
//! | `bounce_on_sleepers` | zero | the ball's bounce is lost |
//! | `seesaw` | subgroup, fixate | none: fixation's release reaches plank and box before the ball lands |
//! | `slow_incline` | sleepy | the sphere freezes on the slope |
//! | `removed_support` | stock, sleepy, fixate | none: a held body falls when its support goes |
//! | `platform_sleepers` | stock, sleepy, fixate | none: the held boxes fall with the platform |
//! | `jointed_sleeper` | stock, sleepy, fixate | none: the hook's release reaches the crate by the joint |
//! | `gravity_change` | stock, sleepy | every kind of sleep: the spheres hang (not reported: see below) |
//! | `static_moved` | stock, sleepy, fixate | none: the held boxes fall when the shelf moves |
//! | `slow_push` | fixate | the pile stops a box pushed slowly into it (unresponsive) |
//!
//! The measured table, with the reading of each row, is in `docs/results.md`
//! ("Stability suite: where the speed-ups fail"); `cargo lab stability` prints it.
//!
//! A scene fails under a target when the target's run shows the failure and the same
//! run without the target (its control) does not; a scene that fails without warm
//! start gets a [`StabilityCase::base`] its targets are measured on. The reference is
//! [`reference()`]. Attribution, the reference, the scripts' tags and what the monitor
//! does not see yet: `docs/ARCHITECTURE.md` ("The stability suite").
//!
//! # Cost
//! Every scene has at most 56 bodies and runs at most 600 steps; the whole table runs
//! 14 scenes × 133 configurations plus controls.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;
use rapier_contact_graph::monitor::ViolationKind;
use rapier_contact_graph::speedups::SpeedUps;
pub use rcg_scenes::stability::*;
use rcg_scenes::Scene;

use crate::measure::{Mode, RunResult, RunSpec, Violations};

/// What a scene is built against: one switch of the paper's §7, the contact graph's own
/// sleep, or stock Rapier's sleep.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    /// Stock Rapier with its own auto-sleep ([`RunSpec::stock`]).
    StockSleep,
    /// The contact graph's sleep (groups + sleepy, [`RunSpec::contact_graph`]); every
    /// combination has it.
    Sleepy,
    /// Contact recycling and warm start.
    Cache,
    /// 1 solver iteration instead of 4.
    Tweak,
    /// Deepest contact only of deep pairs.
    Reduce,
    /// Restitution 0 with a sleepy body.
    Zero,
    /// Linear damping.
    Damp,
    /// Sleepy bodies insulate groups.
    Subgroup,
    /// Sleepy bodies held fixed.
    Fixate,
}

impl Target {
    /// Every target, in report order.
    pub const ALL: [Target; 9] = [
        Target::StockSleep,
        Target::Sleepy,
        Target::Cache,
        Target::Tweak,
        Target::Reduce,
        Target::Zero,
        Target::Damp,
        Target::Subgroup,
        Target::Fixate,
    ];

    /// A short stable name (`"stock"`, `"sleepy"`, `"cache"`, …).
    pub const fn name(self) -> &'static str {
        match self {
            Target::StockSleep => "stock",
            Target::Sleepy => "sleepy",
            Target::Cache => "cache",
            Target::Tweak => "tweak",
            Target::Reduce => "reduce",
            Target::Zero => "zero",
            Target::Damp => "damp",
            Target::Subgroup => "subgroup",
            Target::Fixate => "fixate",
        }
    }

    /// The bit of the switch in [`combination`](crate::table5::combination), for the seven switches.
    pub const fn bit(self) -> Option<u8> {
        match self {
            Target::Cache => Some(0),
            Target::Tweak => Some(1),
            Target::Reduce => Some(2),
            Target::Zero => Some(3),
            Target::Damp => Some(4),
            Target::Subgroup => Some(5),
            Target::Fixate => Some(6),
            Target::StockSleep | Target::Sleepy => None,
        }
    }
}

/// The suite's reference configuration: plain Rapier driven through the layer with
/// contact recycling and warm start on ("cache"), 16 solver iterations (4× Rapier's
/// default), no sleep, no other speed-up.
///
/// Why not [`RunSpec::reference`] (the DIKU run's: 16 iterations with recycling and
/// warm start *off*): without warm start Rapier's solver cannot carry a tall stack.
/// Measured on the 20-box [`tower`]: without warm start it leans from the first second
/// and has fallen within 4 s, with 16 iterations or 64; with warm start but without
/// recycling its top drifts 15–65 cm in 4 s; with both (this reference) less than 2 cm.
/// A reference that drops the tower cannot say whether a switch did.
pub fn reference() -> RunSpec {
    RunSpec {
        name: "reference".into(),
        mode: Mode::Layer(SpeedUps {
            cache: true,
            iterations: Some(16),
            ..SpeedUps::none()
        }),
        repair: false,
    }
}

/// How a failure shows.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Failure {
    /// As plausibility violations of this kind (paper §8, Figs. 15 and 17).
    Violation(ViolationKind),
    /// As wrong motion only: a deviation from the scene's reference, with no violation.
    Deviation,
}

/// One expected failure: a target and how its failure shows.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Expectation {
    /// What produces the failure (on top of the case's [`StabilityCase::base`]).
    pub target: Target,
    /// How it shows.
    pub failure: Failure,
}

const fn fails(target: Target, failure: Failure) -> Expectation {
    Expectation { target, failure }
}

const HANGING: Failure = Failure::Violation(ViolationKind::HangingSleeper);
const DEEP: Failure = Failure::Violation(ViolationKind::DeepPenetration);
const UNRESPONSIVE: Failure = Failure::Violation(ViolationKind::Unresponsive);
const DEVIATION: Failure = Failure::Deviation;

/// One scene of the suite, with what it is built to break.
#[derive(Clone, Copy, Debug)]
pub struct StabilityCase {
    /// The scene's name (as [`Scene::name`]).
    pub name: &'static str,
    /// Builds the scene afresh (deterministic).
    pub build: fn() -> Scene,
    /// Steps to run (dt = 0.01).
    pub steps: u64,
    /// The length unit of deviations, m (the scene's typical body half size).
    pub radius: Real,
    /// Names of the measured bodies; empty: every dynamic body, in handle order.
    pub measured: &'static [&'static str],
    /// What the scene was built against (the paper's case, or the bug report's).
    pub built_against: &'static [Target],
    /// The combination switches (bits of [`combination`](crate::table5::combination)) the failures are
    /// measured on: a target's run is `base` plus the target, its control is `base`
    /// without it. 0 (the contact graph) unless the scene needs a switch to stand at all
    /// (the tower needs the cache: without warm start it falls whatever else is on).
    pub base: u8,
    /// The failures measured with this crate and Rapier 0.36 (`rcg-lab stability`);
    /// `tests/stability_failures.rs` checks each. Empty: the scene does not fail under
    /// what it was built against.
    pub expected: &'static [Expectation],
    /// Whether a final position is acceptable (e.g. still on the incline).
    pub inside: Option<fn(Vector) -> bool>,
}

impl StabilityCase {
    /// The measured bodies of a freshly built scene, in order. O(bodies).
    pub fn measured_bodies(&self, scene: &Scene) -> Vec<RigidBodyHandle> {
        if self.measured.is_empty() {
            scene.dynamic_bodies()
        } else {
            self.measured.iter().filter_map(|n| scene.body(n)).collect()
        }
    }

    /// The run of a target on this case: [`Self::base`] plus the target's switch; the
    /// contact graph's sleep on `base` for [`Target::Sleepy`]; stock Rapier for
    /// [`Target::StockSleep`].
    pub fn target_spec(&self, target: Target) -> RunSpec {
        match (target, target.bit()) {
            (Target::StockSleep, _) => RunSpec::stock(),
            (_, Some(b)) => RunSpec::combination(self.base | (1 << b)),
            _ => RunSpec::combination(self.base),
        }
    }

    /// The control of a target: the same run without it. [`Self::base`] without the
    /// switch; `base` with sleep off for [`Target::Sleepy`] (named `no sleep`); stock
    /// Rapier with sleep off for [`Target::StockSleep`] (named `stock, no sleep`: the
    /// layer with the cache switch only, which is Rapier's defaults without sleep).
    pub fn control_spec(&self, target: Target) -> RunSpec {
        match (target, target.bit()) {
            (Target::StockSleep, _) => RunSpec {
                name: "stock, no sleep".into(),
                mode: Mode::Layer(SpeedUps {
                    cache: true,
                    ..SpeedUps::none()
                }),
                repair: false,
            },
            (_, Some(b)) => RunSpec::combination(self.base & !(1 << b)),
            _ => {
                let on = crate::table5::combination(self.base);
                RunSpec {
                    name: format!("{} no sleep", crate::table5::label(&on)),
                    mode: Mode::Layer(SpeedUps {
                        groups: false,
                        sleepy: false,
                        ..on
                    }),
                    repair: false,
                }
            }
        }
    }
}

/// How far a target's deviation must exceed its control's to count as wrong motion,
/// in the case's length unit (RMS over the run of the mean position error).
///
/// Why 0.5: a failure moves a body by its own size or more (a frozen sphere, a sleeper
/// left in the air, a lost bounce: 1–8 units in the measured table), while switches
/// that only perturb a run stay well below half a unit above their control (the
/// largest seen is the tweaked tower's bounce, 0.22). RMS over the whole run dilutes
/// a failure that starts late: a column whose support is removed half way through
/// measures about 1.
pub const DEVIATION_MARGIN: f64 = 0.5;

/// Positions are sampled every this many steps (and at the last step) for the
/// deviation, by the runner and the tests alike.
pub const SAMPLE_EVERY: u64 = 5;

/// What a failure is judged by: a run's violations and its deviation from the
/// reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Violations by kind.
    pub violations: Violations,
    /// Deviation from the case's reference, in its length unit.
    pub deviation: f64,
}

impl From<&RunResult> for Outcome {
    fn from(r: &RunResult) -> Self {
        Self {
            violations: r.violations,
            deviation: r.deviation,
        }
    }
}

/// Whether a run shows a failure against its control: for a violation kind, more
/// violations of that kind than the control has (so at least one); for a deviation, a
/// deviation exceeding the control's by [`DEVIATION_MARGIN`]. O(1).
pub fn shows(failure: Failure, run: &Outcome, control: &Outcome) -> bool {
    match failure {
        Failure::Violation(kind) => run.violations.get(kind) > control.violations.get(kind),
        Failure::Deviation => run.deviation - control.deviation >= DEVIATION_MARGIN,
    }
}

/// The suite, in a fixed order.
pub fn suite() -> &'static [StabilityCase] {
    &SUITE
}

/// The case called `name`.
pub fn case(name: &str) -> Option<&'static StabilityCase> {
    SUITE.iter().find(|c| c.name == name)
}

static SUITE: [StabilityCase; 14] = [
    StabilityCase {
        name: "hanging_sleeper",
        build: hanging_sleeper::hanging_sleeper,
        steps: 400,
        radius: hanging_sleeper::RADIUS,
        measured: &[],
        built_against: &[Target::Fixate],
        base: 0,
        expected: &[fails(Target::Fixate, DEVIATION)],
        inside: None,
    },
    StabilityCase {
        name: "fixated_pile",
        build: fixated_pile::fixated_pile,
        steps: 300,
        radius: fixated_pile::BOX_HALF,
        measured: &[],
        built_against: &[Target::Fixate],
        base: 0,
        expected: &[
            fails(Target::Tweak, DEEP),
            fails(Target::Reduce, DEEP),
            fails(Target::Fixate, DEEP),
        ],
        inside: None,
    },
    StabilityCase {
        name: "face_to_face",
        build: face_to_face::face_to_face,
        steps: 300,
        radius: face_to_face::BOX_HALF,
        measured: &[],
        built_against: &[Target::Reduce],
        base: 0,
        expected: &[
            fails(Target::Reduce, DEVIATION),
            fails(Target::Tweak, DEVIATION),
        ],
        inside: None,
    },
    StabilityCase {
        name: "tower",
        build: tower::tower,
        steps: 400,
        radius: tower::BOX_HALF,
        measured: &[],
        built_against: &[Target::Tweak],
        base: 1,
        expected: &[fails(Target::Reduce, DEEP)],
        inside: None,
    },
    StabilityCase {
        name: "pyramid",
        build: pyramid::pyramid,
        steps: 400,
        radius: pyramid::BOX_HALF,
        measured: &[],
        built_against: &[Target::Tweak],
        base: 0,
        expected: &[fails(Target::Tweak, DEEP), fails(Target::Reduce, DEEP)],
        inside: None,
    },
    StabilityCase {
        name: "bounce_on_sleepers",
        build: bounce_on_sleepers::bounce_on_sleepers,
        steps: 300,
        radius: bounce_on_sleepers::BALL_RADIUS,
        measured: &["ball"],
        built_against: &[Target::Zero],
        base: 0,
        expected: &[fails(Target::Zero, DEVIATION)],
        inside: None,
    },
    StabilityCase {
        name: "seesaw",
        build: seesaw::seesaw,
        steps: 300,
        radius: seesaw::BOX_HALF,
        measured: &["plank", "box", "ball"],
        built_against: &[Target::Subgroup, Target::Fixate],
        base: 0,
        expected: &[],
        inside: None,
    },
    StabilityCase {
        name: "slow_incline",
        build: slow_incline::slow_incline,
        steps: 600,
        radius: slow_incline::RADIUS,
        measured: &[],
        built_against: &[Target::Sleepy],
        base: 0,
        expected: &[fails(Target::Sleepy, DEVIATION)],
        inside: Some(slow_incline::is_on_incline),
    },
    StabilityCase {
        name: "removed_support",
        build: removed_support::removed_support,
        steps: 300,
        radius: removed_support::BOX_HALF,
        measured: &["b1", "b2", "top"],
        built_against: &[Target::StockSleep, Target::Sleepy, Target::Fixate],
        base: 0,
        expected: &[],
        inside: None,
    },
    StabilityCase {
        name: "platform_sleepers",
        build: platform_sleepers::platform_sleepers,
        steps: 350,
        radius: platform_sleepers::BOX_HALF,
        measured: &["b0", "b1", "b2"],
        built_against: &[Target::StockSleep, Target::Sleepy, Target::Fixate],
        base: 0,
        expected: &[],
        inside: None,
    },
    StabilityCase {
        name: "jointed_sleeper",
        build: jointed_sleeper::jointed_sleeper,
        steps: 400,
        radius: jointed_sleeper::CRATE_HALF,
        measured: &["crate"],
        built_against: &[Target::StockSleep, Target::Sleepy, Target::Fixate],
        base: 0,
        expected: &[],
        inside: None,
    },
    StabilityCase {
        name: "gravity_change",
        build: gravity_change::gravity_change,
        steps: 300,
        radius: gravity_change::RADIUS,
        measured: &[],
        // Not fixation: every combination sleeps, so fixation's control fails the same
        // way and its share cannot be told apart.
        built_against: &[Target::StockSleep, Target::Sleepy],
        base: 0,
        expected: &[
            fails(Target::StockSleep, HANGING),
            fails(Target::Sleepy, HANGING),
        ],
        inside: None,
    },
    StabilityCase {
        name: "static_moved",
        build: static_moved::static_moved,
        steps: 300,
        radius: static_moved::BOX_HALF,
        measured: &["b0", "b1"],
        built_against: &[Target::StockSleep, Target::Sleepy, Target::Fixate],
        base: 0,
        expected: &[],
        inside: None,
    },
    StabilityCase {
        name: "slow_push",
        build: slow_push::slow_push,
        steps: 300,
        radius: slow_push::BOX_HALF,
        measured: &[],
        built_against: &[Target::Fixate],
        base: 0,
        expected: &[fails(Target::Fixate, UNRESPONSIVE)],
        inside: None,
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    fn outcome(penetration: u64, deviation: f64) -> Outcome {
        Outcome {
            violations: Violations {
                penetration,
                ..Violations::default()
            },
            deviation,
        }
    }

    #[test]
    fn suite_names_are_unique_and_name_their_scenes() {
        let mut names: Vec<&str> = suite().iter().map(|c| c.name).collect();
        for c in suite() {
            assert_eq!((c.build)().name, c.name);
            assert_eq!(case(c.name).map(|k| k.name), Some(c.name));
            assert!(c.radius > 0.0 && c.steps > 0, "{}", c.name);
            for e in c.expected {
                assert!(
                    e.target.bit().is_none_or(|b| c.base & (1 << b) == 0),
                    "{}: a target already in the base",
                    c.name
                );
            }
        }
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), suite().len());
        assert!(case("no such scene").is_none());
    }

    #[test]
    fn targets_and_controls_differ_by_the_target_alone() {
        let tower = case("tower").unwrap();
        assert_eq!(tower.target_spec(Target::Tweak).name, "CT-----");
        assert_eq!(tower.control_spec(Target::Tweak).name, "C------");
        let incline = case("slow_incline").unwrap();
        assert_eq!(incline.target_spec(Target::Sleepy).name, "-------");
        match incline.control_spec(Target::Sleepy).mode {
            Mode::Layer(s) => {
                assert!(!s.sleepy && !s.groups && crate::table5::label(&s) == "-------")
            }
            m => panic!("{m:?}"),
        }
        assert_eq!(incline.target_spec(Target::StockSleep), RunSpec::stock());
        match incline.control_spec(Target::StockSleep).mode {
            Mode::Layer(s) => {
                assert!(s.cache && !s.sleepy && crate::table5::label(&s) == "C------")
            }
            m => panic!("{m:?}"),
        }
        assert_eq!(Target::ALL.iter().filter(|t| t.bit().is_some()).count(), 7);
        match reference().mode {
            Mode::Layer(s) => assert!(s.cache && !s.sleepy && s.iterations == Some(16)),
            m => panic!("{m:?}"),
        }
    }

    #[test]
    fn a_failure_shows_only_beyond_its_control() {
        let deep = Failure::Violation(ViolationKind::DeepPenetration);
        assert!(shows(deep, &outcome(3, 0.0), &outcome(0, 0.0)));
        assert!(shows(deep, &outcome(3, 0.0), &outcome(2, 0.0)));
        assert!(!shows(deep, &outcome(2, 0.0), &outcome(2, 0.0)));
        assert!(!shows(deep, &outcome(0, 9.0), &outcome(0, 0.0)));
        let hanging = Failure::Violation(ViolationKind::HangingSleeper);
        assert!(!shows(hanging, &outcome(3, 0.0), &outcome(0, 0.0)));
        assert!(shows(
            Failure::Deviation,
            &outcome(0, 1.6),
            &outcome(5, 1.0)
        ));
        assert!(!shows(
            Failure::Deviation,
            &outcome(0, 1.4),
            &outcome(0, 1.0)
        ));
    }
}
