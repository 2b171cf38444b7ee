//! Disturbance scenes: a settled pile, then something that should move part of it.
//!
//! Built to measure what fixation (held bodies, paper §7, "fixation") does to a pile
//! that is disturbed after it came to rest: a held body is a Rapier fixed body, so a
//! pile of held bodies is a wall unless the layer releases them in time (Erleben
//! 2004, §5 on waking sleepy groups). Each scene drops `boxes` boxes (half size
//! [`BOX_HALF`], friction [`FRICTION`]) in seed-jittered layers into a walled bin,
//! lets them settle for `at` steps, then disturbs the pile at step `at`:
//!
//! | scene | disturbance |
//! |---|---|
//! | [`thrown_ball`](thrown_ball::thrown_ball) | a heavy ball thrown in over a wall |
//! | [`support_removed`](support_removed::support_removed) | a floor segment removed |
//! | [`paddle`](paddle::paddle) | a kinematic paddle sweeping through |
//!
//! A fourth, [`diku_throw`](diku_throw::diku_throw), disturbs the DIKU scene instead
//! ([`mod@crate::diku`]: spheres settled on an inclined plane, not boxes in a bin): a
//! heavy sphere thrown into its pile late in the run; its `boxes` are spheres and its
//! defaults are its own ([`diku_throw::params`]). A fifth, [`bin_hit`](bin_hit::bin_hit),
//! hits the held-bodies benchmark's bin of mixed balls and boxes ([`crate::mixed_pile`])
//! with a heavy ball mid-run; its `boxes` count balls and boxes, its defaults are its
//! own ([`bin_hit::params`]).
//!
//! A [`Disturbance`] is a [`Scene`] plus its pile, its disturbance step and what to do
//! then; the runner calls [`Disturbance::before_step`] before every step (not the
//! scene's script: the disturbance step is a parameter, which a `fn` script cannot
//! capture). Building is O(boxes); the same `(boxes, seed)` gives the same world.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle};

use crate::jitter::Jitter;
use crate::Scene;

pub mod bin_hit;
pub mod diku_throw;
pub mod paddle;
pub mod support_removed;
pub mod thrown_ball;

pub use bin_hit::bin_hit;
pub use diku_throw::diku_throw;
pub use paddle::paddle;
pub use support_removed::support_removed;
pub use thrown_ball::thrown_ball;

/// Half extent of the pile's boxes, m.
pub const BOX_HALF: Real = 0.2;
/// Friction coefficient of the boxes.
pub const FRICTION: Real = 0.7;
/// Half width of the bin's inside (a square), m: the bin is 5 m across.
pub const BIN_HALF: Real = 2.5;
/// Height of the bin's walls above the floor, m.
pub const WALL_HEIGHT: Real = 2.0;
/// Horizontal spacing of the drop grid, m: boxes of 0.4 m, tilted by up to [`TILT`],
/// start apart.
pub const DROP_SPACING: Real = 0.65;
/// Vertical spacing of the drop layers, m.
pub const LAYER_SPACING: Real = 0.65;
/// Horizontal drop jitter, m.
pub const JITTER: Real = 0.03;
/// Rotation jitter about each axis, rad: enough that boxes tumble into a pile rather
/// than stack in columns.
pub const TILT: Real = 0.2;

/// Common parameters of the disturbance scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DisturbParams {
    /// Boxes dropped into the bin (default 250); spheres dropped on the plane in
    /// [`diku_throw`](diku_throw::diku_throw); balls and boxes dropped into the bin of
    /// [`bin_hit`](bin_hit::bin_hit).
    pub boxes: usize,
    /// Seed of the drop jitter (default 0).
    pub seed: u64,
    /// The step before which the pile is disturbed (default 300: 3 s of settling).
    pub at: u64,
    /// Steps run after the disturbance (default 200: 2 s).
    pub after: u64,
}

impl Default for DisturbParams {
    fn default() -> Self {
        DisturbParams {
            boxes: 250,
            seed: 0,
            at: 300,
            after: 200,
        }
    }
}

/// What happens at the disturbance step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Insert a ball (radius, density) at `start` with velocity `velocity`, CCD on.
    Throw {
        /// Ball radius, m.
        radius: Real,
        /// Ball density, kg/m³ (the boxes have 1).
        density: Real,
        /// Where the ball appears.
        start: Vector,
        /// Its initial velocity, m/s.
        velocity: Vector,
    },
    /// Remove this fixed body (and its colliders).
    Remove(RigidBodyHandle),
    /// Move this kinematic body from `start` at `velocity` for `duration` s, then stop.
    Sweep {
        /// The kinematic body.
        body: RigidBodyHandle,
        /// Its position at the disturbance step.
        start: Vector,
        /// Its velocity, m/s.
        velocity: Vector,
        /// How long it moves, s.
        duration: Real,
    },
}

impl Action {
    /// For [`Action::Throw`]: inserts its ball into `world` (dynamic, CCD on, friction
    /// [`FRICTION`]) and returns it; `None` for the other actions. O(1).
    pub fn throw_into(&self, world: &mut PhysicsWorld) -> Option<RigidBodyHandle> {
        let Action::Throw {
            radius,
            density,
            start,
            velocity,
        } = *self
        else {
            return None;
        };
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(start)
                .linvel(velocity)
                .ccd_enabled(true),
            ColliderBuilder::ball(radius)
                .density(density)
                .friction(FRICTION),
        );
        Some(h)
    }
}

/// A disturbance scene: the world, the pile, and what happens at step `at`.
pub struct Disturbance {
    /// The scene (its `script` is `None`; see [`Disturbance::before_step`]).
    pub scene: Scene,
    /// The pile's boxes, in insertion order: the bodies whose displacement counts.
    pub pile: Vec<RigidBodyHandle>,
    /// The step before which the disturbance happens.
    pub at: u64,
    /// Steps in all (settling, then the steps after the disturbance).
    pub steps: u64,
    /// The thrown body, once thrown.
    pub projectile: Option<RigidBodyHandle>,
    /// What happens at `at`.
    pub action: Action,
}

impl Disturbance {
    /// The disturbance of a scene built as a plain one, renamed `name`: its dynamic
    /// bodies, in insertion order, are the pile, and `action` happens before step
    /// `p.at`. O(bodies).
    fn of_plain_scene(
        mut scene: Scene,
        name: &'static str,
        p: &DisturbParams,
        action: Action,
    ) -> Disturbance {
        scene.name = name;
        let pile = scene.dynamic_bodies();
        Disturbance {
            scene,
            pile,
            at: p.at,
            steps: p.at + p.after,
            projectile: None,
            action,
        }
    }

    /// Applies the disturbance when `step == at` and drives a sweeping body from then
    /// on. Call before each step with the step index about to run. O(1).
    pub fn before_step(&mut self, step: u64) {
        let world = &mut self.scene.world;
        match self.action {
            Action::Throw { .. } if step == self.at => {
                self.projectile = self.action.throw_into(world);
            }
            Action::Remove(h) if step == self.at => {
                world.remove_body(h);
            }
            Action::Sweep {
                body,
                start,
                velocity,
                duration,
            } if step >= self.at => {
                let dt = world.integration_parameters.dt;
                let t = ((step + 1 - self.at) as Real * dt).min(duration);
                if let Some(b) = world.bodies.get_mut(body) {
                    b.set_next_kinematic_translation(start + velocity * t);
                }
            }
            _ => {}
        }
    }

    /// Divides the time step by `factor` and multiplies the step counts by it: the same
    /// simulated times, the disturbance at the same time (a refinement). Errors on 0.
    pub fn refine_time_step(&mut self, factor: u64) -> Result<(), String> {
        if factor == 0 {
            return Err("a time-step refinement factor must be at least 1".into());
        }
        self.scene.world.integration_parameters.dt /= factor as Real;
        self.at = self.at.saturating_mul(factor);
        self.steps = self.steps.saturating_mul(factor);
        Ok(())
    }

    /// Runs the disturbance and the world's step `n` times from step `first`, with
    /// Rapier alone (no layer): for tests.
    pub fn run_plain(&mut self, first: u64, n: u64) {
        for step in first..first.saturating_add(n) {
            self.before_step(step);
            self.scene.world.step();
        }
    }
}

/// A fixed wall slab from `y_low` to [`WALL_HEIGHT`] along each side of the bin, outside
/// its inside `[-BIN_HALF, BIN_HALF]²`. All four on one fixed body.
pub(crate) fn walls(world: &mut PhysicsWorld, y_low: Real) -> RigidBodyHandle {
    let t = 0.25;
    let hy = (WALL_HEIGHT - y_low) / 2.0;
    let cy = (WALL_HEIGHT + y_low) / 2.0;
    let h = world.insert_body(RigidBodyBuilder::fixed());
    let long = BIN_HALF + 2.0 * t;
    for (c, half) in [
        (
            Vector::new(-BIN_HALF - t, cy, 0.0),
            Vector::new(t, hy, long),
        ),
        (Vector::new(BIN_HALF + t, cy, 0.0), Vector::new(t, hy, long)),
        (
            Vector::new(0.0, cy, -BIN_HALF - t),
            Vector::new(long, hy, t),
        ),
        (Vector::new(0.0, cy, BIN_HALF + t), Vector::new(long, hy, t)),
    ] {
        world.insert_collider(
            ColliderBuilder::cuboid(half.x, half.y, half.z).translation(c),
            Some(h),
        );
    }
    h
}

/// Drops `n` boxes in layers over the floor `y = 0` between `x_min` and
/// [`BIN_HALF`] (and across the whole bin in `z`): a grid [`DROP_SPACING`] apart per
/// layer, layers [`LAYER_SPACING`] apart, odd layers offset by a quarter spacing, each
/// box jittered by ±[`JITTER`] m and rotated by up to ±[`TILT`] rad about each axis.
/// Returns the boxes in insertion order. O(n).
pub(crate) fn drop_boxes(
    world: &mut PhysicsWorld,
    n: usize,
    x_min: Real,
    seed: u64,
) -> Vec<RigidBodyHandle> {
    let margin = BOX_HALF + JITTER + DROP_SPACING / 4.0 + 0.01;
    let count = |lo: Real, hi: Real| (((hi - lo - 2.0 * margin) / DROP_SPACING) as usize) + 1;
    let (nx, nz) = (count(x_min, BIN_HALF), count(-BIN_HALF, BIN_HALF));
    let per_layer = (nx * nz).max(1);
    let mut pos = Jitter::new(seed, JITTER);
    let mut rot = Jitter::new(seed ^ 0x524F_5441_5445, TILT);
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (layer, k) = (i / per_layer, i % per_layer);
        let (ix, iz) = (k % nx, k / nx);
        let offset = if layer % 2 == 1 {
            DROP_SPACING / 4.0
        } else {
            0.0
        };
        let x = x_min + margin + ix as Real * DROP_SPACING + offset + pos.next();
        let z = -BIN_HALF + margin + iz as Real * DROP_SPACING + offset + pos.next();
        let y = BOX_HALF * 1.8 + 0.05 + layer as Real * LAYER_SPACING;
        let angles = Vector::new(rot.next(), rot.next(), rot.next());
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, y, z))
                .rotation(angles),
            ColliderBuilder::cuboid(BOX_HALF, BOX_HALF, BOX_HALF).friction(FRICTION),
        );
        out.push(h);
    }
    out
}

/// Test check: the disturbance's pile is the plain scene's dynamic bodies, where the
/// plain scene has them.
#[cfg(test)]
fn assert_pile_of(d: &Disturbance, plain: &Scene) {
    assert_eq!(d.pile, plain.dynamic_bodies());
    for &h in &d.pile {
        assert_eq!(
            d.scene.world.bodies[h].translation(),
            plain.world.bodies[h].translation()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pile's positions after building.
    fn snapshot(d: &Disturbance) -> Vec<(Vector, rapier3d::math::Rotation)> {
        d.pile
            .iter()
            .map(|&h| {
                let b = &d.scene.world.bodies[h];
                (b.translation(), *b.rotation())
            })
            .collect()
    }

    #[test]
    fn builds_are_deterministic_seeded_and_inside_the_bin() {
        let p = DisturbParams {
            boxes: 120,
            seed: 3,
            ..Default::default()
        };
        for build in [thrown_ball, support_removed, paddle] {
            let (a, b) = (build(&p), build(&p));
            assert_eq!(a.pile.len(), 120);
            assert_eq!(snapshot(&a), snapshot(&b));
            let c = build(&DisturbParams { seed: 4, ..p });
            assert_ne!(snapshot(&a), snapshot(&c));
            assert_eq!((a.at, a.steps), (p.at, p.at + p.after));
            for (t, _) in snapshot(&a) {
                let reach = BIN_HALF - BOX_HALF * 0.9;
                assert!(
                    t.x.abs() < reach && t.z.abs() < reach && t.y > BOX_HALF,
                    "{t:?}"
                );
            }
        }
    }

    #[test]
    fn refinement_keeps_the_times() {
        let mut d = thrown_ball(&DisturbParams {
            boxes: 10,
            ..Default::default()
        });
        let dt = d.scene.world.integration_parameters.dt;
        d.refine_time_step(2).unwrap();
        assert_eq!((d.at, d.steps), (600, 1000));
        assert_eq!(d.scene.world.integration_parameters.dt, dt / 2.0);
        assert!(d.refine_time_step(0).is_err());
    }
}
