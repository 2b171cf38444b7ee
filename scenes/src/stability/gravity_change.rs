//! Gravity changed while bodies sleep (bevy_rapier #570: "modifying gravity doesn't
//! wake sleeping colliders").
//!
//! Three spheres float at rest 1 m above the ground with gravity off. At step
//! [`GRAVITY_AT`] (1.5 s: every kind of sleep has put them to sleep by then) the script
//! turns gravity on (`(0, -9.81, 0)`, the scenes' usual), and they should fall to the
//! ground. A sleeper that is not woken stays in the air: a hanging sleeper, from the
//! step gravity is on. Measured: Rapier 0.36 does not wake them, so stock Rapier, the
//! contact graph and every combination leave them in the air. Under fixation they are
//! held fixed as well, but every combination sleeps too, so fixation's share of the
//! failure cannot be told apart. The gravity the script sets depends on the step index alone, so
//! a replay from any step gives the same world.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene, GRAVITY_Y};

/// The spheres' radius.
pub const RADIUS: Real = 0.5;
/// Height of the spheres' lowest points above the ground, m.
pub const HOVER: Real = 1.0;
/// The step at which gravity comes on.
pub const GRAVITY_AT: u64 = 150;

/// Builds the scene (gravity off). Bodies: `"ground"`, `"s0"`, `"s1"`, `"s2"`.
pub fn gravity_change() -> Scene {
    let mut world = new_world();
    world.gravity = Vector::ZERO;
    let g = ground(&mut world, 10.0);
    let mut bodies = vec![("ground", g)];
    for (name, x) in [("s0", -1.5), ("s1", 0.0), ("s2", 1.5)] {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, RADIUS + HOVER, 0.0)),
            ColliderBuilder::ball(RADIUS),
        );
        bodies.push((name, h));
    }
    Scene {
        name: "gravity_change",
        world,
        bodies,
        script: Some(switch_gravity),
    }
}

fn switch_gravity(world: &mut PhysicsWorld, step: u64) {
    world.gravity = if step >= GRAVITY_AT {
        Vector::new(0.0, GRAVITY_Y, 0.0)
    } else {
        Vector::ZERO
    };
}
