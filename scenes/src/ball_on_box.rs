//! Ball on box: the smallest scene with a contact chain (ball – box – ground).
//!
//! A fixed ground slab (top face at `y = 0`), a unit dynamic box resting on it and a
//! ball dropped from `y = 2` onto the box. It exercises, in a couple of hundred steps,
//! a pair that already touches at step 0 (box–ground), a pair that is created, starts
//! touching and then rests (ball–box), and a three-body island — enough to check a
//! contact graph by hand. The ball is centred over the box so it lands on the top face
//! and stays there; the box starts exactly on the ground so nothing jumps.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Half extent of the cubic dynamic box.
pub const BOX_HALF: Real = 0.5;
/// Radius of the dropped ball.
pub const BALL_RADIUS: Real = 0.25;
/// Initial height of the ball's centre.
pub const BALL_DROP_Y: Real = 2.0;

/// Builds the scene: bodies `"ground"` (fixed), `"box"` and `"ball"` (dynamic).
pub fn ball_on_box() -> Scene {
    let mut world = new_world();

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (cube, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, BOX_HALF, 0.0)),
        ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, BALL_DROP_Y, 0.0)),
        ColliderBuilder::ball(BALL_RADIUS),
    );

    Scene {
        name: "ball_on_box",
        world,
        bodies: vec![("ground", ground), ("box", cube), ("ball", ball)],
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_comes_to_rest_on_the_box() {
        let mut scene = ball_on_box();
        assert_eq!(scene.world.integration_parameters.dt, 0.01);
        scene.run_plain(0, 200);
        let w = &scene.world;
        let ball = w.bodies[scene.body("ball").unwrap()].translation();
        let cube = w.bodies[scene.body("box").unwrap()].translation();
        let rest_y = 2.0 * BOX_HALF + BALL_RADIUS; // 1.25
        assert!((ball.y - rest_y).abs() < 0.05, "ball y = {}", ball.y);
        assert!(
            ball.x.abs() < 0.05 && ball.z.abs() < 0.05,
            "ball drifted: {ball:?}"
        );
        assert!((cube.y - BOX_HALF).abs() < 0.02, "box y = {}", cube.y);
        assert!(
            cube.x.abs() < 0.02 && cube.z.abs() < 0.02,
            "box drifted: {cube:?}"
        );
        assert!(w.bodies[scene.body("ball").unwrap()].linvel().length() < 0.05);
    }

    #[test]
    fn names_and_determinism() {
        let a = ball_on_box();
        assert_eq!(
            a.bodies.iter().map(|b| b.0).collect::<Vec<_>>(),
            ["ground", "box", "ball"]
        );
        assert!(a.world.bodies[a.body("ground").unwrap()].is_fixed());
        assert!(a.body("nope").is_none());
        let mut a = a;
        let mut b = ball_on_box();
        a.run_plain(0, 150);
        b.run_plain(0, 150);
        for (name, h) in &a.bodies {
            let hb = b.body(name).unwrap();
            assert_eq!(a.world.bodies[*h].position(), b.world.bodies[hb].position());
        }
    }
}
