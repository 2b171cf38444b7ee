//! A settled box pile whose floor segment is taken away.
//!
//! The bin's floor is [`SEGMENTS`] fixed strips across `z`, each 1 m wide along `x`;
//! a lower ground lies [`DROP`] m below, and the walls reach down to it. Before step
//! [`DisturbParams::at`] the middle strip is removed: the boxes on it fall into the
//! trench and the pile beside it slides after them. Rapier wakes what touched a
//! removed collider; a held body is a fixed body, so the layer must release the pile
//! itself (paper §7, fixation; the hanging sleeper of Erleben 2004, Fig. 17, on a
//! pile's scale).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder, RigidBodyHandle};

use super::{drop_boxes, walls, Action, DisturbParams, Disturbance, BIN_HALF};
use crate::{new_world, Scene};

/// Floor strips (1 m wide each along `x`).
pub const SEGMENTS: usize = 5;
/// The strip removed (the middle one).
pub const REMOVED: usize = SEGMENTS / 2;
/// Depth of the lower ground under the floor, m.
pub const DROP: Real = 1.0;

/// Builds the scene. Bodies: `"ground"` (the lower ground), `"walls"`, `"segment0"`
/// .. `"segment4"` (fixed; the middle one is removed at the disturbance step).
pub fn support_removed(p: &DisturbParams) -> Disturbance {
    const NAMES: [&str; SEGMENTS] = ["segment0", "segment1", "segment2", "segment3", "segment4"];
    let mut world = new_world();
    let (g, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -DROP - 0.5, 0.0)),
        ColliderBuilder::cuboid(BIN_HALF + 1.0, 0.5, BIN_HALF + 1.0),
    );
    let w = walls(&mut world, -DROP);
    let mut bodies = vec![("ground", g), ("walls", w)];
    let width = 2.0 * BIN_HALF / SEGMENTS as Real;
    let mut segments: Vec<RigidBodyHandle> = Vec::with_capacity(SEGMENTS);
    for (i, name) in NAMES.into_iter().enumerate() {
        let x = -BIN_HALF + width * (i as Real + 0.5);
        let (h, _) = world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(x, -0.25, 0.0)),
            ColliderBuilder::cuboid(width / 2.0, 0.25, BIN_HALF),
        );
        bodies.push((name, h));
        segments.push(h);
    }
    let pile = drop_boxes(&mut world, p.boxes, -BIN_HALF, p.seed);
    Disturbance {
        scene: Scene {
            name: "support_removed",
            world,
            bodies,
            script: None,
        },
        pile,
        at: p.at,
        steps: p.at + p.after,
        projectile: None,
        action: Action::Remove(segments[REMOVED]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_on_the_removed_segment_falls_to_the_lower_ground() {
        // One box, dropped at the bin's `-x` corner: not over the middle strip. So put
        // it there by hand.
        let mut d = support_removed(&DisturbParams {
            boxes: 1,
            at: 50,
            after: 80,
            seed: 0,
        });
        let h = d.pile[0];
        d.scene.world.bodies[h].set_translation(Vector::new(0.0, 0.5, 0.0), true);
        d.run_plain(0, d.at);
        assert!(d.scene.world.bodies[h].translation().y > 0.0);
        d.run_plain(d.at, d.steps - d.at);
        let y = d.scene.world.bodies[h].translation().y;
        assert!(y < -DROP + 0.3 && y > -DROP, "{y}");
        assert!(d
            .scene
            .body("segment2")
            .is_some_and(|s| d.scene.world.bodies.get(s).is_none()));
    }
}
