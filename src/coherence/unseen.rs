//! Steps the layer did not see: a Rapier step taken without the layer's event handler
//! (the user's own `world.step()` between two `ContactLayer::step`s, or a second layer
//! stepping the same world). Touching tracking learns what changed from the collision
//! events of the steps it sees, so after such a step its graph would be stale; the
//! layer notices it at its next pre-step and reads the world in full once, then goes
//! back to the events (see `docs/ARCHITECTURE.md`, "Steps the layer did not see").
//!
//! Rapier keeps no public step counter, so the witness is what every step changes in
//! the bodies it simulates: a few awake bodies' sleep timers (a step adds `dt` to a
//! body that moves slowly; no user call makes it grow, but `RigidBody::sleep`) and
//! poses (a step moves a body that moves fast, which a user's teleport also does, so a
//! pose counts only when every sampled body moved), and the size of the active set
//! when no sampled body is left. O([`SAMPLE`]) per step.

use rapier3d::prelude::{IslandManager, RigidBodyHandle, RigidBodySet};

use super::Coherence;
use crate::util::rapier::pose_bits;

/// Awake bodies sampled at each analysis.
pub(crate) const SAMPLE: usize = 8;

/// What the last analysis saw of a few awake bodies, to tell at the next pre-step
/// whether Rapier stepped in between.
#[derive(Clone, Debug, Default)]
pub(crate) struct StepWitness {
    /// Sampled bodies: handle, pose bits, velocity bits, sleep timer, and whether its
    /// velocity moves its pose within a step ([`moves_in_a_step`]).
    sample: Vec<(RigidBodyHandle, [u32; 7], [u32; 6], f32, bool)>,
    /// With no dynamic body to sample, a few other bodies of the active set
    /// (kinematic, or fixed by the user or the speed-ups): handle and pose bits.
    others: Vec<(RigidBodyHandle, [u32; 7])>,
    /// Rapier's active-set size at the last analysis.
    active: usize,
    /// Whether an analysis recorded the witness (not after a restore).
    recorded: bool,
}

impl StepWitness {
    /// Records the first [`SAMPLE`] dynamic bodies of Rapier's active set as they are
    /// after the step just analysed (with none, its first other bodies' poses).
    /// O(SAMPLE + the kinematic and fixed bodies before them in the active set).
    pub(crate) fn record(&mut self, bodies: &RigidBodySet, islands: &IslandManager, dt: f32) {
        self.sample.clear();
        // Dynamic bodies only: a kinematic body at rest (or driven by less than a
        // pose's resolution) shows no step.
        let dynamic = islands
            .active_bodies()
            .filter_map(|h| bodies.get(h).filter(|rb| rb.is_dynamic()).map(|rb| (h, rb)));
        for (h, rb) in dynamic.take(SAMPLE) {
            self.sample.push((
                h,
                pose_bits(rb.position()),
                vel_bits(rb),
                rb.activation().time_since_can_sleep,
                moves_in_a_step(rb, dt),
            ));
        }
        self.others.clear();
        if self.sample.is_empty() {
            let others = islands
                .active_bodies()
                .filter_map(|h| bodies.get(h).map(|rb| (h, pose_bits(rb.position()))));
            self.others.extend(others.take(SAMPLE));
        }
        self.active = islands.num_active_bodies();
        self.recorded = true;
    }

    /// Whether Rapier stepped since [`Self::record`], as far as the sample tells: a
    /// sampled body's sleep timer grew, or every sampled body that was moving fast
    /// enough to change its pose in a step (and is
    /// still in the world and dynamic) moved or changed velocity, or, none moving,
    /// every one with any velocity did, or, none with any, every one still there
    /// did, or (none left) a body of the active set that was not
    /// dynamic is dynamic now and moved, or the active set changed size. Bodies
    /// at rest are left out while some moved: a pile's resting bodies keep their pose
    /// through a step (exactly so under the speed-ups, which zero their velocities and
    /// own sleeping, so that no sleep timer grows). A user who teleports every
    /// sampled moving body, or removes them, between two steps makes it answer `true`
    /// too: the layer then reads the world once more than it needed. O(SAMPLE).
    pub(crate) fn stepped_since(&self, bodies: &RigidBodySet, islands: &IslandManager) -> bool {
        if !self.recorded {
            return false;
        }
        let (mut live, mut changed) = (0, 0);
        let (mut moving, mut moving_changed) = (0, 0);
        let (mut drifting, mut drifting_changed) = (0, 0);
        for &(h, pose, vel, timer, moves) in &self.sample {
            // A body removed, turned kinematic or fixed, or disabled by the user (a
            // step does not move it) tells nothing.
            let Some(rb) = bodies
                .get(h)
                .filter(|rb| rb.is_dynamic() && rb.is_enabled())
            else {
                continue;
            };
            live += 1;
            if rb.activation().time_since_can_sleep > timer {
                return true;
            }
            let now = pose_bits(rb.position()) != pose || vel_bits(rb) != vel;
            changed += usize::from(now);
            if moves {
                moving += 1;
                moving_changed += usize::from(now);
            } else if vel.iter().any(|&v| f32::from_bits(v) != 0.0) {
                drifting += 1;
                drifting_changed += usize::from(now);
            }
        }
        if moving > 0 {
            moving_changed == moving
        } else if drifting > 0 {
            // None fast enough to move for sure: the ones with any velocity (a body
            // at rest under the speed-ups has none, and keeps its pose exactly).
            drifting_changed == drifting
        } else if live > 0 {
            changed == live
        } else {
            // A body that was not dynamic, made dynamic by the user, moves in a step.
            let fell = self.others.iter().any(|&(h, pose)| {
                bodies
                    .get(h)
                    .is_some_and(|rb| rb.is_dynamic() && pose_bits(rb.position()) != pose)
            });
            fell || islands.num_active_bodies() != self.active
        }
    }
}

/// Whether a step of `dt` at the body's velocity changes its pose: a translation by
/// more than two units in the last place of its position, or a turn by more than two
/// units in the last place of 1 (a rotation's scale); a body drifting at 1e-9 m/s
/// keeps its pose bit for bit. A `dt` that is not positive and finite counts any
/// velocity. O(1).
fn moves_in_a_step(rb: &rapier3d::prelude::RigidBody, dt: f32) -> bool {
    let (l, a) = (rb.linvel(), rb.angvel());
    if !(dt.is_finite() && dt > 0.0) {
        return l != rapier3d::math::Vector::ZERO || a != rapier3d::math::Vector::ZERO;
    }
    let resolution = 2.0 * f32::EPSILON;
    let scale = rb.translation().abs().max_element().max(1.0);
    l.abs().max_element() * dt > resolution * scale || a.abs().max_element() * dt > resolution
}

/// A body's velocities as bits. O(1).
fn vel_bits(rb: &rapier3d::prelude::RigidBody) -> [u32; 6] {
    let (l, a) = (rb.linvel(), rb.angvel());
    [l.x, l.y, l.z, a.x, a.y, a.z].map(f32::to_bits)
}

impl Coherence {
    /// Called at the pre-step, before Rapier's step: if Rapier stepped since the last
    /// analysis without the layer's event handler, the next update reads the world in
    /// full, as after [`Self::request_full_sync`]. Touching tracking learns changes
    /// from the events alone; proximity tracking reads the pairs of every body awake
    /// now or at the last update, but a body the user woke and put back to sleep
    /// around the missed step was asleep at both. O([`SAMPLE`]).
    pub(crate) fn check_unseen_step(&mut self, bodies: &RigidBodySet, islands: &IslandManager) {
        if self.tracking.is_some() && self.witness.stepped_since(bodies, islands) {
            self.force_full_sync = true;
            self.unseen_step = true;
        }
    }

    /// Whether a step the layer did not see was found since the last analysis. O(1).
    pub(crate) fn unseen_step_pending(&self) -> bool {
        self.unseen_step
    }
}
