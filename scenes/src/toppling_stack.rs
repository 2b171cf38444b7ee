//! Toppling stack: a column of five boxes built offset so that it falls over.
//!
//! Box *i* sits exactly on box *i − 1* but shifted [`SHIFT`] further along +x, so the
//! centre of mass of the boxes above the bottom one lies beyond the bottom box's edge:
//! the column leans, pivots and collapses, the top box reaching the ground near step 120. It
//! is the scene for contacts that *change*: every pair that touches at step 0
//! (ground–b0, b0–b1, ...) is stressed, many of them break, and new pairs (boxes
//! against the ground) begin, so one run exercises the touch lifecycle and the
//! splitting and merging of contact groups. The boxes start exactly in contact (no
//! gap, no overlap), so nothing jumps at step 0 and the fall comes from gravity alone.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Number of boxes in the column.
pub const BOXES: usize = 5;
/// Half extent of each cubic box.
pub const BOX_HALF: Real = 0.25;
/// How much further along +x each box is shifted than the one below it.
pub const SHIFT: Real = 0.2;

/// The names of the boxes, bottom first.
const NAMES: [&str; BOXES] = ["b0", "b1", "b2", "b3", "b4"];

/// Builds the scene: `"ground"` (fixed, top face at `y = 0`) and the dynamic boxes
/// `"b0"` (on the ground) to `"b4"` (on top), box *i* at `x = i·SHIFT`.
pub fn toppling_stack() -> Scene {
    let mut world = new_world();

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(6.0, 0.5, 6.0),
    );
    let mut bodies = vec![("ground", ground)];
    for (i, name) in NAMES.iter().enumerate() {
        let x = i as Real * SHIFT;
        let y = BOX_HALF + 2.0 * BOX_HALF * i as Real;
        let (b, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, 0.0)),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
        bodies.push((*name, b));
    }

    Scene {
        name: "toppling_stack",
        world,
        bodies,
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_column_falls_onto_the_ground() {
        let mut scene = toppling_stack();
        assert_eq!(scene.world.integration_parameters.dt, 0.01);
        let top = scene.body("b4").unwrap();
        let start_y = scene.world.bodies[top].translation().y;
        assert!((start_y - 9.0 * BOX_HALF).abs() < 1e-6);

        // It does not stand: after a few steps it leans further along +x.
        scene.run_plain(0, 30);
        let x30 = scene.world.bodies[top].translation().x;
        assert!(x30 > 4.0 * SHIFT + 0.02, "top box x = {x30}: not leaning");

        scene.run_plain(30, 170);
        let w = &scene.world;
        // The top box ends near the ground (it started 2.25 m up).
        let y = w.bodies[top].translation().y;
        assert!(y < 4.0 * BOX_HALF, "top box still at y = {y}");
        // No box is left stacked high, and every box stayed on the ground slab.
        for name in NAMES {
            let p = w.bodies[scene.body(name).unwrap()].translation();
            assert!(p.y < 5.0 * BOX_HALF, "{name} at {p:?}");
            assert!(p.y > BOX_HALF * 0.5, "{name} fell through: {p:?}");
            assert!(
                p.x.abs() < 5.5 && p.z.abs() < 5.5,
                "{name} left the ground: {p:?}"
            );
        }
    }

    #[test]
    fn names_and_determinism() {
        let a = toppling_stack();
        assert_eq!(
            a.bodies.iter().map(|b| b.0).collect::<Vec<_>>(),
            ["ground", "b0", "b1", "b2", "b3", "b4"]
        );
        assert!(a.world.bodies[a.body("ground").unwrap()].is_fixed());
        let mut a = a;
        let mut b = toppling_stack();
        a.run_plain(0, 150);
        b.run_plain(0, 150);
        for (name, h) in &a.bodies {
            let hb = b.body(name).unwrap();
            assert_eq!(a.world.bodies[*h].position(), b.world.bodies[hb].position());
        }
    }
}
