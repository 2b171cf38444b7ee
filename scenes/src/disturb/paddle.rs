//! A kinematic paddle sweeping through a settled box pile.
//!
//! A vertical kinematic plate stands against the bin's `-x` wall while the boxes
//! settle beside it (the drop grid leaves it [`CLEARANCE`] m); before step
//! [`DisturbParams::at`] it starts to move along `+x` at [`SPEED`] for [`DURATION`] s,
//! pushing the pile's near part before it. Rapier keeps no contact between a
//! kinematic and a fixed body, so a held body (fixation, paper §7) lets the paddle
//! pass through it unless the layer releases it first (Erleben 2004, §5).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{drop_boxes, walls, Action, DisturbParams, Disturbance, BIN_HALF};
use crate::stability::ground;
use crate::{new_world, Scene};

/// The paddle's half extents (thin along `x`), m.
pub const HALF: Vector = Vector::new(0.05, 0.35, 0.6);
/// The paddle's speed, m/s.
pub const SPEED: Real = 1.0;
/// How long it moves, s (it stops 1.2 m into the bin).
pub const DURATION: Real = 1.2;
/// The strip along the `-x` wall left free of boxes, m.
pub const CLEARANCE: Real = 0.3;

/// Builds the scene. Bodies: `"ground"`, `"walls"`, `"paddle"` (kinematic, position
/// based).
pub fn paddle(p: &DisturbParams) -> Disturbance {
    let mut world = new_world();
    let g = ground(&mut world, BIN_HALF + 1.0);
    let w = walls(&mut world, 0.0);
    let start = Vector::new(-BIN_HALF + HALF.x + 0.02, HALF.y + 0.01, 0.0);
    let (paddle, _) = world.insert(
        RigidBodyBuilder::kinematic_position_based().translation(start),
        ColliderBuilder::cuboid(HALF.x, HALF.y, HALF.z),
    );
    let pile = drop_boxes(&mut world, p.boxes, -BIN_HALF + CLEARANCE, p.seed);
    Disturbance {
        scene: Scene {
            name: "paddle",
            world,
            bodies: vec![("ground", g), ("walls", w), ("paddle", paddle)],
            script: None,
        },
        pile,
        at: p.at,
        steps: p.at + p.after,
        projectile: None,
        action: Action::Sweep {
            body: paddle,
            start,
            velocity: Vector::new(SPEED, 0.0, 0.0),
            duration: DURATION,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paddle_waits_then_moves_and_stops() {
        let mut d = paddle(&DisturbParams {
            boxes: 0,
            at: 10,
            after: 200,
            seed: 0,
        });
        let h = d.scene.body("paddle").unwrap();
        let x0 = d.scene.world.bodies[h].translation().x;
        d.run_plain(0, 10);
        assert_eq!(d.scene.world.bodies[h].translation().x, x0);
        d.run_plain(10, 50);
        let x = d.scene.world.bodies[h].translation().x;
        assert!((x - x0 - 0.5).abs() < 1e-3, "{x}");
        d.run_plain(60, 150);
        let x = d.scene.world.bodies[h].translation().x;
        assert!((x - x0 - SPEED * DURATION).abs() < 1e-3, "{x}");
    }
}
