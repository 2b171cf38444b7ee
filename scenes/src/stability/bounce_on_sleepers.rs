//! A bouncing ball landing on a sleeping pile: the scene for zeroed restitution.
//!
//! A block of 3 × 3 × 2 boxes (0.5 m, 1 mm gaps) rests on the ground. A bouncy ball
//! (restitution [`RESTITUTION`], combined with the boxes' 0 by taking the larger, so the
//! ball's own restitution rules every pair) falls from [`DROP_HEIGHT`] above the
//! block's top and lands on the middle box after about 0.64 s, when the block has been
//! at rest for several tenths of a second. It should bounce back up, several times.
//!
//! Built against zero: a pair with a sleepy body gets restitution 0, and every box of
//! the block is sleepy when the ball lands, so the first bounce is lost.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{CoefficientCombineRule, ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// The ball's radius.
pub const BALL_RADIUS: Real = 0.2;
/// The ball's restitution.
pub const RESTITUTION: Real = 0.9;
/// Height of the ball's lowest point above the block's top, m.
pub const DROP_HEIGHT: Real = 2.0;

/// Builds the scene. Bodies: `"ground"`, `"ball"`; the boxes are unnamed.
pub fn bounce_on_sleepers() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let step = 2.0 * BOX_HALF + gap;
    for layer in 0..2 {
        for i in 0..3 {
            for k in 0..3 {
                world.insert(
                    RigidBodyBuilder::dynamic().translation(Vector::new(
                        (i as Real - 1.0) * step,
                        BOX_HALF + gap + layer as Real * step,
                        (k as Real - 1.0) * step,
                    )),
                    ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
                );
            }
        }
    }
    let top = 2.0 * step + gap;
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(
            0.0,
            top + DROP_HEIGHT + BALL_RADIUS,
            0.0,
        )),
        ColliderBuilder::ball(BALL_RADIUS)
            .restitution(RESTITUTION)
            .restitution_combine_rule(CoefficientCombineRule::Max)
            .density(0.2),
    );
    Scene {
        name: "bounce_on_sleepers",
        world,
        bodies: vec![("ground", g), ("ball", ball)],
        script: None,
    }
}
