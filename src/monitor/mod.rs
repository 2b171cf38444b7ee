//! The plausibility monitor (paper §8, Figs. 15 and 17): detectors for the failures that the paper's
//! speed-ups cause, run once per step after the analysis.
//!
//! # What is detected, and why this way
//! - **Hanging sleeper** (paper Fig. 17): a *held* body — asleep in Rapier, or held in
//!   place by the caller (fixated: locked axes and zeroed velocity) — with no supporting
//!   touching contact for longer than [`MonitorConfig::hang_time`]. "Supporting" is
//!   the graph's own query ([`crate::ContactGraph::supports_of`]): a touching physical
//!   edge whose normal, as it pushes the body, has more than
//!   [`MonitorConfig::min_support_cos`] of its length along `-gravity` (or a contact
//!   within the support gap that pushes so), read from Rapier's narrow phase. A
//!   body resting on a fixed slope is supported; a body
//!   left in the air when what it rested on rolled away or was removed is not. The
//!   normals of sleeping pairs are frozen in Rapier (and in the graph's caches), so
//!   the query is exact for sleeping bodies too.
//! - **Launch** (paper Fig. 15 ♠: "objects actually fly up in the air … due to
//!   constraint stabilization correcting large errors"): kinetic energy appearing from
//!   nowhere. A literal per-body test ("a body's kinetic energy rose by more than
//!   gravity could give it") fires on every ordinary collision, because a collision
//!   *moves* energy from one body to another. So the balance is taken per contact
//!   group of the step: the bodies of a group are exactly the bodies that exchanged
//!   impulses in the step (Rapier computes contacts at the start of a step and the
//!   graph reads them after it), fixed bodies do no work, and restitution, friction
//!   and damping only remove energy. What is left to create energy in a group is
//!   gravity — bounded by `Σ m·g·Δx` over the step — and the solver's position
//!   correction, which is the failure we look for. Scripted (kinematic) bodies and user
//!   pushes do work too, so groups touching a scripted body or holding a body the caller
//!   excepts are skipped. See [`MonitorConfig::launch_relative`] for the tolerance.
//!   Rapier's own position correction is gentle with its default parameters (soft
//!   contacts, a stabilisation pass that removes the correction velocity, 3 m/s cap):
//!   two 0.5 m boxes created 0.3 m into each other separate at 0.2 m/s, which is not a
//!   launch. Launches come from stiffer settings and from the speed-ups (releasing a
//!   body fixated by extra mass throws what it sank into).
//! - **Deep penetration**: a touching physical edge of an awake body whose deepest
//!   penetration (`cache().max_penetration`, or read from Rapier under touching
//!   tracking) exceeds [`MonitorConfig::penetration_fraction`] of the
//!   smaller body's size; a body's size is the smallest extent of the union of its
//!   (non-sensor) colliders' AABBs *in the body's own frame*, so it does not change as
//!   the body rotates and can be cached.
//! - **Escape**: a body whose pose or velocity is not finite. Rapier 0.36's own NaN
//!   quarantine resets and disables such bodies during its step, so after a step their
//!   pose is finite again: the bodies it reports ([`crate::WorldView::quarantined`])
//!   are counted as escapes too.
//! - **Unresponsive** (a held body that a contact should have moved): an awake
//!   dynamic body pressing into a body held by the speed-ups' fixation harder across
//!   gravity than resting explains. The pusher's contact impulses of the step (normal
//!   and friction) and its weight give what moved it; what is left (its momentum
//!   lost, a user's push), less the part along gravity and as far as it goes into the
//!   held body, over the pusher's weight or load, is compared with
//!   [`MonitorConfig::unresponsive_push`] in three steps in a row (a push is
//!   sustained; the solver's imbalance in a pile at rest flickers). A body pushed slowly into a
//!   held pile (slower than the speed-ups' `release_speed`, so nothing releases it)
//!   is stopped as by a wall where a sleeping Rapier pile would wake and give way.
//!   See `unresponsive.rs` for the measure and what it was chosen over.
//!
//! # Episodes, not steps
//! Every kind is counted once per *episode*, which is what a table of violations
//! wants: a body left hanging for two seconds is one hanging sleeper, not 190. An
//! episode ends when the condition clears (the body is supported or released, the edge
//! is shallow again, the pose is finite again, no awake body presses the held body
//! over the threshold); a launch episode ends at the first step in which the group of
//! the launched bodies gains no excess energy.
//!
//! # Cost
//! Everything is driven by what the analysis refreshed: [`Monitor::check`] costs
//! O(refreshed bodies + members of their groups + edges refreshed in the step) plus
//! the open episodes (bodies being timed as unsupported, deep edges, escaped bodies),
//! and O(colliders of a body) once per body for its size. The unresponsive check runs
//! only while the speed-ups hold a body: O(edges of the refreshed bodies) plus
//! O(contact pairs of the awake bodies touching a held one). A settled scene costs
//! O(1).
//! The per-body state is pruned of removed bodies as the layer reports them, and
//! swept once it grows past twice the world's body count (amortised O(1)).
//!
//! # Not covered
//! - The first step of a body the monitor has not seen has nothing to compare its
//!   energy with, so its group gets no launch check in that step: call
//!   [`Monitor::prime`] before the first step (and [`Monitor::prime_body`] for bodies
//!   inserted later) to cover it.
//! - Energy pumped in by motors, user forces applied with `add_force`, or joints to
//!   kinematic bodies: except those bodies (the `excepted` argument).
//! - Bodies held by the caller are timed only while the layer refreshes them (awake in
//!   Rapier, which a fixated body is) or while they are already being timed; a body
//!   that falls asleep is seen in the step it falls asleep, and one created asleep in
//!   the step it is created.

mod escape;
mod hanging;
mod launch;
mod penetration;
mod repair;
mod unresponsive;

pub use repair::{LayerMonitor, MonitorMode, RepairConfig, RepairCounts};

use rapier3d::math::Real;
use rapier3d::prelude::RigidBodyHandle;

use crate::coherence::{Coherence, RemovedNode};
pub use crate::events::ViolationKind;
use crate::graph::{ContactGraph, NodeId};
use crate::groups::Groups;
use crate::speedups::SpeedUpState;
use crate::{Error, Result, WorldView};

/// Thresholds of the detectors (defaults as defined in `docs/ARCHITECTURE.md` §6).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MonitorConfig {
    /// Seconds a held body may stay without support before it is a hanging sleeper
    /// (strictly longer than this). Default 0.1 s (paper §8, Figs. 15 and 17).
    pub hang_time: Real,
    /// Deepest allowed penetration as a fraction of the smaller body's size. Default 0.1.
    pub penetration_fraction: Real,
    /// Launch tolerance, relative part. Default 0.05.
    ///
    /// A contact group's excess energy in a step (its kinetic energy gain minus the work
    /// gravity did on it) is a launch when it exceeds
    /// `launch_relative · KE_before + launch_per_kg · m`, where `KE_before` and `m` are
    /// the kinetic energy before the step and the mass of the group's *gainers* (the
    /// members whose energy rose by more than gravity's work on them), so that one body
    /// thrown out of a large pile is not diluted by the pile's mass. The relative part
    /// absorbs the integration error of fast groups (a swinging multibody), the
    /// absolute part the solver's slop in slow ones.
    ///
    /// Tuned with Rapier's default parameters on the quiet scenes of
    /// `tests/monitor_detect_hanging.rs`: the largest excess over tolerance seen was 0.35 in
    /// a settling 300-sphere pile (columns of spheres landing on each other; 0.19 J/kg),
    /// 0.22 for the pendulum multibody, 0.12 for the DIKU scene, below 0.001 for bounces
    /// with restitution 0.8 and 1, colliding balls and the toppling stack. A launch by
    /// position correction (two 0.5 m boxes created 0.3 m into each other, Rapier's
    /// stabilisation pass off) measures 2 with Rapier's soft contacts and 130 with
    /// stiff ones (300 Hz, 100 m/s correction cap); releasing a box fixated with
    /// `set_additional_mass(1e6)` measures 33,000. With Rapier's defaults the same
    /// overlap is resolved at 0.2 m/s and measures 0.04: not a launch.
    pub launch_relative: Real,
    /// Launch tolerance, absolute part, in joules per kilogram of the gainers' mass.
    /// Default 0.5 J/kg: the gainers as a whole thrown at 1 m/s from rest. See
    /// [`Self::launch_relative`].
    pub launch_per_kg: Real,
    /// The smallest cosine between a contact's push and `-gravity` that still counts as
    /// support. Default 0.0: any upward component supports (a body on a fixed slope is
    /// supported). Must be in `[0, 1)`.
    pub min_support_cos: Real,
    /// The largest unexplained push an awake body may put on a held (fixated) body
    /// across gravity or up, in three steps in a row: the push its weight and its other
    /// contacts do not explain (its momentum lost, a user's force), in units of its
    /// weight over the step or its load if larger (see the module docs). Default 2.0:
    /// a box driven at 0.3 m/s into a held box (`dt` = 0.01) measures about 3, a box
    /// pushed with a constant force `F` measures `F` over its weight; bodies settling
    /// on a held pile under [`crate::speedups::SpeedUps::reliable_sleep`] stay below
    /// it for three steps in a row.
    #[cfg_attr(feature = "serde", serde(default = "default_unresponsive_push"))]
    pub unresponsive_push: Real,
}

#[cfg(feature = "serde")]
fn default_unresponsive_push() -> Real {
    MonitorConfig::default().unresponsive_push
}

impl Default for MonitorConfig {
    fn default() -> Self {
        Self {
            hang_time: 0.1,
            penetration_fraction: 0.1,
            launch_relative: 0.05,
            launch_per_kg: 0.5,
            min_support_cos: 0.0,
            unresponsive_push: 2.0,
        }
    }
}

impl MonitorConfig {
    /// Checks every field: all must be finite and non-negative, and
    /// `min_support_cos < 1`. An [`Error::InvalidParameter`] names the first bad one.
    pub fn validate(&self) -> Result<()> {
        let fields = [
            ("hang_time", self.hang_time),
            ("penetration_fraction", self.penetration_fraction),
            ("launch_relative", self.launch_relative),
            ("launch_per_kg", self.launch_per_kg),
            ("min_support_cos", self.min_support_cos),
            ("unresponsive_push", self.unresponsive_push),
        ];
        for (name, value) in fields {
            if !value.is_finite() || value < 0.0 {
                return Err(Error::InvalidParameter {
                    name,
                    reason: format!("must be finite and non-negative, got {value}"),
                });
            }
        }
        if self.min_support_cos >= 1.0 {
            return Err(Error::InvalidParameter {
                name: "min_support_cos",
                reason: format!(
                    "must be below 1 (no contact could support), got {}",
                    self.min_support_cos
                ),
            });
        }
        Ok(())
    }
}

/// One reported violation.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Violation {
    /// The layer's step it was found in ([`LayerAnalysis::current_step`](crate::LayerAnalysis::current_step)).
    pub step: u64,
    /// What went wrong.
    pub kind: ViolationKind,
    /// The body it is reported on: the hanging body; the group's body with the largest
    /// kinetic energy gain; the smaller body of a deep contact (the other one if the
    /// smaller is static geometry); the escaped body; the held body an awake body
    /// pressed.
    pub body: RigidBodyHandle,
    /// The body's node, if the graph has one.
    pub node: Option<NodeId>,
    /// The measure: seconds without support; excess energy of the group in joules;
    /// penetration depth in metres; for an escape, the number of non-finite scalars in
    /// the pose (7) and velocities (6) — 0 for a body Rapier's quarantine already reset;
    /// for an unresponsive body, the largest push across gravity on it in units of the
    /// pusher's weight over the step plus its push along gravity.
    pub value: Real,
}

/// Violations per kind.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViolationCounts {
    /// Hanging sleepers.
    pub hanging_sleeper: u64,
    /// Launches.
    pub launch: u64,
    /// Deep penetrations.
    pub deep_penetration: u64,
    /// Escapes.
    pub escape: u64,
    /// Unresponsive held bodies.
    #[cfg_attr(feature = "serde", serde(default))]
    pub unresponsive: u64,
}

impl ViolationCounts {
    /// The count of one kind.
    pub fn get(&self, kind: ViolationKind) -> u64 {
        match kind {
            ViolationKind::HangingSleeper => self.hanging_sleeper,
            ViolationKind::Launch => self.launch,
            ViolationKind::DeepPenetration => self.deep_penetration,
            ViolationKind::Escape => self.escape,
            ViolationKind::Unresponsive => self.unresponsive,
        }
    }

    /// The sum over all kinds.
    pub fn total(&self) -> u64 {
        self.hanging_sleeper + self.launch + self.deep_penetration + self.escape + self.unresponsive
    }

    fn add(&mut self, kind: ViolationKind) {
        match kind {
            ViolationKind::HangingSleeper => self.hanging_sleeper += 1,
            ViolationKind::Launch => self.launch += 1,
            ViolationKind::DeepPenetration => self.deep_penetration += 1,
            ViolationKind::Escape => self.escape += 1,
            ViolationKind::Unresponsive => self.unresponsive += 1,
        }
    }
}

/// The largest values each detector measured since the monitor was created, as a
/// fraction of its threshold (below 1: never fired). For tuning thresholds and for
/// reporting how close a run came to a violation.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Peaks {
    /// Longest time a held body went unsupported, over `hang_time` (0 when
    /// `hang_time` is 0).
    pub hang: Real,
    /// Largest excess energy of a checked group, over its tolerance.
    pub launch: Real,
    /// Largest excess energy of a checked group, in joules.
    pub launch_excess: Real,
    /// Deepest penetration, over `penetration_fraction ×` the smaller body's size.
    pub penetration: Real,
    /// Largest push on a held body across gravity, over `unresponsive_push` (0 when
    /// `unresponsive_push` is 0, and while nothing is held).
    #[cfg_attr(feature = "serde", serde(default))]
    pub unresponsive: Real,
}

/// The plausibility monitor: call [`Monitor::check`] once after each step's analysis.
///
/// A standalone monitor reads the contact details where it needs them: a held body's
/// support from Rapier's narrow phase, the awake bodies' contact depths from the
/// edges' caches under proximity tracking with the details kept and otherwise from
/// Rapier, with the same figures. It judges the same under either tracking, the default
/// included. The layer's own monitor
/// ([`MonitorMut::set`](crate::MonitorMut::set)) does the same.
///
/// # Example
/// ```
/// use rapier3d::prelude::*;
/// use rapier_contact_graph::monitor::{Monitor, MonitorConfig};
/// use rapier_contact_graph::{ContactLayer, WorldView};
///
/// let mut world = PhysicsWorld::new();
/// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
/// world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.5, 0.0)),
///     ColliderBuilder::ball(0.5),
/// );
/// let mut layer = ContactLayer::new();
/// let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
/// for _ in 0..100 {
///     layer.step(&mut world);
///     let found = monitor.check(&layer, &WorldView::from(&world), &|_| false, &|_| false);
///     assert!(found.is_empty());
/// }
/// assert_eq!(monitor.totals().total(), 0);
/// ```
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Monitor {
    config: MonitorConfig,
    hanging: hanging::Hanging,
    launch: launch::Launch,
    penetration: penetration::Penetration,
    escape: escape::Escape,
    #[cfg_attr(feature = "serde", serde(default))]
    unresponsive: unresponsive::Unresponsive,
    found: Vec<Violation>,
    totals: ViolationCounts,
    peaks: Peaks,
    /// The layer step of the last check (`None` before the first).
    last_step: Option<u64>,
}

/// What the monitor reads of a layer's last analysis: the graph, the contact groups,
/// the analysis' record of what it refreshed and removed, and the speed-ups' state.
/// The monitor takes this view, not the layer, so that it sits below the layer
/// (`docs/ARCHITECTURE.md` §2). `LayerAnalysis::view` makes one, and
/// `&ContactLayer` converts into one, so `monitor.check(&layer, ...)` reads as before.
/// Copying it is free (references and a step number).
#[derive(Clone, Copy, Debug)]
pub struct AnalysisView<'a> {
    /// The contact graph.
    pub graph: &'a ContactGraph,
    /// The contact groups.
    pub groups: &'a Groups,
    /// The analysis: refreshed nodes and edges, removed nodes, the step.
    pub coherence: &'a Coherence,
    /// The speed-ups' state, when they are on.
    pub speedups: Option<&'a SpeedUpState>,
}

impl<'a> AnalysisView<'a> {
    /// The contact graph. O(1).
    pub fn graph(&self) -> &'a ContactGraph {
        self.graph
    }

    /// The contact groups. O(1).
    pub fn groups(&self) -> &'a Groups {
        self.groups
    }

    /// The analysis of the last step. O(1).
    pub fn coherence(&self) -> &'a Coherence {
        self.coherence
    }

    /// The speed-ups' state, when they are on. O(1).
    pub fn speedups(&self) -> Option<&'a SpeedUpState> {
        self.speedups
    }

    /// The last analysed step. O(1).
    pub fn current_step(&self) -> u64 {
        self.coherence.step()
    }

    /// The nodes the last analysis removed. O(1).
    pub fn removed_nodes(&self) -> &'a [RemovedNode] {
        self.coherence.removed_nodes()
    }
}

/// What every detector reads in one check.
pub(crate) struct Ctx<'a, 'w> {
    pub layer: AnalysisView<'a>,
    pub view: &'a WorldView<'w>,
    pub step: u64,
    /// A step passed since the last check (false when `check` is called twice for one
    /// layer step: no time passed, so nothing is timed or balanced).
    pub fresh: bool,
    /// The layer step of the previous check.
    pub prev_step: Option<u64>,
}

impl Monitor {
    /// A monitor with the given thresholds; an invalid config is an error
    /// ([`MonitorConfig::validate`]).
    pub fn new(config: MonitorConfig) -> Result<Self> {
        config.validate()?;
        Ok(Self {
            config,
            hanging: Default::default(),
            launch: Default::default(),
            penetration: Default::default(),
            escape: Default::default(),
            unresponsive: Default::default(),
            found: Vec::new(),
            totals: ViolationCounts::default(),
            peaks: Peaks::default(),
            last_step: None,
        })
    }

    /// The thresholds.
    pub fn config(&self) -> &MonitorConfig {
        &self.config
    }

    /// Runs every detector on the layer's last analysed step and returns the
    /// violations found in it, sorted by kind, then body handle (then in the order the
    /// analysis refreshed the edges, for several deep contacts of one body).
    ///
    /// - `held(h)`: the caller holds body `h` in place this step (fixated by a
    ///   speed-up). Bodies asleep in Rapier are held whatever it says.
    /// - `excepted(h)`: the caller pushed body `h` this step (set its velocity, applied
    ///   an impulse or a force): its contact group gets no launch check. A body the
    ///   caller held at the previous check and does not hold now is excepted
    ///   automatically, since releasing a fixated body restores its velocity.
    ///
    /// Call it once after each step ([`ContactLayer::step`](crate::ContactLayer::step) or
    /// [`ContactLayer::analyze`](crate::ContactLayer::analyze)), with the view of the world that was stepped. A
    /// second call for the same layer step times nothing and balances no energy (no
    /// time passed) but re-runs the penetration and escape checks, so a pose corrupted
    /// between steps is seen at once.
    ///
    /// Cost: O(refreshed bodies + members of their contact groups + edges refreshed in
    /// the step + open episodes); see the module docs.
    pub fn check<'a>(
        &mut self,
        layer: impl Into<AnalysisView<'a>>,
        view: &WorldView,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        excepted: &dyn Fn(RigidBodyHandle) -> bool,
    ) -> &[Violation] {
        self.check_with_quarantine(layer.into(), view, held, excepted, view.quarantined)
    }

    /// [`Self::check`] with an explicit list of the bodies Rapier's NaN quarantine
    /// reset and disabled in the step, each an escape (once per episode: a body already
    /// reported escaped is not reported again). [`Self::check`] takes them from
    /// [`WorldView::quarantined`].
    pub fn check_with_quarantine<'a>(
        &mut self,
        layer: impl Into<AnalysisView<'a>>,
        view: &WorldView,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        excepted: &dyn Fn(RigidBodyHandle) -> bool,
        quarantined: &[RigidBodyHandle],
    ) -> &[Violation] {
        let layer = layer.into();
        let step = layer.current_step();
        let ctx = Ctx {
            layer,
            view,
            step,
            fresh: self.last_step != Some(step),
            prev_step: self.last_step,
        };
        self.found.clear();

        // Forget bodies that left the world (what the layer removed this step).
        if ctx.fresh {
            for r in layer.removed_nodes() {
                if let crate::graph::NodeSource::Body(h) = r.source {
                    self.hanging.forget(h);
                    self.launch.forget(h);
                    self.escape.forget(h);
                    self.unresponsive.forget(h);
                }
                self.penetration.forget_node(r.id);
            }
        }

        self.hanging
            .check(&ctx, &self.config, held, &mut self.found, &mut self.peaks);
        self.launch.check(
            &ctx,
            &self.config,
            held,
            excepted,
            &mut self.found,
            &mut self.peaks,
        );
        self.penetration
            .check(&ctx, &self.config, &mut self.found, &mut self.peaks);
        self.escape.check(&ctx, quarantined, &mut self.found);
        self.unresponsive
            .check(&ctx, &self.config, held, &mut self.found, &mut self.peaks);

        // A total order (two deep contacts of one body by their depth), so that the
        // order the detectors met them in, which follows the graph's edge order,
        // does not show.
        self.found.sort_by(|a, b| {
            (a.kind, a.body.into_raw_parts(), a.node)
                .cmp(&(b.kind, b.body.into_raw_parts(), b.node))
                .then(a.value.total_cmp(&b.value))
        });
        for v in &self.found {
            self.totals.add(v.kind);
        }
        self.last_step = Some(step);
        &self.found
    }

    /// Records the state of every dynamic body of the world as it is now, so that the
    /// launch check covers the next step of bodies it has not seen yet. Without it a
    /// body's first analysed step has nothing to compare with and its group is not
    /// checked in that step (the step that throws bodies created overlapping). Call it
    /// before the first step, or see [`Self::prime_body`] for bodies inserted later.
    /// O(bodies).
    pub fn prime(&mut self, view: &WorldView) {
        for (h, _) in view.bodies.iter() {
            self.launch.prime(view, h);
        }
    }

    /// [`Self::prime`] for one body (e.g. just inserted). O(1).
    pub fn prime_body(&mut self, view: &WorldView, body: RigidBodyHandle) {
        self.launch.prime(view, body);
    }

    /// The violations of the last check.
    pub fn last(&self) -> &[Violation] {
        &self.found
    }

    /// The number of violations of the last check.
    pub fn last_count(&self) -> usize {
        self.found.len()
    }

    /// Violations per kind since the monitor was created.
    pub fn totals(&self) -> ViolationCounts {
        self.totals
    }

    /// How close each detector came to firing since the monitor was created.
    pub fn peaks(&self) -> Peaks {
        self.peaks
    }

    /// The deepest contact the last check saw, as a fraction of the deep-penetration
    /// limit (1 is the limit), with a node of one of its bodies (a simulated one if
    /// there is one). `None` when no touching contact was refreshed. O(1).
    pub fn last_deepest(&self) -> Option<(Real, NodeId)> {
        self.penetration.last_deepest
    }

    /// The held bodies being timed as unsupported, with the seconds so far (in no
    /// particular order). A stability repair can wake them before they become
    /// violations. O(bodies timed).
    pub fn unsupported_held(&self) -> impl Iterator<Item = (RigidBodyHandle, Real)> + '_ {
        self.hanging.timed()
    }

    /// The held bodies that an awake body pressed over
    /// [`MonitorConfig::unresponsive_push`] in the last check (the open unresponsive
    /// episodes, reported or not in that check), each as (held body, the body pressing
    /// it hardest, the measure), in handle order. A stability repair releases them.
    /// O(1).
    pub fn pressed_held(&self) -> &[(RigidBodyHandle, RigidBodyHandle, Real)] {
        self.unresponsive.pressed()
    }
}

/// The node kinds the solver moves (the bodies whose energy and support matter).
#[inline]
pub(crate) fn simulated(layer: AnalysisView, n: NodeId) -> Option<RigidBodyHandle> {
    let node = layer.graph().node(n)?;
    if node.kind().is_simulated() {
        node.body()
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_config_is_valid_and_matches_design() {
        let c = MonitorConfig::default();
        c.validate().unwrap();
        assert_eq!(c.hang_time, 0.1);
        assert_eq!(c.penetration_fraction, 0.1);
        assert_eq!(c.unresponsive_push, 2.0);
        assert!(Monitor::new(c).is_ok());
    }

    #[test]
    fn bad_configs_are_refused_by_name() {
        type Edit = fn(&mut MonitorConfig);
        let cases: [(&str, Edit); 9] = [
            ("hang_time", |c| c.hang_time = Real::NAN),
            ("hang_time", |c| c.hang_time = -0.1),
            ("penetration_fraction", |c| {
                c.penetration_fraction = Real::INFINITY
            }),
            ("launch_relative", |c| c.launch_relative = -1.0),
            ("launch_per_kg", |c| c.launch_per_kg = Real::NAN),
            ("min_support_cos", |c| c.min_support_cos = -0.5),
            ("min_support_cos", |c| c.min_support_cos = 1.0),
            ("unresponsive_push", |c| c.unresponsive_push = -1.0),
            ("unresponsive_push", |c| {
                c.unresponsive_push = Real::INFINITY
            }),
        ];
        for (want, edit) in cases {
            let mut c = MonitorConfig::default();
            edit(&mut c);
            match c.validate() {
                Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, want),
                other => panic!("{c:?}: expected an error on {want}, got {other:?}"),
            }
            assert!(Monitor::new(c).is_err());
        }
        let zero = MonitorConfig {
            hang_time: 0.0,
            penetration_fraction: 0.0,
            launch_relative: 0.0,
            launch_per_kg: 0.0,
            min_support_cos: 0.0,
            unresponsive_push: 0.0,
        };
        zero.validate().unwrap();
    }

    #[test]
    fn counts_by_kind() {
        let mut c = ViolationCounts::default();
        c.add(ViolationKind::Launch);
        c.add(ViolationKind::Launch);
        c.add(ViolationKind::Escape);
        c.add(ViolationKind::Unresponsive);
        assert_eq!(c.get(ViolationKind::Launch), 2);
        assert_eq!(c.get(ViolationKind::Escape), 1);
        assert_eq!(c.get(ViolationKind::Unresponsive), 1);
        assert_eq!(c.unresponsive, 1);
        assert_eq!(c.get(ViolationKind::HangingSleeper), 0);
        assert_eq!(c.total(), 4);
        let names: Vec<_> = ViolationKind::ALL.iter().map(|k| k.name()).collect();
        assert_eq!(
            names,
            [
                "hanging_sleeper",
                "launch",
                "deep_penetration",
                "escape",
                "unresponsive"
            ]
        );
    }
}
