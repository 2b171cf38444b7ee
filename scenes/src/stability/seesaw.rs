//! A seesaw: a lever whose far end carries a resting box, struck at its near end.
//!
//! A plank ([`PLANK_HALF`]) turns about a revolute joint at its centre, fixed
//! [`PIVOT_HEIGHT`] above the ground; its left end rests on a fixed stop, so the plank
//! lies level, and a light box rests on that end. A dense ball falls from
//! [`DROP_HEIGHT`] onto the right end after about 0.55 s, when plank and box have been
//! at rest for a while: the right end goes down, the left end flies up and throws the
//! box.
//!
//! Built against subgrouping (the paper's case: a sleepy body insulates, so the part
//! of the lever it rests on is solved as if held) and, in this crate, against
//! fixation: plank and box are held fixed while sleepy, and a lever turning about its
//! centre moves its ends fast but its centre not at all. Measured: subgrouping
//! changes nothing (in Rapier the solver couples the whole island whatever the groups
//! say, so it only changes which bodies are judged sleepy together); under fixation
//! the falling ball's reach releases plank and box before it lands, and they are not
//! held again while the ball still moves (the release's wave), so the box is thrown
//! as without fixation. Before waves the lever, sleepy again, was held with the box
//! on it and jammed (an unresponsive body).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RevoluteJointBuilder, RigidBodyBuilder};

use super::ground;
use crate::{new_world, Scene};

/// Half extents of the plank.
pub const PLANK_HALF: [Real; 3] = [2.0, 0.05, 0.4];
/// Height of the pivot (the plank's centre) above the ground, m.
pub const PIVOT_HEIGHT: Real = 0.8;
/// Half extent of the box on the left end.
pub const BOX_HALF: Real = 0.15;
/// The ball's radius and density (relative to the box's 1).
pub const BALL: (Real, Real) = (0.25, 2.0);
/// Height of the ball's lowest point above the plank's top, m.
pub const DROP_HEIGHT: Real = 1.0;

/// Builds the scene. Bodies: `"ground"`, `"pivot"`, `"stop"` (fixed), `"plank"`,
/// `"box"`, `"ball"`.
pub fn seesaw() -> Scene {
    let mut world = new_world();
    let g = ground(&mut world, 10.0);
    let [hx, hy, hz] = PLANK_HALF;
    let pivot = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(
        0.0,
        PIVOT_HEIGHT,
        0.0,
    )));
    // The stop under the left end: a post whose top is 1 mm below the plank.
    let stop_half_y = (PIVOT_HEIGHT - hy - 0.001) / 2.0;
    let (stop, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(-hx + 0.1, stop_half_y, 0.0)),
        ColliderBuilder::cuboid(0.1, stop_half_y, hz),
    );
    let (plank, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, PIVOT_HEIGHT, 0.0)),
        ColliderBuilder::cuboid(hx, hy, hz),
    );
    world.impulse_joints.insert(
        pivot,
        plank,
        RevoluteJointBuilder::new(Vector::Z).contacts_enabled(false),
        true,
    );
    let top = PIVOT_HEIGHT + hy;
    let (cube, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(
            -hx + BOX_HALF + 0.05,
            top + BOX_HALF + 0.001,
            0.0,
        )),
        ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF),
    );
    let (r, density) = BALL;
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(hx - 0.3, top + DROP_HEIGHT + r, 0.0)),
        ColliderBuilder::ball(r).density(density),
    );
    Scene {
        name: "seesaw",
        world,
        bodies: vec![
            ("ground", g),
            ("pivot", pivot),
            ("stop", stop),
            ("plank", plank),
            ("box", cube),
            ("ball", ball),
        ],
        script: None,
    }
}
