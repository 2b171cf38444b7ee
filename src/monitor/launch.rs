//! Launches (paper Fig. 15 ♠): contact groups gaining kinetic energy that gravity
//! cannot account for.
//!
//! For each contact group of the step (the groups of the refreshed bodies), with `ΔKE`
//! each member's kinetic energy change since the last check and `W` the work gravity
//! did on it (`m · s · g · (x_now − x_before)`, `s` the body's gravity scale, `x` its
//! centre of mass), the excess is `Σ ΔKE − Σ max(0, W)`. Rapier integrates velocities
//! before positions (symplectic Euler), so in free fall `ΔKE = W − ½ m g² dt²`: the
//! bound is never exceeded by gravity alone; and it computes contacts at the start of
//! a step, so the group the graph shows after the step is the set of bodies that
//! exchanged impulses in it. Energy moved from one member to another cancels in the
//! sum. The group is skipped when a member has no state from an earlier check (it is
//! new; see `Monitor::prime`), is excepted by the caller or was released by the caller
//! since the last check, or when the group touches a scripted body.
//!
//! The violation is reported on the member with the largest gain. A launch spread over
//! consecutive steps is one episode: a group with excess energy that holds a body whose
//! group had excess energy at the previous check is not reported again.

use std::collections::HashMap;

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;

use super::{simulated, Ctx, MonitorConfig, Peaks, Violation, ViolationKind};
use crate::graph::NodeKind;
use crate::groups::GroupId;
use crate::WorldView;

/// What a body was at the last check that saw it.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct BodyState {
    kinetic: Real,
    com: Vector,
    /// The caller held it at that check.
    held: bool,
    /// The last step its group had excess energy.
    launched: Option<u64>,
}

#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Launch {
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    state: HashMap<RigidBodyHandle, BodyState>,
    /// Scratch: this step's groups, and the members of groups with excess energy.
    groups: Vec<GroupId>,
    launched: Vec<RigidBodyHandle>,
}

impl Launch {
    /// Records a body's current state as its state before the next step.
    pub(crate) fn prime(&mut self, view: &WorldView, h: RigidBodyHandle) {
        let Some(rb) = view.bodies.get(h).filter(|rb| rb.is_dynamic()) else {
            return;
        };
        let s = self.state.entry(h).or_insert(BodyState {
            kinetic: 0.0,
            com: Vector::ZERO,
            held: false,
            launched: None,
        });
        s.kinetic = rb.kinetic_energy();
        s.com = rb.center_of_mass();
    }

    pub(crate) fn forget(&mut self, h: RigidBodyHandle) {
        self.state.remove(&h);
    }

    // Long: the energy balance of a group needs every member's state of the step at once.
    pub(crate) fn check(
        &mut self,
        ctx: &Ctx,
        config: &MonitorConfig,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        excepted: &dyn Fn(RigidBodyHandle) -> bool,
        out: &mut Vec<Violation>,
        peaks: &mut Peaks,
    ) {
        if !ctx.fresh {
            return;
        }
        let layer = ctx.layer;
        let graph = layer.graph();
        let gravity = ctx.view.gravity;
        let refreshed = layer.coherence().refreshed_nodes();

        self.groups.clear();
        self.groups.extend(
            refreshed
                .iter()
                .filter_map(|&n| graph.node(n).and_then(|node| node.group())),
        );
        self.groups.sort_unstable();
        self.groups.dedup();
        self.launched.clear();

        'groups: for &gid in &self.groups {
            let Some(group) = layer.groups().get(gid) else {
                continue;
            };
            if group.insulators.iter().any(|&i| {
                graph
                    .node(i)
                    .is_some_and(|n| n.kind() == NodeKind::Kinematic)
            }) {
                continue;
            }
            // Σ ΔKE − Σ max(0, W) over the group; the tolerance counts only the members
            // whose energy rose by more than gravity's work on them (the "gainers"), so
            // one body thrown out of a large group is not diluted by the group's mass.
            let (mut excess, mut before, mut mass) = (0.0, 0.0, 0.0);
            let mut top: Option<(Real, RigidBodyHandle, crate::NodeId)> = None;
            let mut continuing = false;
            for &n in &group.bodies {
                let Some(h) = simulated(layer, n) else {
                    continue;
                };
                let Some(rb) = ctx.view.bodies.get(h) else {
                    continue 'groups;
                };
                let Some(prev) = self.state.get(&h) else {
                    continue 'groups; // new: nothing to compare with
                };
                if excepted(h) || (prev.held && !held(h)) {
                    continue 'groups;
                }
                let m = rb.mass();
                let work = m * rb.gravity_scale() * gravity.dot(rb.center_of_mass() - prev.com);
                let d = rb.kinetic_energy() - prev.kinetic;
                if !(d.is_finite() && work.is_finite()) {
                    continue 'groups; // an escape, reported as such
                }
                let own = d - work.max(0.0);
                excess += own;
                if own > 0.0 {
                    before += prev.kinetic;
                    mass += m;
                }
                if top.is_none_or(|(best, _, _)| d > best) {
                    top = Some((d, h, n));
                }
                continuing |= prev.launched.is_some() && prev.launched == ctx.prev_step;
            }
            let Some((_, body, node)) = top else {
                continue;
            };
            let tolerance = config.launch_relative * before + config.launch_per_kg * mass;
            let ratio = if tolerance > 0.0 {
                excess / tolerance
            } else if excess > 0.0 {
                Real::INFINITY
            } else {
                0.0
            };
            peaks.launch = peaks.launch.max(ratio);
            peaks.launch_excess = peaks.launch_excess.max(excess);
            if excess > tolerance {
                self.launched
                    .extend(group.bodies.iter().filter_map(|&n| simulated(layer, n)));
                if !continuing {
                    out.push(Violation {
                        step: ctx.step,
                        kind: ViolationKind::Launch,
                        body,
                        node: Some(node),
                        value: excess,
                    });
                }
            }
        }

        // Remember this step's state of every refreshed (or new) body.
        let coherence = layer.coherence();
        for &n in refreshed.iter().chain(coherence.created_nodes()) {
            let Some(h) = simulated(layer, n) else {
                continue;
            };
            let Some(rb) = ctx.view.bodies.get(h) else {
                continue;
            };
            let s = self.state.entry(h).or_insert(BodyState {
                kinetic: 0.0,
                com: Vector::ZERO,
                held: false,
                launched: None,
            });
            s.kinetic = rb.kinetic_energy();
            s.com = rb.center_of_mass();
            s.held = held(h);
        }
        for &h in &self.launched {
            if let Some(s) = self.state.get_mut(&h) {
                s.launched = Some(ctx.step);
            }
        }
        // Sweep bodies removed while nobody checked (amortised O(1) per body).
        if self.state.len() > 2 * ctx.view.bodies.len() + 64 {
            let bodies = ctx.view.bodies;
            self.state.retain(|h, _| bodies.contains(*h));
        }
    }
}
