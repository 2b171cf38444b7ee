//! The stability suite's scenes: small scenes built to make each of the paper's §7
//! speed-ups fail (a sleepy sphere left hanging in the air, Fig. 17; objects flying up
//! under fixation, Fig. 15). One file per scene, each saying what it is built against
//! and what it was measured to fail under. The laboratory (`rcg-lab`) pairs each
//! scene with its target switch, control run and reference, and measures the table.
//!
//! | scene | built against |
//! |---|---|
//! | [`hanging_sleeper`] | fixate |
//! | [`fixated_pile`] | fixate |
//! | [`face_to_face`] | reduce |
//! | [`tower`] | tweak |
//! | [`pyramid`] | tweak |
//! | [`bounce_on_sleepers`] | zero |
//! | [`seesaw`] | subgroup |
//! | [`slow_incline`] | sleepy |
//! | [`removed_support`] | stock, sleepy, fixate |
//! | [`platform_sleepers`] | stock, sleepy, fixate |
//! | [`jointed_sleeper`] | stock, sleepy, fixate |
//! | [`gravity_change`] | stock, sleepy |
//! | [`static_moved`] | stock, sleepy, fixate |
//! | [`slow_push`] | fixate |
//!
//! # Scripts find their bodies by tag
//! A [`crate::Script`] is a plain `fn(&mut PhysicsWorld, u64)`, so the scenes
//! whose scripts remove, move or retarget something tag it in `user_data` and look it
//! up by tag ([`tagged_body`], [`tagged_collider`]): O(bodies) per step, which is
//! nothing at these sizes. Every script computes what it sets from the step index
//! alone, so a replay from any step gives the same world. Rejected: a boxed closure
//! capturing the handles. It would change `Scene` for every scene and user (no longer
//! a plain value with a `fn` pointer), for the sake of five scripts.
//!

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};

pub mod bounce_on_sleepers;
pub mod face_to_face;
pub mod fixated_pile;
pub mod gravity_change;
pub mod hanging_sleeper;
pub mod jointed_sleeper;
pub mod platform_sleepers;
pub mod pyramid;
pub mod removed_support;
pub mod seesaw;
pub mod slow_incline;
pub mod slow_push;
pub mod static_moved;
pub mod tower;

/// A fixed ground slab whose top face is `y = 0`, `half` m across in x and z.
pub(crate) fn ground(world: &mut PhysicsWorld, half: Real) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
            ColliderBuilder::cuboid(half, 0.5, half),
        )
        .0
}

/// The body whose `user_data` is `tag` (the first in handle order). A [`Script`] gets
/// only the world, so scenes tag the bodies their scripts drive. O(bodies).
///
/// [`Script`]: crate::Script
pub fn tagged_body(world: &PhysicsWorld, tag: u128) -> Option<RigidBodyHandle> {
    world
        .bodies
        .iter()
        .find(|(_, b)| b.user_data == tag)
        .map(|(h, _)| h)
}

/// The collider whose `user_data` is `tag` (the first in handle order). O(colliders).
pub fn tagged_collider(world: &PhysicsWorld, tag: u128) -> Option<ColliderHandle> {
    world
        .colliders
        .iter()
        .find(|(_, c)| c.user_data == tag)
        .map(|(h, _)| h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn scripts_find_their_bodies_by_tag_and_replay_from_any_step() {
        let scene = platform_sleepers::platform_sleepers();
        assert_eq!(
            tagged_body(&scene.world, platform_sleepers::TAG_PLATFORM),
            scene.body("platform")
        );
        assert!(tagged_body(&scene.world, 0x1234).is_none());
        let shelf = static_moved::static_moved();
        assert!(tagged_collider(&shelf.world, static_moved::TAG_SHELF).is_some());
        assert!(tagged_collider(&shelf.world, 0x1234).is_none());
        // Scripts compute what they set from the step index: a run split around the
        // event equals a run in one go.
        for build in [
            platform_sleepers::platform_sleepers as fn() -> Scene,
            jointed_sleeper::jointed_sleeper,
            removed_support::removed_support,
            gravity_change::gravity_change,
            static_moved::static_moved,
            slow_push::slow_push,
        ] {
            let (mut a, mut b) = (build(), build());
            a.run_plain(0, 200);
            b.run_plain(0, 149);
            b.run_plain(149, 51);
            for (name, h) in &a.bodies {
                let hb = b.body(name).unwrap();
                match (a.world.bodies.get(*h), b.world.bodies.get(hb)) {
                    (Some(x), Some(y)) => {
                        assert_eq!(x.position(), y.position(), "{} {name}", a.name)
                    }
                    (x, y) => assert_eq!(x.is_some(), y.is_some(), "{} {name}", a.name),
                }
            }
        }
    }

    #[test]
    fn platform_and_hook_follow_their_schedules() {
        let dt = crate::DT;
        assert_eq!(
            platform_sleepers::platform_y_after(0, dt),
            platform_sleepers::PLATFORM_Y
        );
        let end = platform_sleepers::MOVE_AT + platform_sleepers::SINK_STEPS;
        let sunk = platform_sleepers::PLATFORM_Y - platform_sleepers::platform_y_after(end, dt);
        assert!((sunk - 0.8).abs() < 1e-5, "{sunk}");
        assert_eq!(
            platform_sleepers::platform_y_after(end + 100, dt),
            platform_sleepers::platform_y_after(end, dt)
        );
        let end = jointed_sleeper::MOVE_AT + jointed_sleeper::DRAG_STEPS;
        let dragged = jointed_sleeper::HOOK_X - jointed_sleeper::hook_x_after(end, dt);
        assert!((dragged - 1.0).abs() < 1e-5, "{dragged}");
    }
}
