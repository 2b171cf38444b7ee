//! A static collider moved under sleepers (avian #654: "sleeping body doesn't wake up
//! when static collider changes", left floating in the air).
//!
//! A shelf — a collider without a parent body, Rapier's static geometry — 1 m above the
//! ground carries two 0.4 m boxes. At step [`MOVE_AT`] (1.5 s: every kind of sleep has
//! put the boxes to sleep by then) the script moves the shelf 4 m aside, once. The
//! boxes should fall to the ground. A sleeper that is not woken stays in the air, a
//! hanging sleeper. Measured: Rapier wakes them (stock Rapier and the contact graph
//! drop them as the reference does); fixation does not, and they stay in the air.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use super::{ground, tagged_collider};
use crate::{new_world, Scene};

/// Half extents of the shelf.
pub const SHELF_HALF: [Real; 3] = [1.0, 0.1, 1.0];
/// The shelf's centre height, m.
pub const SHELF_Y: Real = 1.0;
/// How far the shelf moves along +x, m.
pub const SHIFT: Real = 4.0;
/// The step at which the shelf moves.
pub const MOVE_AT: u64 = 150;
/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.2;
/// The `user_data` tag of the shelf collider.
pub const TAG_SHELF: u128 = 0x5354_4142_000d_0001;

/// Builds the scene. Bodies: `"ground"`, `"b0"`, `"b1"`; the shelf is a collider
/// tagged [`TAG_SHELF`].
pub fn static_moved() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let [hx, hy, hz] = SHELF_HALF;
    world.insert_collider(
        ColliderBuilder::cuboid(hx, hy, hz)
            .translation(Vector::new(0.0, SHELF_Y, 0.0))
            .user_data(TAG_SHELF),
        None,
    );
    let mut bodies = vec![("ground", g)];
    let y = SHELF_Y + hy + BOX_HALF + 0.001;
    for (name, x) in [("b0", -0.5), ("b1", 0.5)] {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0)),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
        bodies.push((name, h));
    }
    Scene {
        name: "static_moved",
        world,
        bodies,
        script: Some(move_shelf),
    }
}

fn move_shelf(world: &mut PhysicsWorld, step: u64) {
    let x = if step >= MOVE_AT { SHIFT } else { 0.0 };
    if let Some(c) = tagged_collider(world, TAG_SHELF) {
        let target = Vector::new(x, SHELF_Y, 0.0);
        // Only when it differs: setting a collider's pose marks it modified.
        if world.colliders[c].translation() != target {
            world.colliders[c].set_translation(target);
        }
    }
}
