//! Small deterministic scenes shared by the examples, the tests, the benchmarks and
//! the laboratory of `rapier-contact-graph`.
//!
//! This crate depends on `rapier3d` alone: a scene is a Rapier world and the names of
//! its interesting bodies, nothing of the contact graph. So the plugin's own unit
//! tests can build scenes without a dependency cycle, and the scenes stay outside the
//! library a Rapier user links (Box2D keeps its samples' scenes in `shared/` the same
//! way). Not published.
//!
//! Like Box2D's "benchmark scenes shared by samples and benchmarks", every scene is
//! built in exactly one place so that an example, a test and a benchmark that say
//! "ball on box" all mean the same bodies at the same places. One concept per file.
//!
//! Every scene uses stock Rapier with `dt = 0.01` ([`DT`]) and gravity `(0, -9.81, 0)`
//! ([`GRAVITY_Y`]); all other parameters are Rapier's defaults. No scene sets
//! `ActiveHooks` or `ActiveEvents` flags or touches `can_sleep`, so a layer observing
//! the world sees exactly what an unmodified Rapier program would produce. Building a
//! scene twice gives bit-identical worlds: the only randomness is the seeded generator
//! of [`sphere_pile`], and no hash-map order is involved.
//!
//! [`disturb`] holds the disturbance scenes: a settled box pile, then a ball thrown
//! in, a floor segment removed or a paddle swept through, at a given step.
//!
//! [`stability`] holds the stability suite's scenes: built to make the
//! speed-ups fail, each with what it is built against and what it was measured to fail
//! under. One of them starts with gravity off ([`stability::gravity_change`]), and
//! their scripts find the bodies they drive by `user_data` tags.

use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle};

pub mod ball_on_box;
pub mod box_pile;
pub mod diku;
pub mod disturb;
mod jitter;
pub mod kinematic_platform;
pub mod pendulum;
pub mod pile;
pub mod sphere_stack;
pub mod stability;
pub mod toppling_stack;
pub mod trigger_ledge;
pub mod two_piles;

pub use ball_on_box::ball_on_box;
pub use box_pile::box_pile;
pub use diku::{diku, DikuParams};
pub use kinematic_platform::kinematic_platform;
pub use pendulum::pendulum_wall;
pub use pile::{mixed_pile, sphere_pile};
pub use sphere_stack::sphere_stack;
pub use toppling_stack::toppling_stack;
pub use trigger_ledge::trigger_ledge;
pub use two_piles::two_piles_with_wall;

/// The time step every scene sets in `integration_parameters.dt`.
pub const DT: rapier3d::math::Real = 0.01;

/// The vertical gravity component every scene uses (gravity is `(0, GRAVITY_Y, 0)`).
pub const GRAVITY_Y: rapier3d::math::Real = -9.81;

/// Sets a world up as the paper's plain solver (brute force at 4 iterations, the
/// reference at 16): `iterations` solver iterations, no contact recycling, no warm
/// start, and no sleep for the bodies it has now. Shared by the laboratory's runs and
/// the benchmarks, so that "brute force" is one configuration everywhere.
pub fn plain_solver(world: &mut PhysicsWorld, iterations: usize) {
    let p = &mut world.integration_parameters;
    p.num_solver_iterations = iterations;
    p.contact_recycling = false;
    p.warmstart_coefficient = 0.0;
    for (_, rb) in world.bodies.iter_mut() {
        let a = rb.activation_mut();
        a.normalized_linear_threshold = -1.0;
        a.angular_threshold = -1.0;
    }
}

/// A per-step script (drives kinematic bodies). Called before each step with the step
/// index about to run (0-based).
pub type Script = fn(&mut PhysicsWorld, u64);

/// A ready-to-step physics world plus the names of its interesting bodies.
pub struct Scene {
    /// Short stable name of the scene (e.g. `"ball_on_box"`), for reports and snapshots.
    pub name: &'static str,
    /// The Rapier world, with `dt` and gravity already set.
    pub world: PhysicsWorld,
    /// Named bodies, in insertion order (names unique), for tests and snapshots.
    pub bodies: Vec<(&'static str, RigidBodyHandle)>,
    /// Optional per-step script; run it with [`Scene::before_step`] before each step.
    pub script: Option<Script>,
}

impl Scene {
    /// The handle of the body called `name`, if the scene has one.
    pub fn body(&self, name: &str) -> Option<RigidBodyHandle> {
        self.bodies
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, h)| h)
    }

    /// The scene's dynamic bodies in handle order: the bodies a measurement follows.
    /// O(bodies).
    pub fn dynamic_bodies(&self) -> Vec<RigidBodyHandle> {
        let mut v: Vec<RigidBodyHandle> = self
            .world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        v.sort_by_key(|h| h.into_raw_parts());
        v
    }

    /// Runs the script (if any) for `step` — call before stepping.
    pub fn before_step(&mut self, step: u64) {
        if let Some(script) = self.script {
            script(&mut self.world, step);
        }
    }

    /// Convenience: before_step + world.step(), `n` times, starting at step index `first`.
    pub fn run_plain(&mut self, first: u64, n: u64) {
        for step in first..first.saturating_add(n) {
            self.before_step(step);
            self.world.step();
        }
    }
}

/// A world with the settings shared by every scene: default Rapier parameters,
/// except `dt = DT` and gravity `(0, GRAVITY_Y, 0)`.
pub(crate) fn new_world() -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = rapier3d::math::Vector::new(0.0, GRAVITY_Y, 0.0);
    world.integration_parameters.dt = DT;
    world
}

/// Helpers shared by the scenes' unit tests.
#[cfg(test)]
pub(crate) mod test_util {
    use super::Scene;
    use rapier3d::prelude::ColliderHandle;

    /// The first collider of a named body.
    pub(crate) fn collider(scene: &Scene, name: &str) -> ColliderHandle {
        scene.world.bodies[scene.body(name).unwrap()].colliders()[0]
    }

    /// Whether two colliders have an active contact.
    pub(crate) fn touching(scene: &Scene, a: ColliderHandle, b: ColliderHandle) -> bool {
        scene
            .world
            .contact_pair(a, b)
            .is_some_and(|p| p.has_any_active_contact())
    }
}
