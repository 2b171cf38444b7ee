//! A sleeper jointed to a kinematic body (Rapier #287, #692: a body asleep is not woken
//! when the kinematic body it is jointed to moves).
//!
//! A 0.5 m crate rests on the ground, tied by a spherical joint at the middle of its
//! left face to a kinematic (position-based) hook 0.75 m further left. The hook stands
//! still until step [`MOVE_AT`] (1.5 s: every kind of sleep has put the crate to
//! sleep by then), then moves along −x at [`DRAG_SPEED`] for [`DRAG_STEPS`] steps and stops,
//! dragging the crate 1 m over the ground.
//!
//! A sleeping crate that is not woken stays where it was while the joint stretches.
//! It still rests on the ground, so no violation is reported: the failure is the
//! motion. Measured: Rapier 0.36 wakes it (stock Rapier and the contact graph drag it
//! as the reference does); under fixation the crate is held fixed and a scripted body
//! never releases it. The drag is slow (0.5 m/s, 0.125 J/kg of kinetic energy) so that the work the
//! hook does stays under the launch detector's tolerance.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder, SphericalJointBuilder};

use super::{ground, tagged_body};
use crate::{new_world, Scene};

/// Half extent of the crate.
pub const CRATE_HALF: Real = 0.25;
/// The hook's initial x (the crate's centre is at x = 0).
pub const HOOK_X: Real = -1.0;
/// The step at which the hook starts moving.
pub const MOVE_AT: u64 = 150;
/// The hook's speed along −x, m/s.
pub const DRAG_SPEED: Real = 0.5;
/// Steps the hook moves (1 m at 0.5 m/s and dt = 0.01).
pub const DRAG_STEPS: u64 = 200;
/// The `user_data` tag of the hook.
pub const TAG_HOOK: u128 = 0x5354_4142_000b_0001;

/// The hook's x once step `step` has run.
pub fn hook_x_after(step: u64, dt: Real) -> Real {
    let moving = (step + 1).saturating_sub(MOVE_AT).min(DRAG_STEPS);
    (HOOK_X as f64 - moving as f64 * dt as f64 * DRAG_SPEED as f64) as Real
}

/// Builds the scene. Bodies: `"ground"`, `"hook"` (kinematic, no collider), `"crate"`.
pub fn jointed_sleeper() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let hook = world.insert_body(
        RigidBodyBuilder::kinematic_position_based()
            .translation(Vector::new(HOOK_X, CRATE_HALF, 0.0))
            .user_data(TAG_HOOK),
    );
    let (cube, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, CRATE_HALF + 0.001, 0.0)),
        ColliderBuilder::cuboid(CRATE_HALF, CRATE_HALF, CRATE_HALF),
    );
    let joint = SphericalJointBuilder::new()
        .local_anchor1(Vector::new(-HOOK_X - CRATE_HALF, 0.0, 0.0))
        .local_anchor2(Vector::new(-CRATE_HALF, 0.0, 0.0));
    world.impulse_joints.insert(hook, cube, joint, true);
    Scene {
        name: "jointed_sleeper",
        world,
        bodies: vec![("ground", g), ("hook", hook), ("crate", cube)],
        script: Some(drag),
    }
}

fn drag(world: &mut PhysicsWorld, step: u64) {
    if step < MOVE_AT {
        return;
    }
    let x = hook_x_after(step, world.integration_parameters.dt);
    if let Some(h) = tagged_body(world, TAG_HOOK) {
        world.bodies[h].set_next_kinematic_translation(Vector::new(x, CRATE_HALF, 0.0));
    }
}
