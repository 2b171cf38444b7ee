//! The bin of mixed balls and boxes hit mid-run by a heavy ball (the pile
//! the held-bodies benchmark and the peers' comparison run).
//!
//! The pile is [`mixed_pile`] itself (`benches/held.rs`'s `mixed` scene): by default
//! [`BODIES`] bodies, balls (radius 0.5 m) and cubes (half extent 0.4 m)
//! alternating, density 1, Rapier's default friction, dropped from a jittered grid
//! into a fixed open-topped bin ([`inner_half_width`], [`wall_height`]) and settling
//! for [`AT`] steps (10 s). Before step [`DisturbParams::at`] a ball of radius
//! [`RADIUS`] and density [`DENSITY`] (10× the pile's; CCD on) appears over the `-x`
//! wall, on the bin's centre line, and flies along `+x` at [`SPEED`], [`ANGLE_DEG`]°
//! below the horizontal, down into the pile; the run goes on for [`AFTER`] steps.
//! Without sleep it ploughs through the pile's middle and pushes a few hundred
//! bodies; a pile of held bodies (fixation, paper §7) stops it short unless the
//! layer releases what it hits in time (Erleben 2004, §5).
//!
//! Throw geometry, for any pile size: the ball's centre starts 0.1 m outside the
//! bin's inner `-x` face and its bottom [`CLEARANCE`] over the wall's top; its path
//! clears the wall's inner top edge. At 1,000 bodies the bin is 16 m across, its
//! walls 8.5 m high and the pile about 3.5 m deep: the ball comes down into the
//! pile about a third of the way across.

use rapier3d::math::{Real, Vector};

use super::{Action, DisturbParams, Disturbance};
use crate::pile::{inner_half_width, mixed_pile, wall_height};

/// Bodies of the default run: the held-bodies benchmark's 1,000-body bin.
pub const BODIES: usize = 1000;
/// The default disturbance step: 10 s of falling and settling.
pub const AT: u64 = 1000;
/// The default steps after the disturbance: 6 s.
pub const AFTER: u64 = 600;
/// Radius of the thrown ball, m (the pile's balls have 0.5 too).
pub const RADIUS: Real = 0.5;
/// Density of the thrown ball: 10× the pile's (Rapier's default, 1).
pub const DENSITY: Real = 10.0;
/// Speed of the throw, m/s.
pub const SPEED: Real = 10.0;
/// Angle of the throw below the horizontal, degrees.
pub const ANGLE_DEG: Real = 30.0;
/// Gap between the ball's bottom and the wall's top at the throw, m: enough that its
/// path clears the wall's inner top edge.
pub const CLEARANCE: Real = 0.5;

/// The default parameters: [`BODIES`] bodies, seed 0, [`AT`], [`AFTER`].
pub const fn params() -> DisturbParams {
    DisturbParams {
        boxes: BODIES,
        seed: 0,
        at: AT,
        after: AFTER,
    }
}

/// Where the ball appears in the bin of `bodies` bodies, and its velocity.
pub fn throw(bodies: usize) -> (Vector, Vector) {
    let start = Vector::new(
        -inner_half_width(bodies) - 0.1,
        wall_height(bodies) + RADIUS + CLEARANCE,
        0.0,
    );
    let a = ANGLE_DEG.to_radians();
    (start, Vector::new(a.cos(), -a.sin(), 0.0) * SPEED)
}

/// The disturbance of the bin of `bodies` bodies: the throw above (a ball of
/// [`RADIUS`] and [`DENSITY`], CCD on). The held-bodies benchmark's `--hit` throws
/// the same ball.
pub fn action(bodies: usize) -> Action {
    let (start, velocity) = throw(bodies);
    Action::Throw {
        radius: RADIUS,
        density: DENSITY,
        start,
        velocity,
    }
}

/// Builds the scene: [`mixed_pile`]`(p.boxes, p.seed)` (`p.boxes` counts balls and
/// boxes), named `"bin_hit"`. Bodies: `"container"` (the floor and the four walls);
/// the pile is every other body, in insertion order; the ball is inserted at the
/// disturbance step ([`Disturbance::projectile`]). O(bodies).
pub fn bin_hit(p: &DisturbParams) -> Disturbance {
    Disturbance::of_plain_scene(mixed_pile(p.boxes, p.seed), "bin_hit", p, action(p.boxes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_the_mixed_bin_with_its_bodies_as_the_pile() {
        let p = DisturbParams {
            boxes: 200,
            seed: 3,
            ..params()
        };
        let d = bin_hit(&p);
        let plain = mixed_pile(200, 3);
        assert_eq!(d.pile.len(), 200);
        crate::disturb::assert_pile_of(&d, &plain);
        assert_eq!((d.at, d.steps), (AT, AT + AFTER));
        assert_eq!(d.scene.name, "bin_hit");
        assert!(d.scene.body("container").is_some());
    }

    #[test]
    fn the_ball_flies_over_the_wall_into_the_bin() {
        // An empty bin of the 1,000-body size: the ball clears the wall, lands inside
        // and stays inside.
        let p = DisturbParams {
            boxes: 1000,
            seed: 0,
            at: 0,
            after: 300,
        };
        let mut d = bin_hit(&p);
        for &h in &d.pile {
            d.scene.world.remove_body(h);
        }
        let (h, top) = (inner_half_width(1000), wall_height(1000));
        for step in 0..d.steps {
            d.run_plain(step, 1);
            let t = d.scene.world.bodies[d.projectile.unwrap()].translation();
            // Over the wall's top until it is inside the bin.
            assert!(
                t.x > -h + RADIUS || t.y > top + RADIUS,
                "step {step}: {t:?}"
            );
        }
        let b = &d.scene.world.bodies[d.projectile.unwrap()];
        let t = b.translation();
        assert!(t.x.abs() < h && t.z.abs() < h && t.y > 0.0, "{t:?}");
        assert!(b.is_ccd_enabled());
        let mass = b.mass();
        let expected = DENSITY * 4.0 / 3.0 * std::f32::consts::PI * RADIUS.powi(3);
        assert!((mass - expected).abs() < 1e-3 * expected, "{mass}");
    }
}
