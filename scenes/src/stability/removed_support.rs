//! A body removed from under a sleeping stack.
//!
//! Four 0.5 m boxes stand in a column on the ground (1 mm gaps). At step
//! [`REMOVE_AT`] (1.5 s: after every kind of sleep has put the column to sleep —
//! Rapier's own takes 0.5 s at rest) the script removes the bottom box, so the
//! three above should drop 0.5 m onto the ground.
//!
//! Rapier wakes the bodies touching a removed collider, so its own sleep handles this
//! (measured: stock Rapier and the contact graph drop the column as the reference
//! does). Fixation does not: its held bodies are not asleep in Rapier but fixed, and
//! only a moving body touching them releases them, so the three boxes stay in the air.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use super::{ground, tagged_body};
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// The step before which the script removes the bottom box.
pub const REMOVE_AT: u64 = 150;
/// The `user_data` tag of the bottom box (how the script finds it).
pub const TAG_BOTTOM: u128 = 0x5354_4142_0009_0001;

/// Builds the scene. Bodies: `"ground"`, `"bottom"` (removed at [`REMOVE_AT`]), `"b1"`,
/// `"b2"`, `"top"`.
pub fn removed_support() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    let mut bodies = vec![("ground", g)];
    for (i, name) in ["bottom", "b1", "b2", "top"].into_iter().enumerate() {
        let tag = if i == 0 { TAG_BOTTOM } else { 0 };
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, BOX_HALF + gap + i as Real * step, 0.0))
                .user_data(tag),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
        bodies.push((name, h));
    }
    Scene {
        name: "removed_support",
        world,
        bodies,
        script: Some(remove_bottom),
    }
}

fn remove_bottom(world: &mut PhysicsWorld, step: u64) {
    if step >= REMOVE_AT {
        if let Some(h) = tagged_body(world, TAG_BOTTOM) {
            world.remove_body(h);
        }
    }
}
