//! The DIKU scene (paper §7, Fig. 12) with a heavy sphere thrown into its settled pile.
//!
//! [`DisturbParams::boxes`] spheres (here spheres, not boxes: default [`SPHERES`], the
//! DIKU run's 120) fall onto the inclined plane of [`mod@crate::diku`], roll down across
//! the engraved letters and settle, most of them in a pile against the lower rim, a
//! few in the grooves; the scene, its seeds and its sizes are the DIKU run's. Late in
//! the run, before step [`DisturbParams::at`] (default [`AT`]: after the DIKU run's
//! 10 s, when the pile has settled and the speed-ups hold most of it), a heavy sphere
//! of radius [`RADIUS`] and density [`DENSITY`] (CCD on) appears over the lower rim
//! above the middle of the plane and flies at [`SPEED`] up the slope and down into
//! the pile; the run goes on for [`AFTER`] steps. Without sleep it lands in the pile's
//! front rows and pushes the spheres around the impact up the slope and sideways
//! along the rim; a pile of held bodies (fixation, paper §7) stops it like a wall
//! unless the layer releases what it hits in time (Erleben 2004, §5).
//!
//! Throw geometry, in the plane frame of [`mod@crate::diku`] (`x` up the slope from the
//! lower rim's inner face, `y` the plane's normal, `z` across): the sphere starts at
//! `x = -0.5` (over the rim wall, whose top is `y = 3`), its bottom [`CLEARANCE`]
//! over the rim's top, at `z = 0`, with velocity [`DIRECTION`] scaled to [`SPEED`]:
//! 45° below the plane, 25° below the horizontal in the world. It passes the rim's
//! inner top edge about 0.4 m clear and comes down at about 12 m/s into the pile's
//! middle rows, about 2.3 m up the slope from the rim. Chosen so that without sleep
//! it clearly moves the pile: it displaces several times as many spheres as the
//! pile's own creep over the same 2 s (the figures are in `docs/disturb.md`).

use rapier3d::math::{Real, Vector};

use super::{Action, DisturbParams, Disturbance};
use crate::diku::{diku, plane_pose, DikuParams, RIM_HEIGHT};

/// Spheres of the default run (the DIKU run's default).
pub const SPHERES: usize = 120;
/// The default disturbance step: the DIKU run's 10 s of falling, rolling and
/// settling.
pub const AT: u64 = 1000;
/// The default steps after the disturbance: 2 s.
pub const AFTER: u64 = 200;
/// Radius of the thrown sphere, m (the pile's spheres have 0.5).
pub const RADIUS: Real = 0.8;
/// Density of the thrown sphere (the pile's spheres have 1): its mass is about 33
/// pile spheres'.
pub const DENSITY: Real = 8.0;
/// Speed of the throw, m/s.
pub const SPEED: Real = 10.0;
/// Direction of the throw in the plane frame: up the slope and into the plane, 45°
/// below the plane.
pub const DIRECTION: Vector = Vector::new(1.0, -1.0, 0.0);
/// Gap between the thrown sphere's bottom and the rim's top at the throw, m: enough
/// that its path clears the rim's inner top edge.
pub const CLEARANCE: Real = 1.7;

/// The default parameters: [`SPHERES`] spheres, seed 0, [`AT`], [`AFTER`].
pub const fn params() -> DisturbParams {
    DisturbParams {
        boxes: SPHERES,
        seed: 0,
        at: AT,
        after: AFTER,
    }
}

/// The DIKU parameters of a disturbance run: `p.boxes` spheres, seed `p.seed`, the
/// DIKU scene's radius and incline.
pub fn diku_params(p: &DisturbParams) -> DikuParams {
    DikuParams {
        spheres: p.boxes,
        seed: p.seed,
        ..Default::default()
    }
}

/// Where the thrown sphere appears and its velocity, in world coordinates.
pub fn throw(p: &DisturbParams) -> (Vector, Vector) {
    let pose = plane_pose(&diku_params(p));
    let start = Vector::new(-0.5, RIM_HEIGHT + CLEARANCE + RADIUS, 0.0);
    let velocity = DIRECTION.normalize() * SPEED;
    (pose.transform_point(start), pose.transform_vector(velocity))
}

/// Builds the scene. Bodies: `"plane"` (fixed: the surface and the rim); the pile is
/// every sphere, in insertion order; the thrown sphere is inserted at the
/// disturbance step ([`Disturbance::projectile`]). O(spheres).
pub fn diku_throw(p: &DisturbParams) -> Disturbance {
    let (start, velocity) = throw(p);
    let action = Action::Throw {
        radius: RADIUS,
        density: DENSITY,
        start,
        velocity,
    };
    Disturbance::of_plain_scene(diku(&diku_params(p)), "diku_throw", p, action)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diku::{is_on_plane, to_plane_frame};

    #[test]
    fn the_sphere_flies_over_the_rim_and_lands_where_the_pile_lies() {
        // No pile: the sphere alone clears the rim wall and first touches the plane in
        // the run-out, where the pile collects.
        let p = DisturbParams {
            boxes: 0,
            seed: 0,
            at: 0,
            after: 200,
        };
        let dp = diku_params(&p);
        let mut d = diku_throw(&p);
        assert!(d.pile.is_empty());
        let mut landed = None;
        for step in 0..d.steps {
            d.run_plain(step, 1);
            let t = d.scene.world.bodies[d.projectile.unwrap()].translation();
            let q = to_plane_frame(&dp, t);
            // Over the rim's top until it is over the plane.
            assert!(q.x > 0.0 || q.y > RIM_HEIGHT + RADIUS, "step {step}: {q:?}");
            if landed.is_none() && q.y < RADIUS + 0.05 {
                landed = Some(q.x);
            }
        }
        let t = d.scene.world.bodies[d.projectile.unwrap()].translation();
        assert!(is_on_plane(&dp, t), "{t:?}");
        let x = landed.expect("never landed");
        assert!(x > 1.0 && x < crate::diku::RUNOUT, "landed at x = {x}");
        assert!(d.scene.world.bodies[d.projectile.unwrap()].is_ccd_enabled());
    }

    #[test]
    fn builds_the_diku_scene_with_its_spheres_as_the_pile() {
        let p = DisturbParams {
            seed: 3,
            ..params()
        };
        let d = diku_throw(&p);
        let plain = diku(&diku_params(&p));
        assert_eq!(d.pile.len(), SPHERES);
        crate::disturb::assert_pile_of(&d, &plain);
        assert_eq!((d.at, d.steps), (AT, AT + AFTER));
        assert_eq!(d.scene.name, "diku_throw");
    }
}
