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
    /// Sampled bodies: handle, pose bits, velocity bits, sleep timer.
    sample: Vec<(RigidBodyHandle, [u32; 7], [u32; 6], f32)>,
    /// Rapier's active-set size at the last analysis.
    active: usize,
    /// Whether an analysis recorded the witness (not after a restore).
    recorded: bool,
}

impl StepWitness {
    /// Records the first [`SAMPLE`] dynamic bodies of Rapier's active set as they are
    /// after the step just analysed. O(SAMPLE + the kinematic and fixed bodies before
    /// them in the active set).
    pub(crate) fn record(&mut self, bodies: &RigidBodySet, islands: &IslandManager) {
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
            ));
        }
        self.active = islands.num_active_bodies();
        self.recorded = true;
    }

    /// Whether Rapier stepped since [`Self::record`], as far as the sample tells: a
    /// sampled body's sleep timer grew, or every sampled body still in the world and
    /// dynamic moved or changed velocity, or (none left) the active set changed
    /// size. A user who teleports every
    /// sampled body, or removes them, between two steps makes it answer `true` too:
    /// the layer then reads the world once more than it needed. O(SAMPLE).
    pub(crate) fn stepped_since(&self, bodies: &RigidBodySet, islands: &IslandManager) -> bool {
        if !self.recorded {
            return false;
        }
        let mut live = 0;
        let mut moved = 0;
        for &(h, pose, vel, timer) in &self.sample {
            // A body removed, or turned kinematic or fixed by the user, tells nothing.
            let Some(rb) = bodies.get(h).filter(|rb| rb.is_dynamic()) else {
                continue;
            };
            live += 1;
            if rb.activation().time_since_can_sleep > timer {
                return true;
            }
            if pose_bits(rb.position()) != pose || vel_bits(rb) != vel {
                moved += 1;
            }
        }
        if live > 0 {
            moved == live
        } else {
            islands.num_active_bodies() != self.active
        }
    }
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
}
