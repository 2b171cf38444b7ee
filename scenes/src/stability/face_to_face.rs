//! Boxes resting face to face: the scene for contact reduction.
//!
//! A column of [`BOXES`] 0.5 m boxes stands on the ground (1 mm gaps): every contact is
//! a face on a face, four contact points each. Without warm start (the contact graph's
//! base configuration: the cache switch off) the solver lets the lower faces sink
//! more than a centimetre under the weight above while the column settles.
//!
//! Built against reduce: a pair deeper than the reduce depth (5 mm) keeps only its
//! deepest contact point, so a face that should rest on four corners rests on one, the
//! box pivots about it, and the column leans and falls. Measured: it does, and so it
//! does under tweak; with warm start (the cache switch) the faces sink less than the
//! reduce depth and reduce changes nothing.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// Boxes in the column.
pub const BOXES: usize = 4;

/// Builds the scene. Bodies: `"ground"`, `"b0"` (bottom) to `"b3"`.
pub fn face_to_face() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    let mut bodies = vec![("ground", g)];
    const NAMES: [&str; BOXES] = ["b0", "b1", "b2", "b3"];
    for (i, name) in NAMES.iter().enumerate() {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(
                0.0,
                BOX_HALF + gap + i as Real * step,
                0.0,
            )),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
        bodies.push((*name, h));
    }
    Scene {
        name: "face_to_face",
        world,
        bodies,
        script: None,
    }
}
