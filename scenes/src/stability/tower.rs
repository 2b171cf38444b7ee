//! A 20-box tower: the long contact chain that few solver iterations cannot hold.
//!
//! [`BOXES`] 0.5 m boxes stacked in one column on the ground, 1 mm apart. Its weight is
//! carried down a chain of 20 face contacts, and a solver iteration propagates load
//! along a few links only, so the lower contacts see the full weight only through warm
//! starting, which carries the impulses over from step to step.
//!
//! Built against tweak (1 solver iteration instead of 4). Measured: without warm start
//! (the cache switch off) the tower falls in every configuration, tweak or not, 16
//! iterations included, so the suite measures it on the cache switch
//! (`rcg_lab::stability::StabilityCase::base`); there one iteration keeps it standing, bouncing
//! (its top moves ±8 cm), and reduce drops it.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes (height).
pub const BOX_HALF: Real = 0.25;
/// Half width of the boxes (x and z).
pub const BOX_WIDTH: Real = BOX_HALF;
/// Boxes in the tower.
pub const BOXES: usize = 20;

/// Builds the scene. Bodies: `"ground"`, `"bottom"`, `"top"`; the others are unnamed
/// (bottom to top in handle order).
pub fn tower() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    let mut handles = Vec::with_capacity(BOXES);
    for i in 0..BOXES {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(
                0.0,
                BOX_HALF + gap + i as Real * step,
                0.0,
            )),
            ColliderBuilder::cuboid(BOX_WIDTH, BOX_HALF, BOX_WIDTH),
        );
        handles.push(h);
    }
    Scene {
        name: "tower",
        world,
        bodies: vec![
            ("ground", g),
            ("bottom", handles[0]),
            ("top", handles[BOXES - 1]),
        ],
        script: None,
    }
}
