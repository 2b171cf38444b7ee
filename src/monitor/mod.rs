//! The plausibility monitor (paper §8, Figs. 15 and 17): detectors for the failures that the paper's
//! speed-ups cause, run once per step after the analysis.
//!
//! # What is detected
//! - **Hanging sleeper** (Fig. 17): a body asleep or held with no supporting touching
//!   contact for longer than [`MonitorConfig::hang_time`] (support as
//!   [`crate::ContactGraph::supports_of`] judges it).
//! - **Launch** (Fig. 15): kinetic energy appearing from nowhere, balanced per contact
//!   group of the step against the work gravity can do
//!   ([`MonitorConfig::launch_relative`]); groups with a kinematic or excepted body
//!   are skipped.
//! - **Deep penetration**: a touching edge of an awake body deeper than
//!   [`MonitorConfig::penetration_fraction`] of the smaller body's size.
//! - **Escape**: a pose or velocity that is not finite, or a body Rapier quarantined
//!   ([`crate::WorldView::quarantined`]).
//! - **Unresponsive**: an awake body pressing into a held body harder across gravity
//!   than resting explains, three steps in a row
//!   ([`MonitorConfig::unresponsive_push`]).
//!
//! Each kind is counted once per *episode* (until the condition clears). Why each
//! test is built this way, and what is not covered: `docs/ARCHITECTURE.md`
//! ("The monitor's detectors"). Call [`Monitor::prime`] before the first step so that
//! the first step's groups get a launch check.
//!
//! # Cost
//! [`Monitor::check`] costs O(refreshed bodies + members of their groups + edges
//! refreshed in the step) plus the open episodes, and O(colliders of a body) once per
//! body for its size; the unresponsive check runs only while bodies are held. A
//! settled scene costs O(1).

mod config;
mod escape;
mod hanging;
mod launch;
mod penetration;
mod repair;
mod unresponsive;
mod violations;

pub use config::MonitorConfig;
pub use repair::{LayerMonitor, MonitorMode, RepairConfig, RepairCounts};
pub use violations::{Peaks, Violation, ViolationCounts};

use rapier3d::math::Real;
use rapier3d::prelude::RigidBodyHandle;

use crate::coherence::{Coherence, RemovedNode};
pub use crate::events::ViolationKind;
use crate::graph::{ContactGraph, NodeId};
use crate::groups::Groups;
use crate::speedups::SpeedUpState;
use crate::{Result, WorldView};

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
mod tests;
