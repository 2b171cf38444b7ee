//! The hanging sleeper (paper Fig. 17): a sphere resting on a sphere that rolls away
//! while the upper one is sleepy.
//!
//! Two spheres stand in a column on the ground (`lower`, `upper`, 0.01 m gaps, as in
//! [`crate::sphere_stack()`]); a third, `striker`, rolls towards the column along
//! +x at [`STRIKER_SPEED`] and reaches it after about 1.4 s, long after the column has
//! come to rest (0.2 s at rest makes a body sleepy). The striker hits `lower` only.
//! `lower` leaves the collision slower than the striker came (a rolling sphere keeps
//! part of its motion as spin), rolls away, and `upper`, perched on it, slides off and
//! falls to the ground.
//!
//! Built against fixation: the striker is faster than the default release speed
//! (0.5 m/s), so it releases `lower`; `lower` leaves slower than that, so the sphere it
//! carried, held fixed in the air, is never released. `upper` is frictionless: held
//! fixed, a rough one would brake `lower` to a stop under it (measured), and nothing
//! would roll away. Measured: under fixation `upper` stays 1 m above the ground for
//! the rest of the run; Rapier's sleep and the contact graph's wake the column.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{CoefficientCombineRule, ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Radius of the three spheres.
pub const RADIUS: Real = 0.5;
/// The striker's initial speed along +x, m/s (rolling without slipping).
pub const STRIKER_SPEED: Real = 0.7;
/// The striker's initial distance from the column's axis, m.
pub const STRIKER_X: Real = -2.0;

/// Builds the scene. Bodies: `"ground"` (fixed), `"lower"`, `"upper"`, `"striker"`.
pub fn hanging_sleeper() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.01;
    let ball = || ColliderBuilder::ball(RADIUS).friction(1.0);
    let (lower, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, RADIUS + gap, 0.0)),
        ball(),
    );
    // Frictionless, so that it neither brakes `lower` nor is dragged along by it.
    let (upper, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0 * RADIUS + 2.0 * gap, 0.0)),
        ball()
            .friction(0.0)
            .friction_combine_rule(CoefficientCombineRule::Min),
    );
    let (striker, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(STRIKER_X, RADIUS, 0.0))
            .linvel(Vector::new(STRIKER_SPEED, 0.0, 0.0))
            .angvel(Vector::new(0.0, 0.0, -STRIKER_SPEED / RADIUS)),
        ball(),
    );
    Scene {
        name: "hanging_sleeper",
        world,
        bodies: vec![
            ("ground", g),
            ("lower", lower),
            ("upper", upper),
            ("striker", striker),
        ],
        script: None,
    }
}
