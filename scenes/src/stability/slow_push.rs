//! A box pushed slowly into a pile at rest (a held body that a contact should move).
//!
//! Five 0.5 m boxes rest on the ground (1 mm gaps): a row of three along +x, and two
//! more on top, each bridging two boxes of the row (a pile whose boxes all touch
//! through the upper ones). A pusher box of the same size,
//! [`PUSHER_DENSITY`] times as dense, stands
//! [`PUSH_GAP`] to the row's left; from the first step the script sets its velocity
//! along +x to [`PUSH_SPEED`] before every step (what a user's controller or a
//! constant drive does), so it reaches the row after about 1.5 s, when every kind of
//! sleep has put the pile to rest, and pushes it for the rest of the run.
//!
//! Built against fixation: the pile's boxes are held fixed by then, and the pusher
//! is slower than the speed-ups' `release_speed` (0.5 m/s), so nothing releases them:
//! the row stops the pusher as a wall would. Rapier's own sleep and the contact
//! graph's wake the pile when the pusher touches it and push it along, as the
//! reference does. The monitor reports the stopped push as an unresponsive held
//! body; its repair releases the pile.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use super::{ground, tagged_body};
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// The pusher's speed along +x, m/s (below the speed-ups' default `release_speed`).
pub const PUSH_SPEED: Real = 0.3;
/// The gap between the pusher and the row at the start, m (1.5 s at [`PUSH_SPEED`]).
pub const PUSH_GAP: Real = 0.45;
/// The pusher's density relative to the pile's boxes' (1): heavy enough that the
/// drive pushes the pile along against the ground's friction.
pub const PUSHER_DENSITY: Real = 10.0;
/// The `user_data` tag of the pusher (how the script finds it).
pub const TAG_PUSHER: u128 = 0x5354_4142_000e_0001;

/// Builds the scene. Bodies: `"ground"`, `"pusher"`, `"b0"`, `"b1"`, `"b2"` (the row,
/// from the pusher's side), `"t01"`, `"t12"` (on `b0` and `b1`, on `b1` and `b2`).
pub fn slow_push() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    let cube = || ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF);
    let mut bodies = vec![("ground", g)];
    let (pusher, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-2.0 * BOX_HALF - PUSH_GAP, BOX_HALF + gap, 0.0))
            .user_data(TAG_PUSHER),
        cube().density(PUSHER_DENSITY),
    );
    bodies.push(("pusher", pusher));
    for (i, name) in ["b0", "b1", "b2"].into_iter().enumerate() {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(
                i as Real * step,
                BOX_HALF + gap,
                0.0,
            )),
            cube(),
        );
        bodies.push((name, h));
    }
    for (i, name) in [(0, "t01"), (1, "t12")] {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(
                (i as Real + 0.5) * step,
                BOX_HALF + gap + step,
                0.0,
            )),
            cube(),
        );
        bodies.push((name, h));
    }
    Scene {
        name: "slow_push",
        world,
        bodies,
        script: Some(push),
    }
}

/// Sets the pusher's velocity along +x to [`PUSH_SPEED`] (the other components as
/// they are), whatever the step.
fn push(world: &mut PhysicsWorld, _step: u64) {
    if let Some(h) = tagged_body(world, TAG_PUSHER) {
        let rb = &mut world.bodies[h];
        if rb.is_dynamic() {
            let v = rb.linvel();
            rb.set_linvel(Vector::new(PUSH_SPEED, v.y, v.z), true);
        }
    }
}
