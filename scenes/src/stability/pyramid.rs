//! A 10-level pyramid of boxes: many contacts per body, the other classic solver test.
//!
//! [`LEVELS`] rows of 0.5 m boxes, the bottom one [`LEVELS`] wide, each row one box
//! shorter and centred on the one below (55 boxes), 1 mm apart. Each box rests on two
//! below it (four on the half-overlaps of the bottom row), so the weight spreads
//! sideways as it goes down, and the bottom row carries the rest.
//!
//! Built against tweak (1 solver iteration instead of 4). Measured: without warm start
//! (the contact graph's base) one iteration lets the boxes sink into each other, tens
//! of deep penetrations, and so does reduce; with warm start neither does.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// Rows of the pyramid (the bottom row has this many boxes).
pub const LEVELS: usize = 10;

/// Builds the scene. Bodies: `"ground"`, `"apex"`; the others are unnamed (row by row
/// from the bottom, left to right).
pub fn pyramid() -> Scene {
    pyramid_of(LEVELS)
}

/// The same pyramid with `levels` rows (`levels * (levels + 1) / 2` boxes), for the
/// benchmarks: stock Rapier puts a pyramid of 40 rows to sleep too.
pub fn pyramid_of(levels: usize) -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0_f32.max(levels as Real * 0.3));
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    let mut apex = None;
    for row in 0..levels {
        let n = levels - row;
        let x0 = -(n as Real - 1.0) * step / 2.0;
        for i in 0..n {
            let (h, _) = world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(
                    x0 + i as Real * step,
                    BOX_HALF + gap + row as Real * step,
                    0.0,
                )),
                ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
            );
            apex = Some(h);
        }
    }
    let mut bodies = vec![("ground", g)];
    if let Some(h) = apex {
        bodies.push(("apex", h));
    }
    Scene {
        name: "pyramid",
        world,
        bodies,
        script: None,
    }
}
