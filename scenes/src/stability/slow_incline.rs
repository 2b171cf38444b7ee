//! A sphere rolling slowly down a shallow incline.
//!
//! A fixed plane inclined [`SLOPE_DEGREES`]° and a sphere placed on it at rest near its
//! upper end. Rolling without slipping it accelerates at `5/7 · g · sin θ` (0.24 m/s²
//! at 2°), so for its first 0.4 s it moves slower than 0.1 m/s — a kinetic energy
//! below the sleepy threshold — and in the 6 s of the run it rolls 4.4 m.
//!
//! Built against sleepiness (the contact graph's own sleep): 0.2 s below the threshold
//! makes the sphere sleepy, its group (the sphere alone) sleeps, and it stays on the
//! slope for good: nothing ever touches it to wake it. It is supported by the slope,
//! so no violation is reported: the failure is the motion. Rapier's own sleep needs
//! 0.5 s below 0.05 m/s, and the sphere passes 0.05 m/s after 0.2 s, so stock Rapier
//! lets it roll.

use rapier3d::math::{Pose, Real, Rotation, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use crate::{new_world, Scene};

/// The incline's angle, degrees.
pub const SLOPE_DEGREES: Real = 2.0;
/// The sphere's radius.
pub const RADIUS: Real = 0.25;
/// Half length of the incline along its slope, m.
pub const HALF_LENGTH: Real = 6.0;
/// Where the sphere starts, along the slope from the incline's centre (uphill +), m.
pub const START: Real = 5.0;

fn slope_pose() -> Pose {
    Pose::from_parts(
        Vector::ZERO,
        Rotation::from_rotation_z(SLOPE_DEGREES.to_radians()),
    )
}

/// Builds the scene. Bodies: `"incline"` (fixed, top surface through the origin),
/// `"sphere"`.
pub fn slow_incline() -> Scene {
    let mut world = new_world();
    let pose = slope_pose();
    let (incline, _) = world.insert(
        RigidBodyBuilder::fixed().pose(pose),
        ColliderBuilder::cuboid(HALF_LENGTH, 0.5, 2.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let at = pose * Vector::new(START, RADIUS + 0.001, 0.0);
    let (sphere, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(at),
        ColliderBuilder::ball(RADIUS),
    );
    Scene {
        name: "slow_incline",
        world,
        bodies: vec![("incline", incline), ("sphere", sphere)],
        script: None,
    }
}

/// Whether a position is still above the incline (not rolled off its lower end).
pub fn is_on_incline(p: Vector) -> bool {
    let local = slope_pose().inverse() * p;
    local.x.abs() <= HALF_LENGTH && local.y > 0.0
}
