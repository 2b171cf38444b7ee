//! A pile of boxes that stock Rapier puts to sleep: the held-bodies benchmark's scene.
//!
//! `n` boxes of 0.5 m are dropped in columns on a fixed ground: a square footprint of
//! `ceil(sqrt(n / LAYERS))` columns 0.6 m apart, [`LAYERS`] boxes per column 0.55 m
//! apart, each dropped with a seeded horizontal jitter of ±[`JITTER`] m. The columns
//! land as stacks that touch their neighbours little, so the whole pile comes to rest
//! within about two seconds and Rapier's own sleep takes every box: the scene on which
//! "a held body costs what a sleeping body costs" can be measured against stock
//! Rapier's sleeping pile.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use crate::jitter::Jitter;
use crate::stability::ground;
use crate::{new_world, Scene};

/// Half extent of the boxes, m.
pub const BOX_HALF: Real = 0.25;
/// Boxes per column.
pub const LAYERS: usize = 5;
/// Horizontal drop jitter, m.
pub const JITTER: Real = 0.02;

/// Builds the pile. Bodies: `"ground"`; the boxes are all the other bodies, column by
/// column, bottom to top.
pub fn box_pile(n: usize, seed: u64) -> Scene {
    let mut world = new_world();
    let columns = n.div_ceil(LAYERS).max(1);
    let side = (columns as f64).sqrt().ceil() as usize;
    let spacing = 0.6;
    let half_width = side as Real * spacing / 2.0;
    let g = ground(&mut world, half_width + 2.0);
    let mut rng = Jitter::new(seed, JITTER);
    for i in 0..n {
        let (column, layer) = (i / LAYERS, i % LAYERS);
        let (ix, iz) = (column % side, column / side);
        let x = -half_width + spacing * (ix as Real + 0.5) + rng.next();
        let z = -half_width + spacing * (iz as Real + 0.5) + rng.next();
        let y = BOX_HALF + 0.01 + layer as Real * 0.55;
        world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, z)),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
        );
    }
    Scene {
        name: "box_pile",
        world,
        bodies: vec![("ground", g)],
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stock_rapier_puts_the_pile_to_sleep() {
        let mut scene = box_pile(100, 1);
        for _ in 0..500 {
            scene.world.step();
        }
        assert_eq!(scene.world.bodies.len(), 101);
        assert_eq!(scene.world.islands.num_active_bodies(), 0);
        for (_, rb) in scene.world.bodies.iter().filter(|(_, rb)| rb.is_dynamic()) {
            assert!(rb.translation().y > 0.0 && rb.translation().y < 3.0);
        }
    }
}
