//! A kinematic platform moving under sleeping bodies (the family of Rapier #287: a
//! driven body does not wake the sleepers that depend on it).
//!
//! A kinematic (position-based) platform 1 m above the ground carries three 0.4 m
//! boxes. It stands still until step [`MOVE_AT`] (1.5 s: every kind of sleep has put the
//! boxes to sleep by then), then sinks at [`SINK_SPEED`] for [`SINK_STEPS`] steps and
//! stops 0.1 m above the ground. The boxes should ride down with it.
//!
//! A sleeper that is not woken stays where it was and is left in the air, a hanging
//! sleeper. Measured: Rapier 0.36 wakes them (stock Rapier and the contact graph ride
//! down with the platform). Under fixation the boxes are held fixed, and a scripted
//! body never releases a held one (only a moving *simulated* body does), so the
//! platform sinks away from under them. The platform's position is computed from the step index
//! alone, never accumulated, so a replay from any step gives the same positions.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use super::{ground, tagged_body};
use crate::{new_world, Scene};

/// Half extents of the platform.
pub const PLATFORM_HALF: [Real; 3] = [1.5, 0.1, 1.5];
/// The platform's initial height (centre), m.
pub const PLATFORM_Y: Real = 1.0;
/// The step at which the platform starts sinking.
pub const MOVE_AT: u64 = 150;
/// The platform's sinking speed, m/s.
pub const SINK_SPEED: Real = 0.5;
/// Steps the platform sinks (0.8 m at 0.5 m/s and dt = 0.01).
pub const SINK_STEPS: u64 = 160;
/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.2;
/// The `user_data` tag of the platform.
pub const TAG_PLATFORM: u128 = 0x5354_4142_000a_0001;

/// The platform's centre height once step `step` has run.
pub fn platform_y_after(step: u64, dt: Real) -> Real {
    let moving = (step + 1).saturating_sub(MOVE_AT).min(SINK_STEPS);
    (PLATFORM_Y as f64 - moving as f64 * dt as f64 * SINK_SPEED as f64) as Real
}

/// Builds the scene. Bodies: `"ground"`, `"platform"` (kinematic), `"b0"`, `"b1"`,
/// `"b2"`.
pub fn platform_sleepers() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let [hx, hy, hz] = PLATFORM_HALF;
    let (platform, _) = world.insert(
        RigidBodyBuilder::kinematic_position_based()
            .translation(Vector::new(0.0, PLATFORM_Y, 0.0))
            .user_data(TAG_PLATFORM),
        ColliderBuilder::cuboid(hx, hy, hz),
    );
    let mut bodies = vec![("ground", g), ("platform", platform)];
    let y = PLATFORM_Y + hy + BOX_HALF + 0.001;
    for (name, x) in [("b0", -0.9), ("b1", 0.0), ("b2", 0.9)] {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0)),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
        bodies.push((name, h));
    }
    Scene {
        name: "platform_sleepers",
        world,
        bodies,
        script: Some(move_platform),
    }
}

fn move_platform(world: &mut PhysicsWorld, step: u64) {
    if step < MOVE_AT {
        return;
    }
    let y = platform_y_after(step, world.integration_parameters.dt);
    if let Some(h) = tagged_body(world, TAG_PLATFORM) {
        world.bodies[h].set_next_kinematic_translation(Vector::new(0.0, y, 0.0));
    }
}
