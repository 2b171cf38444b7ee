//! Kinematic platform: a scripted, position-based kinematic body carrying a box.
//!
//! A platform moves along +x at a constant 0.5 m/s and a dynamic box rides on it by
//! friction; a fixed ground sits far below (top at `y = -5`) so that nothing else
//! interferes. It is the scene for anything that must treat kinematic bodies right:
//! they are island members but are driven, not simulated, and the contact they carry
//! stays active while the platform keeps moving. The platform's target is computed
//! from the step index and `dt` alone ([`platform_x_after`]), never accumulated, so a
//! replay from any step gives the same positions.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle};

use super::{new_world, Scene};

/// Platform speed along +x, in m/s.
pub const PLATFORM_SPEED: Real = 0.5;
/// Half extents of the platform cuboid.
pub const PLATFORM_HALF: [Real; 3] = [1.0, 0.1, 1.0];
/// Half extent of the riding box.
pub const BOX_HALF: Real = 0.25;

/// The platform's x position once step `step` (0-based) has run, for time step `dt`:
/// `(step + 1) * dt * PLATFORM_SPEED`, computed in `f64` so it does not accumulate error.
pub fn platform_x_after(step: u64, dt: Real) -> Real {
    (step.saturating_add(1) as f64 * dt as f64 * PLATFORM_SPEED as f64) as Real
}

/// Builds the scene. Bodies: `"ground"` (fixed), `"platform"` (kinematic, position
/// based, starts at the origin) and `"box"` (dynamic, resting on the platform). The
/// scene's script moves the platform; call [`Scene::before_step`] before every step.
pub fn kinematic_platform() -> Scene {
    let mut world = new_world();

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -5.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let [hx, hy, hz] = PLATFORM_HALF;
    let (platform, _) = world.insert(
        RigidBodyBuilder::kinematic_position_based().translation(Vector::ZERO),
        ColliderBuilder::cuboid(hx, hy, hz),
    );
    let (cube, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, hy + BOX_HALF, 0.0)),
        ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
    );

    Scene {
        name: "kinematic_platform",
        world,
        bodies: vec![("ground", ground), ("platform", platform), ("box", cube)],
        script: Some(move_platform),
    }
}

/// The scene's script: sets the platform's next translation for step `step`.
fn move_platform(world: &mut PhysicsWorld, step: u64) {
    let x = platform_x_after(step, world.integration_parameters.dt);
    if let Some(platform) = find_platform(world) {
        world.bodies[platform].set_next_kinematic_translation(Vector::new(x, 0.0, 0.0));
    }
}

/// The one kinematic body of the world (a `Script` gets no scene, only the world).
fn find_platform(world: &PhysicsWorld) -> Option<RigidBodyHandle> {
    world
        .bodies
        .iter()
        .find(|(_, b)| b.is_kinematic())
        .map(|(h, _)| h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn platform_moves_exactly_and_carries_the_box() {
        let mut scene = kinematic_platform();
        let platform = scene.body("platform").unwrap();
        let cube = scene.body("box").unwrap();
        assert!(scene.world.bodies[platform].is_kinematic());
        scene.run_plain(0, 100);
        let w = &scene.world;
        let p = w.bodies[platform].translation();
        let expected = 100.0 * 0.01 * 0.5;
        assert!((p.x - expected).abs() < 1e-4, "platform x = {}", p.x);
        assert!(
            p.y.abs() < 1e-6 && p.z.abs() < 1e-6,
            "platform left its line: {p:?}"
        );
        let b = w.bodies[cube].translation();
        assert!(
            (b.x - p.x).abs() < 0.1,
            "box x = {} vs platform {}",
            b.x,
            p.x
        );
        assert!(
            (b.y - (PLATFORM_HALF[1] + BOX_HALF)).abs() < 0.02,
            "box y = {}",
            b.y
        );
    }

    #[test]
    fn split_run_equals_single_run() {
        let mut a = kinematic_platform();
        let mut b = kinematic_platform();
        a.run_plain(0, 60);
        b.run_plain(0, 25);
        b.run_plain(25, 35);
        for (name, h) in &a.bodies {
            let hb = b.body(name).unwrap();
            assert_eq!(a.world.bodies[*h].position(), b.world.bodies[hb].position());
        }
    }
}
