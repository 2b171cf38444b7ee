//! The monitor owned by the layer: off, report, or repair.
//!
//! # Modes
//! - **Off**: nothing runs; the layer costs what it cost without a monitor.
//! - **Report**: after every analysis the detectors of [`super::Monitor`] run on the
//!   step; each violation is counted ([`crate::StepStats::violations`],
//!   [`super::Monitor::totals`]) and sent as an [`EventKind::Violation`] event on the
//!   event channels. Report mode reads the world and never writes it, so it does not
//!   change motion (tested bit for bit).
//! - **Repair**: report, and act on what the detectors see, in the next pre-step:
//!   - *an unsupported held body* (a sleeper or a fixated body whose support is gone,
//!     timed by the hanging detector from the first unsupported step, long before it
//!     is a violation) is woken together with its contact group: fixated bodies are
//!     released (type and velocities restored), sleepers woken in Rapier, and the
//!     speed-ups' rest counters of the group start again, so the group cannot be put
//!     back to sleep before it has moved;
//!   - *a held body an awake body presses into* over
//!     [`MonitorConfig::unresponsive_push`] (an unresponsive body, in the step it is
//!     found: a push cannot be seen coming) is released with the held bodies it
//!     touched when it was held, or that touched it, transitively, nearest first, as
//!     far as the pusher's momentum could set them moving (the reach's bound), and
//!     the pusher's rest count starts again, so that the next step moves what the
//!     push would move in a sleeping Rapier pile;
//!   - *a released or woken body* gets a capped position correction for
//!     [`RepairConfig::cap_steps`] steps (Rapier's `normalized_max_corrective_velocity`
//!     lowered to [`RepairConfig::corrective_cap`] while any such body is fresh), so
//!     that the penetration it built up while held is pushed out gently instead of
//!     throwing it (paper Fig. 15 ♠);
//!   - *a launch* that happened anyway is stopped: the launched group's velocities are
//!     scaled down to take the excess energy out again (the launch stays counted);
//!   - *a contact on its way to a deep penetration* (deeper than
//!     [`RepairConfig::penetration_warning`] of the limit) makes the speed-ups that
//!     thin out the solver (fewer iterations and deepest contact only) stand down for
//!     [`RepairConfig::cap_steps`] steps: full iterations, every contact point.
//!
//!   Each action is reported as an [`EventKind::Repaired`] event naming the body and
//!   the violation it prevents.
//!
//! Repair acts on the hanging detector's timer, not on the report, so a body falls in
//! the step after its support went; why, and what was rejected: `docs/ARCHITECTURE.md`
//! ("Repair"). Repairs are applied in body-handle order: the same inputs give the same
//! writes into Rapier.
//!
//! # Cost
//! Report: the detectors' cost (see [`super`]). Repair: O(members of the groups
//! acted on) per action, plus O(1) per step.

use std::collections::BTreeMap;

use rapier3d::math::Real;
use rapier3d::prelude::RigidBodyHandle;

use super::{Monitor, MonitorConfig, Violation, ViolationKind};
use crate::events::{Event, EventKind};
use crate::graph::{ContactGraph, NodeId};
use crate::groups::Groups;
use crate::logic::WorldMut;
use crate::speedups::SpeedUpState;
use crate::util::rapier::live_body_mut;
use crate::{Error, Result};

/// What the layer's monitor does (see the module docs).
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MonitorMode {
    /// No monitor (the default).
    #[default]
    Off,
    /// Detect, count, and send violation events; never write the world.
    Report,
    /// Report, and repair what the detectors see.
    Repair,
}

impl MonitorMode {
    /// A short stable name (`"off"`, `"report"`, `"repair"`).
    pub const fn name(self) -> &'static str {
        match self {
            MonitorMode::Off => "off",
            MonitorMode::Report => "report",
            MonitorMode::Repair => "repair",
        }
    }
}

/// Parameters of the repair mode.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RepairConfig {
    /// Rapier's `normalized_max_corrective_velocity` while a released or woken body is
    /// fresh (Rapier's default is 3). Default 0.5.
    pub corrective_cap: Real,
    /// Steps a released or woken body stays fresh, and a deep penetration keeps fewer
    /// iterations and deepest contact only standing down. Default 10.
    pub cap_steps: u32,
    /// The early warning of a deep penetration: fewer iterations and deepest contact only stand down as soon as
    /// a contact is deeper than this fraction of the deep-penetration limit. Default
    /// 0.5. In `(0, 1]`.
    pub penetration_warning: Real,
    /// A body that would travel farther than this in one step (metres) is fast: it
    /// gets Rapier's soft-CCD prediction (twice its travel) while it is. Default 0.02.
    pub fast_travel: Real,
}

impl Default for RepairConfig {
    fn default() -> Self {
        Self {
            corrective_cap: 0.5,
            cap_steps: 10,
            penetration_warning: 0.5,
            fast_travel: 0.02,
        }
    }
}

impl RepairConfig {
    /// Checks the fields: `corrective_cap` finite and positive, `penetration_warning` in
    /// `(0, 1]`, `fast_travel` finite and non-negative.
    pub fn validate(&self) -> Result<()> {
        if !(self.corrective_cap.is_finite() && self.corrective_cap > 0.0) {
            return Err(Error::InvalidParameter {
                name: "corrective_cap",
                reason: format!("must be finite and positive, got {}", self.corrective_cap),
            });
        }
        if !(self.fast_travel.is_finite() && self.fast_travel >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "fast_travel",
                reason: format!("must be finite and non-negative, got {}", self.fast_travel),
            });
        }
        if !(self.penetration_warning > 0.0 && self.penetration_warning <= 1.0) {
            return Err(Error::InvalidParameter {
                name: "penetration_warning",
                reason: format!("must be in (0, 1], got {}", self.penetration_warning),
            });
        }
        Ok(())
    }
}

/// One planned repair.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
enum Action {
    /// Wake (release) the body and its group.
    Wake(RigidBodyHandle),
    /// Release a held body (an unresponsive one) and as much of its held group as the
    /// body pressing into it can set moving.
    Release(RigidBodyHandle, RigidBodyHandle),
    /// Scale the velocities of the body's group by this factor.
    Damp(RigidBodyHandle, Real),
    /// Stand fewer iterations and deepest contact only down.
    Thicken,
}

/// Counters of the repairs of one step.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RepairCounts {
    /// Groups woken (or released) because a held body lost its support or an awake
    /// body pressed into it.
    pub woken: u64,
    /// Launched groups slowed down.
    pub damped: u64,
    /// Steps in which fewer iterations and deepest contact only stood down for a deep penetration.
    pub thickened: u64,
}

/// The monitor a [`crate::ContactLayer`] owns (see [`crate::MonitorMut::set`]).
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LayerMonitor {
    mode: MonitorMode,
    repair: RepairConfig,
    pub(crate) monitor: Monitor,
    /// Bodies the user pushed since the last analysis (no launch check).
    pub(crate) pushed: Vec<RigidBodyHandle>,
    planned: Vec<Action>,
    /// Bodies released or woken by repair or fixation, with the step their
    /// freshness ends.
    fresh: BTreeMap<(u32, u32), u64>,
    /// Fewer iterations and deepest contact only stand down until this step.
    thick_until: u64,
    /// Rapier's corrective velocity before the cap (restored after it).
    saved_cap: Option<Real>,
    /// Fast bodies of the last analysis with the soft-CCD prediction they get.
    fast_now: Vec<(RigidBodyHandle, Real)>,
    /// Bodies given a soft-CCD prediction, with their own value before.
    predicted: BTreeMap<(u32, u32), (RigidBodyHandle, Real)>,
    totals: RepairCounts,
    /// The step of the last analysis.
    step: u64,
}

impl LayerMonitor {
    pub(crate) fn new(
        mode: MonitorMode,
        config: MonitorConfig,
        repair: RepairConfig,
    ) -> Result<Self> {
        repair.validate()?;
        Ok(Self {
            mode,
            repair,
            monitor: Monitor::new(config)?,
            pushed: Vec::new(),
            planned: Vec::new(),
            fresh: BTreeMap::new(),
            thick_until: 0,
            saved_cap: None,
            fast_now: Vec::new(),
            predicted: BTreeMap::new(),
            totals: RepairCounts::default(),
            step: 0,
        })
    }

    /// The mode.
    pub fn mode(&self) -> MonitorMode {
        self.mode
    }

    /// The repair parameters.
    pub fn repair_config(&self) -> &RepairConfig {
        &self.repair
    }

    /// The detectors (their totals, peaks, last violations). O(1).
    pub fn monitor(&self) -> &Monitor {
        &self.monitor
    }

    /// Repairs since the monitor was set.
    pub fn repairs(&self) -> RepairCounts {
        self.totals
    }

    /// Whether fewer iterations and deepest contact only stand down (a deep penetration was seen within the
    /// last [`RepairConfig::cap_steps`] steps).
    pub fn thinning_suspended(&self) -> bool {
        self.thick_until > self.step
    }

    /// Changes the mode; leaving repair ends the caps at the next pre-step.
    pub(crate) fn set_mode(&mut self, mode: MonitorMode) {
        self.mode = mode;
        if mode != MonitorMode::Repair {
            self.fresh.clear();
            self.planned.clear();
            self.thick_until = 0;
        }
    }

    /// Plans the repairs for what the last check found and appends the events.
    /// `fixation_released` are the bodies this analysis released from the speed-ups'
    /// fixation (given back right after it, or at the next pre-step).
    #[allow(clippy::too_many_arguments)]
    // Long: one planning pass per kind of finding, in the order the module doc lists them.
    pub(crate) fn plan(
        &mut self,
        step: u64,
        graph: &ContactGraph,
        groups: &Groups,
        view: &crate::WorldView,
        refreshed: &[NodeId],
        released_by_speedups: &[RigidBodyHandle],
        events: &mut Vec<Event>,
        want_events: bool,
    ) {
        self.step = step;
        // Fast bodies get a soft-CCD prediction of twice their next step's travel, so
        // that an impact within one step is met by speculative contacts rather than
        // found deep inside its target a step later.
        self.fast_now.clear();
        if self.mode == MonitorMode::Repair {
            for &n in refreshed {
                let Some(h) = graph.body_of(n) else { continue };
                let Some(rb) = view.bodies.get(h).filter(|rb| rb.is_dynamic()) else {
                    continue;
                };
                let travel = rb.linvel().length() * view.dt;
                if travel.is_finite() && travel > self.repair.fast_travel {
                    self.fast_now.push((h, 2.0 * travel));
                }
            }
        }
        let found: &[Violation] = self.monitor.last();
        if want_events {
            for v in found {
                events.extend(monitor_event(step, EventKind::Violation, v, graph));
            }
        }
        self.planned.clear();
        if self.mode != MonitorMode::Repair {
            return;
        }
        let mut repaired: Vec<Violation> = Vec::new();
        // Unsupported held bodies, in handle order.
        let mut held: Vec<(RigidBodyHandle, Real)> = self.monitor.unsupported_held().collect();
        held.sort_by_key(|(h, _)| h.into_raw_parts());
        for (h, seconds) in held {
            self.planned.push(Action::Wake(h));
            repaired.push(Violation {
                step,
                kind: ViolationKind::HangingSleeper,
                body: h,
                node: graph.node_of_body(h),
                value: seconds,
            });
        }
        // Held bodies an awake body presses into: released with their group.
        // The pusher's group is woken too: its rest count starts again, so that a
        // pusher stopped by the held body is not fixated in the same pre-step.
        for &(h, by, value) in self.monitor.pressed_held() {
            let planned = |a: &Action| matches!(a, Action::Release(x, _) if *x == h);
            if self.planned.iter().any(planned) {
                continue;
            }
            self.planned.push(Action::Release(h, by));
            if !self.planned.contains(&Action::Wake(by)) {
                self.planned.push(Action::Wake(by));
            }
            repaired.push(Violation {
                step,
                kind: ViolationKind::Unresponsive,
                body: h,
                node: graph.node_of_body(h),
                value,
            });
        }
        // The early warning: a contact on its way to a deep penetration.
        if let Some((ratio, n)) = self.monitor.last_deepest() {
            if ratio > self.repair.penetration_warning {
                if let Some(body) = graph.body_of(n) {
                    self.planned.push(Action::Thicken);
                    repaired.push(Violation {
                        step,
                        kind: ViolationKind::DeepPenetration,
                        body,
                        node: Some(n),
                        value: ratio,
                    });
                }
            }
        }
        for v in found {
            match v.kind {
                ViolationKind::Launch => {
                    // Take the excess out of the group's kinetic energy.
                    let ke = group_energy(graph, groups, view, v.body);
                    if ke > 0.0 && v.value > 0.0 {
                        let keep = ((ke - v.value) / ke).max(0.0);
                        self.planned.push(Action::Damp(v.body, keep.sqrt()));
                        repaired.push(*v);
                    }
                    // The thinned solver (fewer iterations) is what throws bodies when warm
                    // start over-corrects: full strength for a while.
                    if !self.planned.contains(&Action::Thicken) {
                        self.planned.push(Action::Thicken);
                    }
                }
                ViolationKind::DeepPenetration => {
                    if !self.planned.contains(&Action::Thicken) {
                        self.planned.push(Action::Thicken);
                    }
                    repaired.push(*v);
                }
                ViolationKind::HangingSleeper
                | ViolationKind::Escape
                | ViolationKind::Unresponsive => {}
            }
        }
        // Bodies the speed-ups release get the capped correction too.
        for &h in released_by_speedups {
            self.fresh
                .insert(h.into_raw_parts(), step + self.repair.cap_steps as u64);
        }
        if want_events {
            for v in &repaired {
                events.extend(monitor_event(step, EventKind::Repaired, v, graph));
            }
        }
    }

    /// Applies the planned repairs to the world, before Rapier's step. Returns the
    /// nodes woken (their groups are disturbed by the caller when subgrouping).
    // Long: applies each planned kind of repair in turn within the pre-step's one borrow of the world.
    pub(crate) fn apply(
        &mut self,
        world: &mut WorldMut,
        graph: &ContactGraph,
        groups: &Groups,
        mut speedups: Option<&mut SpeedUpState>,
        mods: &mut crate::logic::hooks::ContactMods,
        woken: &mut Vec<NodeId>,
    ) {
        let step = self.step;
        for action in std::mem::take(&mut self.planned) {
            match action {
                Action::Wake(h) => {
                    self.totals.woken += 1;
                    for (n, m) in group_bodies(graph, groups, h) {
                        if let Some(s) = speedups.as_deref_mut() {
                            s.repair_wake(m, mods);
                        }
                        if let Some(rb) = live_body_mut(world.bodies, m) {
                            if rb.is_dynamic() {
                                rb.wake_up(true);
                            }
                        }
                        self.fresh
                            .insert(m.into_raw_parts(), step + self.repair.cap_steps as u64);
                        woken.push(n);
                    }
                }
                Action::Release(h, by) => {
                    self.totals.woken += 1;
                    let Some(s) = speedups.as_deref_mut() else {
                        continue;
                    };
                    for m in s.repair_release_group(h, by, world, mods) {
                        self.fresh
                            .insert(m.into_raw_parts(), step + self.repair.cap_steps as u64);
                        woken.extend(graph.node_of_body(m));
                    }
                }
                Action::Damp(h, factor) => {
                    self.totals.damped += 1;
                    for (_, m) in group_bodies(graph, groups, h) {
                        if let Some(rb) = live_body_mut(world.bodies, m) {
                            if rb.is_dynamic() {
                                let (v, w) = (rb.linvel(), rb.angvel());
                                rb.set_linvel(v * factor, true);
                                rb.set_angvel(w * factor, true);
                            }
                        }
                    }
                }
                Action::Thicken => {
                    self.totals.thickened += 1;
                    self.thick_until = step + self.repair.cap_steps as u64;
                }
            }
        }
        // Soft-CCD predictions: set for the fast bodies, given back once slow again.
        let fast = std::mem::take(&mut self.fast_now);
        let mut keep: Vec<(u32, u32)> = fast.iter().map(|(h, _)| h.into_raw_parts()).collect();
        keep.sort_unstable();
        let done: Vec<(u32, u32)> = self
            .predicted
            .keys()
            .copied()
            .filter(|k| keep.binary_search(k).is_err())
            .collect();
        for k in done {
            let Some(&(h, own)) = self.predicted.get(&k) else {
                continue;
            };
            // Given back once the body can be written to (or is gone).
            if !world.bodies.contains(h) {
                self.predicted.remove(&k);
            } else if let Some(rb) = live_body_mut(world.bodies, h) {
                rb.set_soft_ccd_prediction(own);
                self.predicted.remove(&k);
            }
        }
        for (h, prediction) in fast {
            if let Some(rb) = live_body_mut(world.bodies, h) {
                let own = self
                    .predicted
                    .entry(h.into_raw_parts())
                    .or_insert((h, rb.soft_ccd_prediction()))
                    .1;
                rb.set_soft_ccd_prediction(own.max(prediction));
            }
        }
        // The capped correction while any released or woken body is fresh.
        self.fresh.retain(|_, until| *until > step);
        let params = &mut *world.integration_parameters;
        if !self.fresh.is_empty() {
            let saved = *self
                .saved_cap
                .get_or_insert(params.normalized_max_corrective_velocity);
            params.normalized_max_corrective_velocity = saved.min(self.repair.corrective_cap);
        } else if let Some(saved) = self.saved_cap.take() {
            params.normalized_max_corrective_velocity = saved;
        }
    }

    /// Undoes what repair mode changed in the world's parameters (when the mode goes
    /// off or the monitor is removed).
    pub(crate) fn restore(&mut self, world: &mut WorldMut) {
        for (_, (h, own)) in std::mem::take(&mut self.predicted) {
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_soft_ccd_prediction(own);
            }
        }
        if let Some(saved) = self.saved_cap.take() {
            world
                .integration_parameters
                .normalized_max_corrective_velocity = saved;
        }
        self.fresh.clear();
        self.planned.clear();
        self.thick_until = 0;
    }
}

/// The event of a violation or repair; `None` for a body without a node (the event
/// layer names nodes).
fn monitor_event(step: u64, kind: EventKind, v: &Violation, graph: &ContactGraph) -> Option<Event> {
    let a = v.node.or_else(|| graph.node_of_body(v.body))?;
    let mut e = Event::plain(step, kind, a, None, Some(v.body), None, 0);
    e.violation = Some(v.kind);
    e.value = v.value;
    Some(e)
}

/// The bodies of `h`'s contact group (just `h` when it has none), with their nodes, in
/// node order.
fn group_bodies(
    graph: &ContactGraph,
    groups: &Groups,
    h: RigidBodyHandle,
) -> Vec<(NodeId, RigidBodyHandle)> {
    let Some(n) = graph.node_of_body(h) else {
        return Vec::new();
    };
    let members: Vec<NodeId> = graph
        .node(n)
        .and_then(|node| node.group())
        .and_then(|g| groups.get(g))
        .map_or_else(|| vec![n], |g| g.bodies.clone());
    members
        .into_iter()
        .filter_map(|m| graph.body_of(m).map(|b| (m, b)))
        .collect()
}

/// The kinetic energy of `h`'s contact group now.
fn group_energy(
    graph: &ContactGraph,
    groups: &Groups,
    view: &crate::WorldView,
    h: RigidBodyHandle,
) -> Real {
    group_bodies(graph, groups, h)
        .into_iter()
        .filter_map(|(_, m)| view.bodies.get(m))
        .filter(|rb| rb.is_dynamic())
        .map(|rb| rb.kinetic_energy())
        .filter(|e| e.is_finite())
        .sum()
}
