//! Hanging sleepers (paper Fig. 17): held bodies without support.
//!
//! Which bodies are looked at: the bodies the analysis refreshed (awake now or at the
//! step before: a body is refreshed in the step it falls asleep), the bodies created in
//! the step (one may be created asleep), the bodies fixated by the speed-ups whose
//! remembered support is gone ([`crate::speedups::SpeedUpState::fixation_supported`]),
//! the held bodies next to a change (a touching contact ended, a neighbour was
//! removed, a scripted body touching or jointed to them moves, gravity changed), and
//! the bodies already being timed.
//!
//! Nothing that moves holds a body still: a held body touching or jointed to a moving
//! scripted body is unsupported whatever else it rests on (the sleepers Rapier leaves
//! behind a moving kinematic body, rapier #287 and #692). A sleeping body that is not being timed was
//! supported when it fell asleep, and its contacts are frozen until Rapier wakes it —
//! which it does when something touching it is removed — so it needs no look.
//!
//! Support is judged by the contact normals and the contacts within [`SUPPORT_GAP`],
//! read from Rapier's narrow phase for the body looked at whatever the tracking (the
//! graph's cached test on the same pairs; touching tracking, the default, caches
//! neither). Only held bodies are judged, so the reading costs O(their contact
//! pairs).

use std::collections::HashMap;

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;

use super::{simulated, Ctx, MonitorConfig, Peaks, Violation, ViolationKind};
use crate::coherence::details::resting_supports;
use crate::graph::NodeId;
use crate::speedups::SUPPORT_GAP;

/// A held, unsupported body being timed.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Timed {
    seconds: Real,
    reported: bool,
    /// The layer step of its last look (a body is looked at once per check).
    looked: u64,
}

#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Hanging {
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    timed: HashMap<RigidBodyHandle, Timed>,
    /// The gravity of the last check (a change re-judges every held body).
    gravity: Option<Vector>,
    /// Scratch: held bodies next to a change.
    near: Vec<(RigidBodyHandle, NodeId)>,
    /// Scratch: the timed bodies not refreshed in this step.
    rest: Vec<RigidBodyHandle>,
}

impl Hanging {
    pub(crate) fn forget(&mut self, h: RigidBodyHandle) {
        self.timed.remove(&h);
    }

    pub(crate) fn timed(&self) -> impl Iterator<Item = (RigidBodyHandle, Real)> + '_ {
        self.timed.iter().map(|(h, t)| (*h, t.seconds))
    }

    pub(crate) fn check(
        &mut self,
        ctx: &Ctx,
        config: &MonitorConfig,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        out: &mut Vec<Violation>,
        peaks: &mut Peaks,
    ) {
        // Gravity is remembered before anything else, so that gravity switched on from
        // zero is a change too (bevy_rapier #570: sleepers ignore it).
        let gravity_changed = self
            .gravity
            .replace(ctx.view.gravity)
            .is_some_and(|before| before != ctx.view.gravity);
        let g = ctx.view.gravity.length();
        if !g.is_finite() || g <= 0.0 {
            // Without gravity nothing hangs.
            self.timed.clear();
            return;
        }
        let up = -ctx.view.gravity / g;
        self.look_near_changes(ctx, held, gravity_changed);
        for i in 0..self.near.len() {
            let (h, n) = self.near[i];
            self.look(ctx, config, held, up, h, Some(n), out, peaks);
        }
        let coherence = ctx.layer.coherence();
        for &n in coherence
            .refreshed_nodes()
            .iter()
            .chain(coherence.created_nodes())
        {
            // A body fixated by the speed-ups is a `Fixed` node while held: the caller's
            // `held` says it is one of ours.
            let h = simulated(ctx.layer, n).or_else(|| {
                ctx.layer
                    .graph()
                    .body_of(n)
                    .filter(|&h| held(h) && ctx.view.bodies.get(h).is_some_and(|rb| rb.is_fixed()))
            });
            if let Some(h) = h {
                self.look(ctx, config, held, up, h, Some(n), out, peaks);
            }
        }
        // Fixated bodies are not refreshed while nothing moves them; the speed-ups
        // tell which lost their support.
        if let Some(s) = ctx.layer.speedups() {
            for h in s.unsupported_fixated() {
                if held(h) {
                    let n = ctx.layer.graph().node_of_body(h);
                    self.look(ctx, config, held, up, h, n, out, peaks);
                }
            }
        }
        self.rest.clear();
        self.rest.extend(
            self.timed
                .iter()
                .filter(|(_, t)| t.looked != ctx.step)
                .map(|(h, _)| *h),
        );
        for i in 0..self.rest.len() {
            let h = self.rest[i];
            let n = ctx.layer.graph().node_of_body(h);
            self.look(ctx, config, held, up, h, n, out, peaks);
        }
    }

    /// Collects into `near` the held bodies that are not refreshed but next to
    /// something that changed: both ends of an edge whose touching ended in the step,
    /// the survivors of edges removed with a node, the bodies a moving scripted body
    /// touches or is jointed to, and, when gravity changed, every held body (once per
    /// change: O(nodes)). Otherwise O(edges touched or removed in the step + contacts
    /// and joints of moving scripted bodies).
    fn look_near_changes(
        &mut self,
        ctx: &Ctx,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        gravity_changed: bool,
    ) {
        self.near.clear();
        let layer = ctx.layer;
        let graph = layer.graph();
        let view = ctx.view;
        let is_held = |h: RigidBodyHandle| {
            view.bodies
                .get(h)
                .is_some_and(|rb| in_simulation(ctx, h, rb) && (rb.is_sleeping() || held(h)))
        };
        let near = &mut self.near;
        let mut add = |n: NodeId| {
            if let Some(h) = graph.body_of(n).filter(|&h| is_held(h)) {
                near.push((h, n));
            }
        };
        if gravity_changed {
            for (n, node) in graph.nodes() {
                if node.kind().is_simulated() || node.kind() == crate::NodeKind::Fixed {
                    add(n);
                }
            }
        } else {
            let coherence = layer.coherence();
            for &e in coherence.touched_edges() {
                if let Some(e) = graph.edge(e) {
                    if e.touching_mark(ctx.step) == Some(crate::graph::Transition::Vanished) {
                        add(e.a());
                        add(e.b());
                    }
                }
            }
            for e in coherence.removed_edges() {
                add(e.a());
                add(e.b());
            }
            for &n in coherence.refreshed_nodes() {
                let Some(node) = graph.node(n) else { continue };
                if node.kind() != crate::NodeKind::Kinematic {
                    continue;
                }
                let Some(k) = node.body() else { continue };
                let moving = view.bodies.get(k).is_some_and(crate::world::moves);
                if !moving {
                    continue;
                }
                for (m, _, e) in graph.neighbors(n) {
                    if e.kind() == crate::graph::EdgeKind::Physical {
                        add(m);
                    }
                }
                for (b1, b2, _, _) in view.impulse_joints.attached_joints(k) {
                    let other = if b1 == k { b2 } else { b1 };
                    if let Some(m) = graph.node_of_body(other) {
                        add(m);
                    }
                }
            }
        }
        self.near.sort_by_key(|(h, _)| h.into_raw_parts());
        self.near.dedup();
    }

    #[allow(clippy::too_many_arguments)]
    // Long: the cases of a held body (commented) share its timer and its support reading.
    fn look(
        &mut self,
        ctx: &Ctx,
        config: &MonitorConfig,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        up: Vector,
        h: RigidBodyHandle,
        n: Option<NodeId>,
        out: &mut Vec<Violation>,
        peaks: &mut Peaks,
    ) {
        if self.timed.get(&h).is_some_and(|t| t.looked == ctx.step) {
            // Looked at already: in this check (refreshed and created), or in an
            // earlier check of the same step (no time passed since).
            return;
        }
        let graph = ctx.layer.graph();
        let (Some(n), Some(rb)) = (n, ctx.view.bodies.get(h)) else {
            self.timed.remove(&h);
            return;
        };
        let simulated = graph.node(n).is_some_and(|node| node.kind().is_simulated());
        // A simulated body is held when asleep or held by the caller; a body the
        // caller turned fixed (the speed-ups' fixation) when the caller holds it.
        // (A held body the speed-ups disabled for one step to take it out of Rapier's
        // active set is still held.)
        let is_held = in_simulation(ctx, h, rb)
            && if simulated {
                rb.is_sleeping() || held(h)
            } else {
                rb.is_fixed() && held(h)
            };
        // Without the layer's contact details there are no normals to judge support
        // by; then any touching contact counts (no false alarms).
        let supported = || {
            // Nothing that moves holds a body still: a held body jointed to, or touching,
            // a moving scripted body (rapier #692, #287) is not held plausibly, whatever
            // else supports it.
            let moving_script = |other: RigidBodyHandle| {
                ctx.view
                    .bodies
                    .get(other)
                    .is_some_and(|rb| rb.is_kinematic() && crate::world::moves(rb))
            };
            let dragged = ctx
                .view
                .impulse_joints
                .attached_joints(h)
                .any(|(b1, b2, _, _)| moving_script(if b1 == h { b2 } else { b1 }))
                || graph
                    .touching(n)
                    .any(|m| graph.body_of(m).is_some_and(moving_script));
            if dragged {
                return false;
            }
            // A body fixated by the speed-ups is fixed in Rapier, which computes no
            // contacts between fixed bodies: what held it when it was fixated is
            // remembered by the speed-ups (see `SpeedUpState::fixation_supported`).
            if ctx
                .layer
                .speedups()
                .and_then(|s| s.fixation_supported(h))
                .unwrap_or(false)
            {
                return true;
            }
            // Read from Rapier whatever the tracking (touching tracking keeps neither
            // normals nor the contacts within the gap that do not touch), as the
            // speed-ups' support memory reads it.
            let mut found = Vec::new();
            resting_supports(
                graph,
                ctx.view,
                n,
                up,
                config.min_support_cos,
                SUPPORT_GAP,
                &mut found,
            );
            !found.is_empty()
        };
        if !is_held || supported() {
            self.timed.remove(&h);
            return;
        }
        let t = self.timed.entry(h).or_insert(Timed {
            seconds: 0.0,
            reported: false,
            looked: u64::MAX,
        });
        t.looked = ctx.step;
        if ctx.fresh {
            t.seconds += ctx.view.dt;
        }
        if config.hang_time > 0.0 {
            peaks.hang = peaks.hang.max(t.seconds / config.hang_time);
        }
        if t.seconds > config.hang_time && !t.reported {
            t.reported = true;
            out.push(Violation {
                step: ctx.step,
                kind: ViolationKind::HangingSleeper,
                body: h,
                node: Some(n),
                value: t.seconds,
            });
        }
    }
}

/// Whether a body takes part in the simulation: enabled, or disabled by the
/// speed-ups for this one step on its way out of Rapier's active set (a body the user
/// disabled, held or not, is out of it). O(parking).
fn in_simulation(ctx: &Ctx, h: RigidBodyHandle, rb: &rapier3d::prelude::RigidBody) -> bool {
    rb.is_enabled()
        || ctx
            .layer
            .speedups()
            .is_some_and(|s| s.parking().any(|p| p == h))
}
