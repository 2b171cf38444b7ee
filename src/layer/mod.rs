//! The layer a Rapier user adds: one call per step keeps the contact graph, the marks
//! and the contact groups in step with the world.
//!
//! `ContactLayer`'s `impl` is split across files by task, as Rapier splits
//! `impl NarrowPhase` by phase:
//! - `step.rs`: `step`, `pre_step`, `analyze`, `detach` (paper §3, §5, Fig. 11);
//! - `queries.rs`: the graph, groups, nodes of Rapier handles, tracking, the event
//!   handler, `validate`;
//! - `by_handle.rs`: queries by Rapier handle (what touches a body, what holds it
//!   up, whether it is grounded, what is inside a sensor, a body's group);
//! - `events.rs`: subscriptions (§4, Table 3);
//! - `logic.rs`: the views `logic()` / `logic_mut()`: rules, timers, passive bodies,
//!   containers, trigger widening (§3.2);
//! - `speedups.rs`: `speedups_mut()` and `monitor_mut()`, the speed-ups (§7), the
//!   monitor (§8), and the hooks Rapier calls;
//! - `analysis.rs`: the views `analysis()` / `analysis_mut()`: what the last
//!   analysis read and found, and how it reads.

use crate::coherence::{Coherence, WalkCounters};
use crate::events::{Event, EventBus};
use crate::graph::{ContactGraph, NodeId};
use crate::groups::{GroupStats, Groups};
use crate::logic::Logic;
use crate::monitor::LayerMonitor;
use crate::speedups::SpeedUpState;

mod analysis;
mod by_handle;
mod events;
mod logic;
mod queries;
mod speedups;
mod step;

pub use analysis::{LayerAnalysis, LayerAnalysisMut};
pub use by_handle::Touching;
pub use logic::{LayerLogic, LayerLogicMut, RuleMember};
pub use speedups::{MonitorMut, SpeedUpsMut};

/// Statistics of one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StepStats {
    /// The step's index (1 for the first analysed step).
    pub step: u64,
    /// Live nodes.
    pub nodes: usize,
    /// Live edges.
    pub edges: usize,
    /// Bodies Rapier integrated in the step: its active set without the fixed bodies
    /// it keeps there (held bodies not yet out of it, see [`crate::speedups`]).
    pub awake_bodies: usize,
    /// What the pair walk read.
    pub walk: WalkCounters,
    /// Group statistics.
    pub groups: GroupStats,
    /// Events generated in the step (before filtering per subscription).
    pub events: usize,
    /// Violations the monitor found in the step (0 with the monitor off; see
    /// [`MonitorMut::set`]).
    pub violations: usize,
}

/// The contact graph layer: one call per step ([`Self::step`], or [`Self::pre_step`],
/// Rapier's step with [`Self::hooks`], then [`Self::analyze`]) keeps the contact
/// graph, the marks and the contact groups in step with a Rapier world.
///
/// # Example
/// ```
/// use rapier3d::prelude::*;
/// use rapier_contact_graph::{ContactLayer, NodeKind};
///
/// let mut world = PhysicsWorld::new();
/// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
/// let (ball, _) = world.insert(
///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.2, 0.0)),
///     ColliderBuilder::ball(0.5),
/// );
/// let mut layer = ContactLayer::new();
/// for _ in 0..60 {
///     layer.step(&mut world);
/// }
/// // Who touches the ball, and what holds it up, by Rapier handle.
/// assert_eq!(layer.touching_body(&world.bodies, ball).unwrap().len(), 1);
/// let supports = layer.supports_of_body(&world, ball, 0.0).unwrap();
/// assert_eq!(supports.len(), 1, "the ball rests on the ground");
/// assert!(layer.is_grounded(&world, ball).unwrap());
/// let node = layer.node_of_body(&world.bodies, ball).unwrap();
/// assert_eq!(layer.graph().node(node).unwrap().kind(), NodeKind::Dynamic);
/// layer.validate(&world).unwrap();
/// ```
///
/// # Methods by task
/// - **Stepping:** [`Self::step`]; or [`Self::pre_step`], Rapier's step with
///   [`Self::hooks`] / [`Self::hooks_with`] and [`Self::event_handler`] /
///   [`Self::event_handler_with`], then [`Self::analyze`]; [`Self::detach`] gives the
///   world back as the user left it. [`Self::set_tracking`] (or
///   [`Self::with_tracking`]) chooses how contacts are followed.
/// - **Who touches what, by Rapier handle:** [`Self::touching_body`],
///   [`Self::supports_of_body`], [`Self::is_grounded`], [`Self::contact_details`],
///   [`Self::sensor_contents`], [`Self::sensors_containing`],
///   [`Self::group_of_body`]; [`Self::last_events_of_body`].
/// - **Events:** [`Self::subscribe`], [`Self::subscribe_bounded`],
///   [`Self::subscribe_with_id`], [`Self::unsubscribe`], [`Self::last_events`].
/// - **The graph and its groups, by node** (for what has no Rapier handle):
///   [`Self::graph`], [`Self::groups`], and the bridges [`Self::node_of_body`] and
///   [`Self::node_of_collider`], checked against the world.
/// - **Checking and saving:** [`Self::validate`], [`Self::snapshot`],
///   [`Self::restore`], [`Self::restore_with`].
/// - **Rules, timers, passive bodies, composites, trigger widening:** the views
///   [`Self::logic`] ([`LayerLogic`]) and [`Self::logic_mut`] ([`LayerLogicMut`]),
///   e.g. `layer.logic_mut().ignore_pair(&world, a, b)`.
/// - **Speed-ups and the monitor:** [`Self::speedups`] and [`Self::speedups_mut`]
///   ([`SpeedUpsMut`]), [`Self::monitor`] and [`Self::monitor_mut`]
///   ([`MonitorMut`]).
/// - **Diagnostics and tuning:** [`Self::analysis`] ([`LayerAnalysis`]: statistics,
///   the step's edge and node changes, subscription counters, the held predicate)
///   and [`Self::analysis_mut`] ([`LayerAnalysisMut`]: pair walk, per-edge details,
///   group split budget and settling, full rescan).
///
/// A handle or world the layer cannot answer for is an [`Error`](crate::Error),
/// each its own: another world's sets `ForeignWorld`, a removed body `UnknownBody`,
/// a body inserted since the last step `UnseenBody` (or an empty answer where the
/// query says so), a collider that is not a sensor `NotASensor`.
///
/// Observe-only unless asked: without rules it sets no hook flag on any collider, and
/// the hooks it hands Rapier are then never called, so attaching it changes nothing
/// in Rapier's results (tested bit for bit). Under touching tracking (the default) it
/// adds `ActiveEvents::COLLISION_EVENTS` to colliders (which changes no result, and
/// `detach` takes off); sensors' collision types are widened only on request
/// ([`LayerLogicMut::set_trigger_widening`]).
#[derive(Debug)]
pub struct ContactLayer {
    graph: ContactGraph,
    groups: Groups,
    coherence: Coherence,
    logic: Logic,
    bus: EventBus,
    stats: StepStats,
    /// The gravity of the last analysed world.
    gravity: rapier3d::math::Vector,
    colliders_seen: usize,
    ticks: Vec<(NodeId, u64)>,
    events: Vec<Event>,
    speedups: Option<SpeedUpState>,
    monitor: Option<LayerMonitor>,
    monitor_events: Vec<Event>,
    /// Set when the monitor goes off: the next pre-step undoes its repairs' changes.
    monitor_restore: Option<LayerMonitor>,
    /// The event handler given to Rapier: the step's touch transitions (touching
    /// tracking).
    touch_feed: crate::coherence::TouchFeed,
    /// Scratch: the drained touch transitions.
    touch_events: Vec<crate::coherence::TouchEvent>,
    /// Set when the layer's event handler is handed out (or [`Self::step`] runs);
    /// taken by the analysis: the feed reached Rapier's step (see
    /// [`crate::coherence::Tracking`]). Atomic so that `event_handler(&self)` can set
    /// it and the layer stays `Sync`.
    feed_lent: std::sync::atomic::AtomicBool,
}

impl Default for ContactLayer {
    fn default() -> Self {
        Self::new()
    }
}

impl ContactLayer {
    /// A layer with an empty graph and the given tracking ([`Self::set_tracking`]):
    /// `ContactLayer::with_tracking(Tracking::Proximity)` for a layer read by the
    /// graph's node-based detail queries, which read every pair's details copied each
    /// step (the by-handle queries, the speed-ups and a
    /// [`Monitor`](crate::monitor::Monitor) read Rapier instead, under either
    /// tracking). O(1).
    pub fn with_tracking(tracking: crate::coherence::Tracking) -> Self {
        let mut layer = Self::new();
        layer.set_tracking(tracking);
        layer
    }

    /// A layer with an empty graph; the first update fills it from the world. It
    /// tracks touching contacts from Rapier's events where it can (see
    /// [`Tracking`](crate::coherence::Tracking)). O(1).
    pub fn new() -> Self {
        Self {
            graph: ContactGraph::default(),
            groups: Groups::default(),
            coherence: Coherence::default(),
            logic: Logic::new(),
            bus: EventBus::default(),
            stats: StepStats::default(),
            gravity: rapier3d::math::Vector::ZERO,
            colliders_seen: 0,
            ticks: Vec::new(),
            events: Vec::new(),
            speedups: None,
            monitor: None,
            monitor_events: Vec::new(),
            monitor_restore: None,
            touch_feed: Default::default(),
            touch_events: Vec::new(),
            feed_lent: Default::default(),
        }
    }
}

#[cfg(feature = "serde")]
impl ContactLayer {
    /// A copy of the layer's state without its subscriptions (see
    /// [`crate::snapshot`]). O(state).
    pub(crate) fn to_state(&self) -> crate::snapshot::LayerState {
        crate::snapshot::LayerState {
            graph: self.graph.clone(),
            groups: self.groups.clone(),
            coherence: self.coherence.clone(),
            logic: self.logic.clone(),
            bus: crate::snapshot::SavedBus(self.bus.without_subscriptions()),
            stats: self.stats,
            gravity: self.gravity,
            colliders_seen: self.colliders_seen,
            ticks: self.ticks.clone(),
            events: self.events.clone(),
            speedups: self.speedups.clone(),
            monitor: self.monitor.clone(),
            monitor_events: self.monitor_events.clone(),
            monitor_restore: self.monitor_restore.clone(),
        }
    }

    /// The layer of a checked state. O(1).
    pub(crate) fn from_state(s: crate::snapshot::LayerState) -> Self {
        Self {
            graph: s.graph,
            groups: s.groups,
            coherence: s.coherence,
            logic: s.logic,
            bus: s.bus.0,
            stats: s.stats,
            gravity: s.gravity,
            colliders_seen: s.colliders_seen,
            ticks: s.ticks,
            events: s.events,
            speedups: s.speedups,
            monitor: s.monitor,
            monitor_events: s.monitor_events,
            monitor_restore: s.monitor_restore,
            touch_feed: Default::default(),
            touch_events: Vec::new(),
            feed_lent: Default::default(),
        }
    }
}

impl<'a> From<&'a ContactLayer> for crate::monitor::AnalysisView<'a> {
    fn from(layer: &'a ContactLayer) -> Self {
        layer.analysis_view()
    }
}

impl<'a> From<&'a mut ContactLayer> for crate::monitor::AnalysisView<'a> {
    fn from(layer: &'a mut ContactLayer) -> Self {
        (&*layer).analysis_view()
    }
}

#[cfg(test)]
mod tests {
    use rapier3d::prelude::*;

    use super::ContactLayer;

    /// A ground and a column of boxes that topples onto it: groups keep changing.
    fn toppling_column() -> PhysicsWorld {
        let mut world = PhysicsWorld::new();
        world.insert(
            RigidBodyBuilder::fixed(),
            ColliderBuilder::cuboid(10.0, 0.5, 10.0),
        );
        for i in 0..4 {
            world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(
                    0.1 * i as f32,
                    1.0 + 1.05 * i as f32,
                    0.0,
                )),
                ColliderBuilder::cuboid(0.5, 0.5, 0.5),
            );
        }
        world
    }

    #[test]
    fn a_traversal_stamp_at_the_end_of_its_range_starts_again_with_the_same_groups() {
        let (mut wrapped, mut plain) = (toppling_column(), toppling_column());
        let (mut a, mut b) = (ContactLayer::new(), ContactLayer::new());
        for _ in 0..5 {
            a.step(&mut wrapped);
            b.step(&mut plain);
        }
        // The traversal stamp one short of the end of its range.
        a.groups.set_stamp(u64::MAX - 1);
        for _ in 0..200 {
            a.step(&mut wrapped);
            b.step(&mut plain);
            a.validate(&wrapped).unwrap();
            let members = |l: &ContactLayer| {
                let mut v: Vec<Vec<_>> = l.groups().iter().map(|(_, g)| g.bodies.clone()).collect();
                v.sort();
                v
            };
            assert_eq!(members(&a), members(&b));
        }
    }

    #[cfg(feature = "serde")]
    #[test]
    fn a_restored_step_count_near_the_end_of_its_range_is_refused() {
        let mut world = toppling_column();
        let mut layer = ContactLayer::new();
        layer.step(&mut world);
        let mut snapshot = layer.snapshot(&world);
        snapshot
            .state_mut()
            .coherence
            .set_step_for_test(u64::MAX - 1);
        let err = ContactLayer::restore(&snapshot, &world).unwrap_err();
        assert!(err.to_string().contains("step count"), "{err}");
    }
}
