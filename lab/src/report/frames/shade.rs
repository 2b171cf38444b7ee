//! What colour a body gets: the five states of the paper's Fig. 17 and the standard
//! classifier that reads them off the layer, the monitor and Rapier.
//!
//! The renderer asks a caller-supplied `&dyn Fn(RigidBodyHandle) -> Shade`, so any
//! notion of state can be pictured; [`Classifier`] is the one the paper's figure
//! uses. It takes plain inputs — the body set, the layer, a slice of violating bodies —
//! rather than a `Monitor`, so it does not care who owns the monitor;
//! [`violating_bodies`] makes that slice from a [`Monitor`].
//!
//! # The rules, first match wins
//! 1. **Violating**: the body is in the caller's violating list (the monitor's last
//!    violations and the held bodies it is timing as unsupported). First, so that a
//!    fixated body left hanging in the air — the paper's hanging sleeper — shows as a
//!    violation and not as fixed geometry.
//! 2. **Fixed**: a fixed or kinematic body in Rapier, or one held by the `hold`
//!    speed-up (which makes it fixed in Rapier too).
//! 3. **Sleepy**: sleepy for the speed-ups, or asleep in Rapier.
//! 4. **At rest** ("absolute rest" in the paper): linear speed and angular speed both
//!    at most [`Classifier::rest_speed`] (default [`DEFAULT_REST_SPEED`]). Exactly zero
//!    would rarely hold while Rapier keeps a body awake (gravity against the soft
//!    contacts leaves a residual speed); the default sits well above that noise and
//!    far below visible motion.
//! 5. **Moving**: everything else, non-finite velocities included.
//!
//! Rejected: sorting the violating list to binary-search it. It holds the few bodies
//! violating in one step, so a linear scan is faster than the sort.

use rapier3d::math::Real;
use rapier3d::prelude::{RigidBodyHandle, RigidBodySet};

use rapier_contact_graph::monitor::Monitor;
use rapier_contact_graph::{ContactLayer, Error, Result};

/// The state a body is drawn in (paper Fig. 17: "Purple means sleepy, red moving, blue
/// absolute rest, green fixed"; violating added, in amber with a thick outline).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Shade {
    /// Moving: red.
    Moving,
    /// At (absolute) rest: blue.
    AtRest,
    /// Sleepy or asleep: purple.
    Sleepy,
    /// Fixed, scripted or fixated: green.
    Fixed,
    /// Part of a plausibility violation: amber, thick dark-orange outline.
    Violating,
}

impl Shade {
    /// Every shade, in legend order.
    pub const ALL: [Shade; 5] = [
        Shade::Moving,
        Shade::AtRest,
        Shade::Sleepy,
        Shade::Fixed,
        Shade::Violating,
    ];

    /// The name in the legend.
    pub const fn name(self) -> &'static str {
        match self {
            Shade::Moving => "moving",
            Shade::AtRest => "at rest",
            Shade::Sleepy => "sleepy",
            Shade::Fixed => "fixed",
            Shade::Violating => "violating",
        }
    }

    /// The fill colour, `[r, g, b]`.
    pub const fn rgb(self) -> [u8; 3] {
        match self {
            Shade::Moving => [0xE0, 0x3C, 0x31],
            Shade::AtRest => [0x2F, 0x6F, 0xD6],
            Shade::Sleepy => [0x8E, 0x44, 0xAD],
            Shade::Fixed => [0x3F, 0xA3, 0x4D],
            Shade::Violating => [0xFF, 0xC1, 0x07],
        }
    }

    /// The outline colour, `[r, g, b]`: the fill darkened, dark orange for violating.
    pub const fn outline_rgb(self) -> [u8; 3] {
        match self {
            Shade::Moving => [0x7A, 0x1A, 0x13],
            Shade::AtRest => [0x14, 0x38, 0x72],
            Shade::Sleepy => [0x4A, 0x1F, 0x5C],
            Shade::Fixed => [0x1E, 0x55, 0x26],
            Shade::Violating => [0xC4, 0x4A, 0x00],
        }
    }

    /// The outline width in pixels: 1.5, and 4 for violating so it stands out.
    pub const fn outline_width(self) -> f64 {
        match self {
            Shade::Violating => 4.0,
            _ => 1.5,
        }
    }
}

/// Default [`Classifier::rest_speed`]: 1 mm/s (and 1 mrad/s).
pub const DEFAULT_REST_SPEED: Real = 1e-3;

/// The standard classifier of the paper's Fig. 17 (rules in the module docs).
///
/// ```
/// use rapier3d::prelude::*;
/// use rcg_lab::report::frames::{Classifier, Shade};
/// use rapier_contact_graph::ContactLayer;
///
/// let mut world = PhysicsWorld::new();
/// let (ground, _) = world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
/// let (ball, _) = world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0, 0.0)),
///     ColliderBuilder::ball(0.5),
/// );
/// let mut layer = ContactLayer::new();
/// layer.step(&mut world);
/// let classes = Classifier::new(&world.bodies, &layer);
/// assert_eq!(classes.shade(ground), Shade::Fixed);
/// assert_eq!(classes.shade(ball), Shade::Moving); // falling
/// assert_eq!(classes.violating(&[ball]).shade(ball), Shade::Violating);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Classifier<'a> {
    bodies: &'a RigidBodySet,
    layer: &'a ContactLayer,
    violating: &'a [RigidBodyHandle],
    rest_speed: Real,
}

impl<'a> Classifier<'a> {
    /// A classifier reading `bodies` (the world's body set) and the layer's
    /// speed-ups, with no violating bodies and the default rest speed. O(1).
    pub fn new(bodies: &'a RigidBodySet, layer: &'a ContactLayer) -> Self {
        Classifier {
            bodies,
            layer,
            violating: &[],
            rest_speed: DEFAULT_REST_SPEED,
        }
    }

    /// The same classifier with `bodies` drawn violating (e.g. [`violating_bodies`]).
    /// O(1); each [`Self::shade`] then costs O(`bodies.len()`).
    pub fn violating(mut self, bodies: &'a [RigidBodyHandle]) -> Self {
        self.violating = bodies;
        self
    }

    /// The same classifier with another rest threshold: a body is at rest when its
    /// linear speed (m/s) and its angular speed (rad/s) are both at most `speed`.
    /// Negative or non-finite speeds are an [`Error::InvalidParameter`]; 0 means
    /// exactly zero velocity. O(1).
    pub fn with_rest_speed(mut self, speed: Real) -> Result<Self> {
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "rest_speed",
                reason: format!("{speed} is not a finite speed >= 0"),
            });
        }
        self.rest_speed = speed;
        Ok(self)
    }

    /// The rest threshold in use.
    pub fn rest_speed(&self) -> Real {
        self.rest_speed
    }

    /// The shade of body `h`. A body the set does not hold (removed, foreign handle)
    /// is [`Shade::Fixed`]: nothing in this world moves it. O(violating list) plus
    /// O(log fixated bodies).
    pub fn shade(&self, h: RigidBodyHandle) -> Shade {
        if self.violating.contains(&h) {
            return Shade::Violating;
        }
        let Some(rb) = self.bodies.get(h) else {
            return Shade::Fixed;
        };
        let speedups = self.layer.speedups();
        if !rb.is_dynamic() || speedups.is_some_and(|s| s.is_fixated(h)) {
            return Shade::Fixed;
        }
        if rb.is_sleeping() || speedups.is_some_and(|s| s.is_sleepy(h)) {
            return Shade::Sleepy;
        }
        let (v, w) = (rb.linvel().length(), rb.angvel().length());
        if v <= self.rest_speed && w <= self.rest_speed {
            Shade::AtRest
        } else {
            Shade::Moving
        }
    }
}

/// The bodies the monitor finds violating now: those of its last check's violations
/// and the held bodies it is timing as unsupported (hanging sleepers from the first
/// step they hang, not only in the step the hang time runs out, so a sequence of
/// frames shows the whole episode). Sorted by handle, without repeats.
/// O(v log v) for v bodies listed.
pub fn violating_bodies(monitor: &Monitor) -> Vec<RigidBodyHandle> {
    let mut out: Vec<RigidBodyHandle> = monitor
        .last()
        .iter()
        .map(|v| v.body)
        .chain(monitor.unsupported_held().map(|(h, _)| h))
        .collect();
    out.sort_by_key(|h| h.into_raw_parts());
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::prelude::*;
    use rapier_contact_graph::speedups::SpeedUps;

    #[test]
    fn colours_are_distinct_and_names_unique() {
        for (i, a) in Shade::ALL.iter().enumerate() {
            for b in &Shade::ALL[i + 1..] {
                assert_ne!(a.rgb(), b.rgb());
                assert_ne!(a.name(), b.name());
            }
            assert_ne!(a.rgb(), a.outline_rgb());
        }
        assert!(Shade::Violating.outline_width() > Shade::Moving.outline_width());
    }

    #[test]
    fn classifier_follows_the_rules_in_order() {
        let mut world = rcg_scenes::sphere_stack(2).world;
        let ids: Vec<RigidBodyHandle> = world.bodies.iter().map(|(h, _)| h).collect();
        let (ground, low, high) = (ids[0], ids[1], ids[2]);
        let (kin, _) = world.insert(
            RigidBodyBuilder::kinematic_velocity_based()
                .translation(Vector::new(3.0, 3.0, 0.0))
                .linvel(Vector::X),
            ColliderBuilder::ball(0.2),
        );
        let mut layer = ContactLayer::new();
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        let c = Classifier::new(&world.bodies, &layer);
        assert_eq!(c.shade(ground), Shade::Fixed);
        assert_eq!(c.shade(kin), Shade::Fixed);
        // Just released with a gap under them: falling.
        assert_eq!(c.shade(low), Shade::Moving);
        assert_eq!(c.violating(&[ground, low]).shade(low), Shade::Violating);
        assert_eq!(c.violating(&[ground]).shade(ground), Shade::Violating);
        // A velocity below the threshold is rest; the threshold can be 0.
        world.bodies[high].set_linvel(Vector::new(0.0, 5e-4, 0.0), false);
        let c = Classifier::new(&world.bodies, &layer);
        assert_eq!(c.shade(high), Shade::AtRest);
        assert_eq!(c.with_rest_speed(0.0).unwrap().shade(high), Shade::Moving);
        world.bodies[high].set_angvel(Vector::new(0.0, 0.1, 0.0), false);
        let c = Classifier::new(&world.bodies, &layer);
        assert_eq!(c.shade(high), Shade::Moving);
        // Removed bodies and bad thresholds.
        world.remove_body(kin);
        let c = Classifier::new(&world.bodies, &layer);
        assert_eq!(c.shade(kin), Shade::Fixed);
        for bad in [-1.0, Real::NAN, Real::INFINITY] {
            assert!(matches!(
                c.with_rest_speed(bad),
                Err(Error::InvalidParameter { .. })
            ));
        }
    }

    #[test]
    fn sleepy_and_fixated_bodies_under_the_speedups() {
        let mut world = rcg_scenes::sphere_stack(2).world;
        let ids: Vec<RigidBodyHandle> = world.bodies.iter().map(|(h, _)| h).collect();
        let mut layer = ContactLayer::new();
        let sleepy_only = SpeedUps::contact_graph();
        let steps = sleepy_only.sleepy_steps;
        layer.speedups_mut().set(Some(sleepy_only)).unwrap();
        let mut seen_sleepy = false;
        for _ in 0..steps * 5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
            let c = Classifier::new(&world.bodies, &layer);
            let s = layer.speedups().unwrap();
            for &h in &ids[1..] {
                let sleepy = s.is_sleepy(h) || world.bodies[h].is_sleeping();
                assert_eq!(c.shade(h) == Shade::Sleepy, sleepy);
                seen_sleepy |= sleepy;
            }
        }
        assert!(seen_sleepy, "the settled stack became sleepy");

        let mut world = rcg_scenes::sphere_stack(2).world;
        let mut layer = ContactLayer::new();
        layer
            .speedups_mut()
            .set(Some(SpeedUps {
                hold: true,
                ..SpeedUps::contact_graph()
            }))
            .unwrap();
        let mut seen_fixated = false;
        for _ in 0..steps * 5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
            let c = Classifier::new(&world.bodies, &layer);
            let s = layer.speedups().unwrap();
            for &h in &ids[1..] {
                if s.is_fixated(h) {
                    seen_fixated = true;
                    assert_eq!(c.shade(h), Shade::Fixed);
                }
            }
        }
        assert!(seen_fixated, "the settled stack was fixated");
    }
}
