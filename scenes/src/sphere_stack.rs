//! Sphere stack: a vertical column of spheres, the classic "long contact chain".
//!
//! `n` spheres of radius 0.5 are stacked on a fixed ground with a 0.01 gap between
//! neighbours, so every pair starts separated but within Rapier's prediction distance
//! and the column settles in a few steps into a chain ground – s0 – s1 – … . A
//! perfectly aligned stack stays upright in Rapier; the spheres get friction anyway so
//! small solver asymmetries cannot roll them off one another. It is the scene for
//! checking anything that propagates along a chain of contacts (paths, layers, depth).
//!
//! Body names must be `&'static str`, so they come from a static table and `n` is
//! clamped to [`MAX_SPHERES`].

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Largest supported stack height; `sphere_stack(n)` clamps `n` to this.
pub const MAX_SPHERES: usize = 16;
/// Radius of every sphere.
pub const RADIUS: Real = 0.5;
/// Initial gap between neighbouring spheres (and between `s0` and the ground).
pub const GAP: Real = 0.01;
/// Friction coefficient given to the spheres.
pub const FRICTION: Real = 1.0;

const NAMES: [&str; MAX_SPHERES] = [
    "s0", "s1", "s2", "s3", "s4", "s5", "s6", "s7", "s8", "s9", "s10", "s11", "s12", "s13", "s14",
    "s15",
];

/// Builds a stack of `n` spheres (clamped to `1..=MAX_SPHERES`) on a fixed ground
/// whose top face is at `y = 0`. Bodies: `"ground"`, then `"s0"` (bottom) up to
/// `"s{n-1}"` (top). Sphere `i` starts at `y = GAP + RADIUS + i * (2 * RADIUS + GAP)`.
pub fn sphere_stack(n: usize) -> Scene {
    let n = n.clamp(1, MAX_SPHERES);
    let mut world = new_world();
    let mut bodies = Vec::with_capacity(n + 1);

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    bodies.push(("ground", ground));

    for (i, name) in NAMES.iter().take(n).enumerate() {
        let y = GAP + RADIUS + i as Real * (2.0 * RADIUS + GAP);
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, y, 0.0)),
            ColliderBuilder::ball(RADIUS).friction(FRICTION),
        );
        bodies.push((*name, h));
    }

    Scene {
        name: "sphere_stack",
        world,
        bodies,
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stack_of_three_stays_upright() {
        let mut scene = sphere_stack(3);
        assert_eq!(scene.bodies.len(), 4);
        scene.run_plain(0, 200);
        let w = &scene.world;
        let mut prev_y = 0.0;
        for (i, name) in ["s0", "s1", "s2"].iter().enumerate() {
            let p = w.bodies[scene.body(name).unwrap()].translation();
            let expected = RADIUS + i as Real * 2.0 * RADIUS;
            assert!(
                (p.y - expected).abs() < 0.05,
                "{name} y = {} (want {expected})",
                p.y
            );
            assert!(
                p.x.abs() < 0.05 && p.z.abs() < 0.05,
                "{name} slid off: {p:?}"
            );
            assert!(p.y > prev_y);
            prev_y = p.y;
        }
    }

    #[test]
    fn n_is_clamped() {
        let scene = sphere_stack(100);
        assert_eq!(scene.bodies.len(), MAX_SPHERES + 1);
        assert_eq!(scene.bodies.last().unwrap().0, "s15");
        assert_eq!(sphere_stack(0).bodies.len(), 2);
    }
}
