//! A hit releases the held mass its momentum could set moving (paper §7, fixation):
//! the spread from everything one moving body reaches is one walk with the body's
//! whole budget, not a walk per reached body with a share of it, which overlapped
//! near the impact and released far less than the budget
//! (`docs/ARCHITECTURE.md`, "Releasing held bodies", *Group*).

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;

/// The floor's boxes: half extent, m, and boxes along a side.
const HALF: f32 = 0.2;
const SIDE: usize = 12;

/// A floor of 12 × 12 boxes settled and held, then a wide slab (1.2 m × 0.2 m ×
/// 1.2 m, density `density`) dropped on its middle at 2 m/s, from 5 cm over it.
/// Returns the boxes held when the slab came, the held boxes released within 10
/// steps, and the held mass the slab's momentum could set moving at
/// `release_speed`, in boxes.
fn slab_dropped(density: f32) -> (usize, usize, f32) {
    let (world, boxes) = common::build::floor_of_boxes(SIDE, HALF);
    let mut scene = common::plain_scene("floor_of_boxes", world);
    let config = SpeedUps::reliable_sleep();
    let release_speed = config.release_speed;
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(config)).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, 60);
    let s = layer.speedups().unwrap();
    let mut held: Vec<RigidBodyHandle> =
        boxes.iter().copied().filter(|&h| s.is_fixated(h)).collect();
    let count = held.len();
    let speed = 2.0;
    let slab = common::build::slab_over_floor(&mut scene.world, HALF, density, speed);
    for step in 60..70 {
        common::step_validated(&mut scene, &mut layer, step);
        let s = layer.speedups().unwrap();
        held.retain(|&h| s.is_fixated(h));
    }
    let box_mass = (2.0 * HALF).powi(3);
    let plain = scene.world.bodies[slab].mass() * speed / release_speed / box_mass;
    (count, count - held.len(), plain)
}

#[test]
fn a_wide_hit_releases_the_held_mass_its_momentum_can_move() {
    // The slab comes down on about 16 boxes at once, and its momentum could set about
    // 18 boxes' mass moving at `release_speed`: the spread goes past the boxes it hit,
    // as far as a few times that mass, and no further. A walk per hit box with a
    // sixteenth of the budget each (and a margin of 4) released 29.
    let (held, released, plain) = slab_dropped(1.0);
    eprintln!("held {held}, released {released}, momentum {plain:.1} boxes");
    assert_eq!(held, SIDE * SIDE, "the floor was held");
    assert!(
        released as f32 >= 2.0 * plain,
        "the spread spends the slab's budget on distinct bodies: {released} released \
         for {plain:.1} boxes' momentum"
    );
    assert!(
        released < held / 2,
        "the budget bounds the spread: {released} of {held} released"
    );
}
