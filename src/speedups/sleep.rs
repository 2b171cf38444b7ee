//! Sleepy: the rest tracking of awake bodies, and the sleep-eligibility the layer
//! writes into Rapier so that Rapier puts whole islands to sleep.

use std::collections::BTreeMap;

use rapier3d::dynamics::RigidBodyActivation;
use rapier3d::prelude::RigidBodyHandle;

use super::{key, SpeedUpState, SpeedUps};
use crate::graph::{ContactGraph, NodeId, NodeSource};
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;
use crate::WorldView;

/// Per-body rest tracking, indexed by body slot.
#[derive(Clone, Copy, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Rest {
    generation: u32,
    pub(super) steps: u32,
    pub(super) sleepy: bool,
    /// Sleep-eligibility currently written into Rapier.
    pub(super) eligible: bool,
}

/// Makes a body sleep-eligible in Rapier. O(1).
fn eligible_activation(a: &mut RigidBodyActivation, dt: f32) {
    a.normalized_linear_threshold = f32::MAX;
    a.angular_threshold = f32::MAX;
    // Two steps: a body woken by Rapier (timer reset) cannot fall asleep again in the
    // same step, before the layer has seen it wake.
    a.time_until_sleep = 2.0 * dt;
}

/// Records a body's sleep thresholds before the speed-ups first change them. O(log n).
pub(super) fn remember_activation(
    saved: &mut BTreeMap<(u32, u32), (RigidBodyHandle, [f32; 3])>,
    h: RigidBodyHandle,
    rb: &rapier3d::dynamics::RigidBody,
) {
    let a = rb.activation();
    saved.entry(key(h)).or_insert((
        h,
        [
            a.normalized_linear_threshold,
            a.angular_threshold,
            a.time_until_sleep,
        ],
    ));
}

/// Makes a body never sleep-eligible in Rapier. O(1).
pub(super) fn never_activation(a: &mut RigidBodyActivation) {
    a.normalized_linear_threshold = -1.0;
    a.angular_threshold = -1.0;
}

impl SpeedUpState {
    /// A body's rest record, if it has one. O(1).
    pub(super) fn rest_of(&self, h: RigidBodyHandle) -> Option<&Rest> {
        let (i, g) = key(h);
        self.rest.get(i as usize).filter(|r| r.generation == g)
    }

    /// A body's rest record, a new one if it has none. O(1).
    pub(super) fn rest_mut(&mut self, h: RigidBodyHandle) -> &mut Rest {
        let (i, g) = key(h);
        let i = i as usize;
        if self.rest.len() <= i {
            self.rest.resize(i + 1, Rest::default());
        }
        let r = &mut self.rest[i];
        if r.generation != g {
            *r = Rest {
                generation: g,
                ..Rest::default()
            };
        }
        r
    }

    /// Whether a body is sleepy (at rest for `sleepy_steps` steps). O(1).
    pub fn is_sleepy(&self, h: RigidBodyHandle) -> bool {
        self.rest_of(h).is_some_and(|r| r.sleepy) || self.is_fixated(h)
    }

    /// Tracks the refreshed bodies' energy (before the groups are rebuilt, so that
    /// subgrouping sees this step's sleepy bodies). O(refreshed bodies).
    pub(crate) fn track(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
        woke: &[(NodeId, bool)],
        mods: &mut ContactMods,
    ) {
        if self.detached {
            return;
        }
        self.sleepy_changed.clear();
        self.stats.sleepy = 0;
        self.stats.fixations = 0;
        self.stats.releases = 0;
        if refreshed.is_empty() && woke.is_empty() {
            return;
        }
        let c = self.config.clone();
        for &(n, awake) in woke {
            if awake {
                if let Some(h) = graph.body_of(n) {
                    let r = self.rest_mut(h);
                    r.steps = 0;
                    let was = std::mem::replace(&mut r.sleepy, false);
                    if was {
                        mods.set_sleepy(h, false);
                        self.zero_flags.push((h, false));
                        self.sleepy_changed.push(h);
                    }
                }
            }
        }
        for &n in refreshed {
            let Some(node) = graph.node(n) else { continue };
            let NodeSource::Body(h) = node.source() else {
                continue;
            };
            if !node.kind().is_simulated() || !node.is_awake() {
                continue;
            }
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            let mass = rb.mass();
            let ke = if mass > 0.0 {
                rb.kinetic_energy() / mass
            } else {
                0.0
            };
            let at_rest = ke.is_finite() && ke < c.sleepy_energy;
            let r = self.rest_mut(h);
            r.steps = if at_rest {
                r.steps.saturating_add(1)
            } else {
                0
            };
            let sleepy = r.steps >= c.sleepy_steps;
            if sleepy != r.sleepy {
                r.sleepy = sleepy;
                mods.set_sleepy(h, sleepy);
                self.zero_flags.push((h, sleepy));
                self.sleepy_changed.push(h);
            }
            if sleepy {
                self.stats.sleepy = self.stats.sleepy.saturating_add(1);
            }
        }
    }

    /// The sleep-eligibility each body of the awake groups (or, without groups, each
    /// refreshed body) should have now: a group is eligible when all its bodies are
    /// sleepy. O(awake groups' members + refreshed bodies).
    pub(super) fn wanted_eligibility(
        &self,
        graph: &ContactGraph,
        groups: &crate::Groups,
        refreshed: &[NodeId],
        c: &SpeedUps,
    ) -> Vec<(RigidBodyHandle, bool)> {
        let mut want: Vec<(RigidBodyHandle, bool)> = Vec::new();
        if c.groups {
            // The awake groups only: O(their members), not O(the slots the groups
            // have used), which a settled, held scene would pay every step. (Their
            // order does not matter: each body is in one group, and the pre-step
            // writes the decisions in handle order.)
            for (_, g) in groups.iter_awake() {
                let from = want.len();
                want.extend(
                    g.bodies
                        .iter()
                        .filter_map(|&n| graph.body_of(n))
                        .map(|h| (h, false)),
                );
                let all = want[from..].iter().all(|&(h, _)| self.is_sleepy(h));
                if all {
                    for w in &mut want[from..] {
                        w.1 = true;
                    }
                }
            }
            // Sleepy bodies outside any group (insulated by subgrouping) decide alone.
            for &n in refreshed {
                if let Some(node) = graph.node(n) {
                    if node.kind().is_simulated() && node.group().is_none() {
                        if let Some(h) = node.body() {
                            want.push((h, self.is_sleepy(h)));
                        }
                    }
                }
            }
        } else {
            for &n in refreshed {
                if let Some(h) = graph.body_of(n) {
                    want.push((h, self.is_sleepy(h)));
                }
            }
        }
        want
    }

    /// Queues the eligibility changes among `want` for the pre-step. O(want).
    pub(super) fn note_eligibility(
        &mut self,
        view: &WorldView,
        want: Vec<(RigidBodyHandle, bool)>,
    ) {
        for (h, eligible) in want {
            // Most decisions are those of the last step: the body is looked up in
            // Rapier only when its eligibility changes (a body without a record is
            // not eligible).
            if self.rest_of(h).is_some_and(|r| r.eligible) == eligible {
                continue;
            }
            if view.bodies.get(h).is_none_or(|b| !b.is_dynamic()) {
                continue;
            }
            let r = self.rest_mut(h);
            if r.eligible != eligible {
                r.eligible = eligible;
                self.eligibility.push((h, eligible));
            }
        }
    }

    /// Writes the queued eligibility changes into Rapier (sorted by handle). O(changes).
    pub(super) fn write_eligibility(&mut self, world: &mut WorldMut) {
        let dt = world.integration_parameters.dt;
        for (h, eligible) in std::mem::take(&mut self.eligibility) {
            // Read first: a write flags the body, and a held one flagged is the user's
            // ([`Self::release_written`]).
            if !world.bodies.get(h).is_some_and(|rb| rb.is_dynamic()) {
                continue;
            }
            if let Some(rb) = world.bodies.get_mut(h) {
                remember_activation(&mut self.activations, h, rb);
                if eligible {
                    eligible_activation(rb.activation_mut(), dt);
                } else {
                    never_activation(rb.activation_mut());
                }
            }
        }
    }
}
