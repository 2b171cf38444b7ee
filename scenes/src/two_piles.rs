//! Two piles with a wall: two contact groups that share only a fixed body.
//!
//! A fixed thin wall stands on a fixed ground at `x = 0`; on each side a 2 × 2 pile of
//! boxes leans against it (1 mm gaps, within Rapier's prediction distance). Both piles
//! touch the wall and the ground, but never each other. Fixed bodies do not join
//! simulation islands, so the scene checks that anything grouping bodies by contact
//! (islands, contact groups, coherence) keeps the left pile `l0..l3` and the right pile
//! `r0..r3` apart instead of merging them through the shared wall or ground. The layout
//! is mirror-symmetric so the two groups should evolve as mirror images.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Half thickness (along x) of the wall.
pub const WALL_HALF_X: Real = 0.1;
/// Half height of the wall (it stands on the ground, top at `y = 2 * WALL_HALF_Y`).
pub const WALL_HALF_Y: Real = 1.5;
/// Half depth (along z) of the wall.
pub const WALL_HALF_Z: Real = 3.0;
/// Half extent of every pile box.
pub const BOX_HALF: Real = 0.4;

const LEFT: [&str; 4] = ["l0", "l1", "l2", "l3"];
const RIGHT: [&str; 4] = ["r0", "r1", "r2", "r3"];

/// Builds the scene. Bodies: `"ground"`, `"wall"` (both fixed), then the left pile
/// `"l0".."l3"` and the right pile `"r0".."r3"` (dynamic). In each pile, index 0 is
/// bottom-near-wall, 1 bottom-far, 2 top-near-wall, 3 top-far.
pub fn two_piles_with_wall() -> Scene {
    let mut world = new_world();
    let mut bodies = Vec::with_capacity(10);

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    bodies.push(("ground", ground));
    let (wall, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, WALL_HALF_Y, 0.0)),
        ColliderBuilder::cuboid(WALL_HALF_X, WALL_HALF_Y, WALL_HALF_Z),
    );
    bodies.push(("wall", wall));

    // Distance of the box centres from the wall plane x = 0.
    let near = WALL_HALF_X + BOX_HALF + 0.001;
    let far = WALL_HALF_X + 3.0 * BOX_HALF + 0.002;
    let bottom = BOX_HALF;
    let top = 3.0 * BOX_HALF + 0.001;
    let layout = [(near, bottom), (far, bottom), (near, top), (far, top)];

    for (side, names) in [(-1.0, LEFT), (1.0, RIGHT)] {
        for (name, &(dx, y)) in names.iter().zip(layout.iter()) {
            let (h, _) = world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(side * dx, y, 0.0)),
                ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
            );
            bodies.push((*name, h));
        }
    }

    Scene {
        name: "two_piles_with_wall",
        world,
        bodies,
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piles_stay_on_their_side() {
        let mut scene = two_piles_with_wall();
        assert_eq!(scene.bodies.len(), 10);
        scene.run_plain(0, 200);
        let w = &scene.world;
        for (name, h) in &scene.bodies {
            let p = w.bodies[*h].translation();
            if name.starts_with('l') {
                assert!(p.x < -0.05, "{name} crossed: {p:?}");
                assert!(
                    p.x < -(WALL_HALF_X + BOX_HALF) + 0.01,
                    "{name} in wall: {p:?}"
                );
            } else if name.starts_with('r') {
                assert!(p.x > 0.05, "{name} crossed: {p:?}");
                assert!(p.x > WALL_HALF_X + BOX_HALF - 0.01, "{name} in wall: {p:?}");
            }
            if name.len() == 2 {
                // Pile boxes keep their layer: bottom ones at 0.4, top ones at 1.2.
                let idx: usize = name[1..].parse().unwrap();
                let want = if idx < 2 { BOX_HALF } else { 3.0 * BOX_HALF };
                assert!(
                    (p.y - want).abs() < 0.05,
                    "{name} y = {} (want {want})",
                    p.y
                );
            }
        }
    }

    #[test]
    fn piles_never_touch_each_other() {
        let mut scene = two_piles_with_wall();
        let left: Vec<_> = LEFT.iter().map(|n| scene.body(n).unwrap()).collect();
        let right: Vec<_> = RIGHT.iter().map(|n| scene.body(n).unwrap()).collect();
        for step in 0..200 {
            scene.before_step(step);
            scene.world.step();
            for pair in scene.world.narrow_phase.contact_pairs() {
                let b1 = scene.world.colliders[pair.collider1].parent().unwrap();
                let b2 = scene.world.colliders[pair.collider2].parent().unwrap();
                let crosses = (left.contains(&b1) && right.contains(&b2))
                    || (left.contains(&b2) && right.contains(&b1));
                assert!(!crosses, "step {step}: a left and a right body are paired");
            }
        }
    }
}
