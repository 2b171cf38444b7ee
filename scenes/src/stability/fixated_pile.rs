//! A released fixated pile (paper Fig. 15 ♠, "objects fly up in the air"): a heavy
//! ball dropped on a wall of boxes that came to rest.
//!
//! Twenty 0.5 m boxes stand in a wall five wide and four high on the ground (1 mm
//! gaps). A ball [`BALL_DENSITY`] times as dense as the boxes falls from
//! [`DROP_HEIGHT`] above the wall and lands on the edge between two top boxes after
//! about 0.7 s, when the wall has long been at rest, and knocks them about.
//!
//! Built against fixation: every box of the resting wall is held fixed when the ball
//! lands, and the ball releases the boxes it touches. In the paper the bodies held
//! with inverse mass zero kept sinking into each other, and releasing them let the
//! position correction throw them up. In this crate a held body is a fixed body
//! (nothing sinks into it further than into the ground) and a released body gets back
//! exactly the velocity it had, so the scene measures whether any energy appears at the
//! release. Measured: none does, in any configuration; fixation even spares the wall
//! the deep penetrations the impact causes without it. Tweak and reduce add to them.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes.
pub const BOX_HALF: Real = 0.25;
/// Boxes across and rows of the wall.
pub const WALL: (usize, usize) = (5, 4);
/// The ball's radius.
pub const BALL_RADIUS: Real = 0.4;
/// The ball's density relative to the boxes' (1).
pub const BALL_DENSITY: Real = 3.0;
/// Height of the ball's lowest point above the wall's top, m.
pub const DROP_HEIGHT: Real = 2.5;

/// Builds the scene. Bodies: `"ground"`, `"ball"`; the boxes are unnamed (row by row
/// from the bottom, left to right).
pub fn fixated_pile() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let gap = 0.001;
    let (cols, rows) = WALL;
    let step = 2.0 * BOX_HALF + gap;
    let x0 = -(cols as Real - 1.0) * step / 2.0;
    for row in 0..rows {
        for col in 0..cols {
            let at = Vector::new(
                x0 + col as Real * step,
                BOX_HALF + gap + row as Real * step,
                0.0,
            );
            world.insert(
                RigidBodyBuilder::dynamic().translation(at),
                ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
            );
        }
    }
    let top = rows as Real * step + gap;
    // Aimed between two top boxes (x = step / 2), so it lands on their edges.
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(
            step / 2.0,
            top + DROP_HEIGHT + BALL_RADIUS,
            0.0,
        )),
        ColliderBuilder::ball(BALL_RADIUS).density(BALL_DENSITY),
    );
    Scene {
        name: "fixated_pile",
        world,
        bodies: vec![("ground", g), ("ball", ball)],
        script: None,
    }
}
