//! A heavy ball thrown into a settled pile of boxes.
//!
//! [`DisturbParams::boxes`] boxes settle in the 5 m bin on a fixed floor; before step
//! [`DisturbParams::at`] a ball of radius [`RADIUS`] and density [`DENSITY`] (4× the
//! boxes', CCD on) appears over the `-x` wall and flies at [`SPEED`] into the pile,
//! downwards at a slope of [`SLOPE`]. Without sleep it ploughs into the pile's near half; a pile
//! of held bodies (fixation, paper §7) stops it like a wall unless the layer releases
//! what it hits in time (Erleben 2004, §5: a sleepy group is woken by a body moving
//! into it).

use rapier3d::math::{Real, Vector};

use super::{drop_boxes, walls, Action, DisturbParams, Disturbance, BIN_HALF, WALL_HEIGHT};
use crate::stability::ground;
use crate::{new_world, Scene};

/// Ball radius, m.
pub const RADIUS: Real = 0.35;
/// Ball density (the boxes have 1).
pub const DENSITY: Real = 4.0;
/// Ball speed at the throw, m/s.
pub const SPEED: Real = 8.0;
/// Downward slope of the throw: vertical over horizontal speed.
pub const SLOPE: Real = 0.45;

/// Where the ball appears: over the `-x` wall, its bottom 0.25 m above the wall's top,
/// on the bin's centre line.
pub fn start() -> Vector {
    Vector::new(-BIN_HALF - 0.1, WALL_HEIGHT + RADIUS + 0.25, 0.0)
}

/// Builds the scene. Bodies: `"ground"`, `"walls"`; the ball is inserted at the
/// disturbance step ([`Disturbance::projectile`]).
pub fn thrown_ball(p: &DisturbParams) -> Disturbance {
    let mut world = new_world();
    let g = ground(&mut world, BIN_HALF + 1.0);
    let w = walls(&mut world, 0.0);
    let pile = drop_boxes(&mut world, p.boxes, -BIN_HALF, p.seed);
    let h = SPEED / (1.0 + SLOPE * SLOPE).sqrt();
    Disturbance {
        scene: Scene {
            name: "thrown_ball",
            world,
            bodies: vec![("ground", g), ("walls", w)],
            script: None,
        },
        pile,
        at: p.at,
        steps: p.at + p.after,
        projectile: None,
        action: Action::Throw {
            radius: RADIUS,
            density: DENSITY,
            start: start(),
            velocity: Vector::new(h, -SLOPE * h, 0.0),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ball_flies_over_the_wall_into_the_bin() {
        // No boxes: the ball alone clears the wall and lands inside.
        let mut d = thrown_ball(&DisturbParams {
            boxes: 0,
            at: 2,
            after: 60,
            seed: 0,
        });
        d.run_plain(0, d.steps);
        let b = &d.scene.world.bodies[d.projectile.unwrap()];
        let t = b.translation();
        assert!(t.x > -BIN_HALF + RADIUS && t.x < BIN_HALF, "{t:?}");
        assert!(t.y > 0.0 && t.y < WALL_HEIGHT, "{t:?}");
        assert!(b.is_ccd_enabled());
    }
}
