//! The layer a Rapier user adds: one call per step keeps the contact graph, the marks
//! and the contact groups in step with the world.
//!
//! # Example
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{ContactLayer, NodeKind};
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.2, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! for _ in 0..60 {
//!     layer.step(&mut world);
//! }
//! let node = layer.graph().try_node_of_body(ball).unwrap();
//! assert_eq!(layer.graph().node(node).unwrap().kind(), NodeKind::Rigid);
//! assert!(layer.is_supported(node).unwrap(), "the ball rests on the ground");
//! layer.validate(&world).unwrap();
//! ```

use crossbeam_channel::Receiver;
use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

use crate::coherence::{Coherence, RemovedNode, Screen, WalkCounters};
use crate::events::{Event, EventBus, Filter, SubscriptionId};
use crate::graph::{Category, ContactGraph, Edge, EdgeId, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::groups::{GroupStats, Groups};
use crate::logic::hooks::HooksView;
use crate::logic::{Logic, Rule, WorldMut};
use crate::monitor::{LayerMonitor, MonitorConfig, MonitorMode, RepairConfig};
use crate::speedups::{SpeedUpState, SpeedUps};
use crate::{Error, Result, WorldView};

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
    /// Bodies awake after the step.
    pub awake_bodies: usize,
    /// What the pair walk read.
    pub walk: WalkCounters,
    /// Group statistics.
    pub groups: GroupStats,
    /// Events generated in the step (before filtering per subscription).
    pub events: usize,
    /// Violations the monitor found in the step (0 with the monitor off; see
    /// [`ContactLayer::set_monitor`]).
    pub violations: usize,
}

/// The contact graph layer.
///
/// Observe-only unless asked: without rules it sets no hook flag on any collider, and
/// the hooks it hands Rapier are then never called, so attaching it changes nothing
/// in Rapier's results (tested bit for bit). Triggers widen the collision types of
/// sensor colliders only (sensors push nothing; see [`Self::set_trigger_widening`]).
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
}

impl Default for ContactLayer {
    fn default() -> Self {
        Self::new()
    }
}

impl ContactLayer {
    /// A layer with an empty graph; the first update fills it from the world.
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
        }
    }

    /// Runs the pre-step ([`Self::pre_step`]), one Rapier step with the layer's hooks,
    /// then the analysis ([`Self::analyze`]).
    ///
    /// Cost: Rapier's step, plus the analysis: O(pairs of awake bodies + members of the
    /// rebuilt groups + events), plus O(bodies + colliders) on a step where their count
    /// changed.
    pub fn step(&mut self, world: &mut PhysicsWorld) -> StepStats {
        self.pre_step(WorldMut::from(&mut *world));
        world.step_with_events(&self.hooks(), &());
        self.analyze(WorldView::from(&*world))
    }

    /// Applies the queued logical changes to the world (hook flags of rule members,
    /// passive bodies, trigger collision types, the speed-ups' fixations), after
    /// checking them against the world as it is now: what Rapier would panic on is
    /// refused or guarded (see [`Self::set_passive`] and [`Self::refusals`]).
    /// [`Self::step`] calls it; users who step Rapier themselves call it before each
    /// step and pass [`Self::hooks`] to Rapier. O(1) when nothing is queued and no body
    /// is passive; O(passive bodies) while some are (their joints are checked when the
    /// world has impulse joints, their multibody membership when it has multibodies).
    pub fn pre_step(&mut self, mut world: WorldMut) {
        let colliders_changed = world.colliders.len() != self.colliders_seen;
        self.colliders_seen = world.colliders.len();
        self.logic.pre_step(
            &self.graph,
            &mut world,
            colliders_changed,
            self.coherence.created_nodes(),
        );
        if let Some(mut m) = self.monitor_restore.take() {
            m.restore(&mut world);
        }
        if let Some(m) = &mut self.monitor {
            let mut woken = Vec::new();
            m.apply(
                &mut world,
                &self.graph,
                &self.groups,
                self.speedups.as_mut(),
                &mut self.logic.hooks.mods,
                &mut woken,
            );
            let suspend = m.thinning_suspended();
            if let Some(s) = &mut self.speedups {
                s.suspend_thinning = suspend;
                if s.config().subgroup {
                    // Woken bodies stop insulating: regroup them.
                    for n in woken {
                        self.groups.disturb(&mut self.graph, n);
                    }
                }
            }
        }
        if let Some(s) = &mut self.speedups {
            s.pre_step(&mut world, &mut self.logic.hooks.mods);
        }
    }

    /// Sets the plausibility monitor ([`crate::monitor`], DESIGN §6) the layer runs
    /// after each analysis: [`MonitorMode::Off`] removes it; [`MonitorMode::Report`]
    /// counts violations ([`StepStats::violations`]) and sends them as
    /// [`crate::events::EventKind::Violation`] events; [`MonitorMode::Repair`] also
    /// acts on them (see [`crate::monitor::LayerMonitor`]). Invalid thresholds are an
    /// error and change nothing. Changing the mode keeps the detectors' totals;
    /// changing the thresholds starts a new monitor. O(1).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.5, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer
    ///     .set_monitor(MonitorMode::Repair, MonitorConfig::default(), RepairConfig::default())
    ///     .unwrap();
    /// for _ in 0..100 {
    ///     assert_eq!(layer.step(&mut world).violations, 0);
    /// }
    /// assert_eq!(layer.monitor().unwrap().monitor().totals().total(), 0);
    /// ```
    pub fn set_monitor(
        &mut self,
        mode: MonitorMode,
        config: MonitorConfig,
        repair: RepairConfig,
    ) -> Result<()> {
        config.validate()?;
        repair.validate()?;
        if mode == MonitorMode::Off {
            if let Some(m) = self.monitor.take() {
                self.monitor_restore = Some(m);
            }
            return Ok(());
        }
        match &mut self.monitor {
            Some(m) if m.monitor.config() == &config && m.repair_config() == &repair => {
                m.set_mode(mode);
            }
            _ => {
                if let Some(old) = self.monitor.take() {
                    self.monitor_restore = Some(old);
                }
                self.monitor = Some(LayerMonitor::new(mode, config, repair)?);
            }
        }
        Ok(())
    }

    /// Whether a body is held in place: fixated by the speed-ups (fixed in Rapier until
    /// released) or asleep in Rapier. This is the `held` a [`crate::monitor::Monitor`]
    /// run outside the layer wants, and what the layer's own monitor uses. O(log
    /// fixated bodies).
    pub fn holds(&self, bodies: &rapier3d::prelude::RigidBodySet, h: RigidBodyHandle) -> bool {
        self.speedups.as_ref().is_some_and(|s| s.is_fixated(h))
            || bodies.get(h).is_some_and(|b| b.is_sleeping())
    }

    /// Primes the monitor's launch check with the world as it is now (see
    /// [`crate::monitor::Monitor::prime`]): call it before the first step. No-op with
    /// the monitor off. O(bodies).
    pub fn prime_monitor(&mut self, view: &WorldView) {
        if let Some(m) = &mut self.monitor {
            m.monitor.prime(view);
        }
    }

    /// The layer's monitor, if it is on. O(1).
    pub fn monitor(&self) -> Option<&LayerMonitor> {
        self.monitor.as_ref()
    }

    /// Tells the monitor that the caller pushed `body` before this step (set its
    /// velocity, applied an impulse or a force): its contact group gets no launch check
    /// in the step's analysis. Stale handles are ignored. O(1).
    pub fn mark_pushed(&mut self, body: RigidBodyHandle) {
        if let Some(m) = &mut self.monitor {
            m.pushed.push(body);
        }
    }

    /// Switches the paper's speed-ups on (`Some`) or off (`None`), at any time. The
    /// configuration is validated first: invalid parameters are an error and change
    /// nothing. See [`crate::speedups`] for what each switch does to the world.
    ///
    /// Switching them off releases fixated bodies and restores the hook flags and
    /// damping the speed-ups changed, in the next pre-step; Rapier's sleep thresholds
    /// go back to Rapier's defaults.
    pub fn set_speedups(&mut self, config: Option<SpeedUps>) -> Result<()> {
        match config {
            Some(c) => {
                c.validate()?;
                let was = self.speedups().map(|s| s.config().subgroup);
                if was.unwrap_or(false) != c.subgroup {
                    self.regroup_all();
                }
                match &mut self.speedups {
                    Some(s) => s.reconfigure(c),
                    None => self.speedups = Some(SpeedUpState::new(c)),
                }
            }
            None => {
                if self.speedups().is_some_and(|s| s.config().subgroup) {
                    self.regroup_all();
                }
                if let Some(s) = &mut self.speedups {
                    s.detach();
                }
            }
        }
        Ok(())
    }

    /// Dissolves every group (their bodies are regrouped at the next analysis), when
    /// what insulates changes. O(groups).
    fn regroup_all(&mut self) {
        let ids: Vec<_> = self.groups.iter().map(|(id, _)| id).collect();
        for id in ids {
            self.groups.dissolve(&mut self.graph, id);
        }
    }

    /// The speed-ups' state, if they are on.
    pub fn speedups(&self) -> Option<&SpeedUpState> {
        self.speedups.as_ref().filter(|s| !s.is_detached())
    }

    /// The physics hooks to give Rapier when stepping it yourself (see
    /// [`HooksView`]). Rapier calls them only for colliders the layer flagged (rule
    /// members, and the colliders a contact speed-up concerns).
    pub fn hooks(&self) -> HooksView<'_> {
        HooksView {
            state: &self.logic.hooks,
            graph: &self.graph,
        }
    }

    /// The post-step analysis alone, for users who step Rapier themselves (their own
    /// `PhysicsPipeline::step` or `PhysicsWorld::step_with_events`). Call it once after
    /// every step.
    pub fn analyze(&mut self, view: WorldView) -> StepStats {
        self.gravity = view.gravity;
        let force = std::mem::take(&mut self.logic.force);
        let screen = Screen {
            rules: self.logic.hooks.table(),
            force: &force,
        };
        self.coherence
            .update(&mut self.graph, &mut self.groups, &view, &screen);
        let step = self.coherence.step();
        for r in self.coherence.removed_nodes() {
            if let NodeSource::Body(h) = r.source {
                self.logic.forget_body(h);
            }
        }

        // Containers follow the joints; bodies whose structure changed are regrouped
        // (and their kind refreshed: multibody links are `Link`s).
        let mut created = Vec::new();
        // Kind changes (a jointed body turned fixed, e.g. by fixation) change which
        // bodies a container holds: resync then.
        let force = self.coherence.kind_changes() > 0;
        let changed = self.logic.containers.sync(
            &mut self.graph,
            &view,
            step,
            &mut created,
            force,
            &mut self.groups,
        );
        for n in changed.into_iter().chain(created) {
            if let Some(h) = self.graph.body_of(n) {
                let mut sink = Vec::new();
                crate::graph::mirror::ensure_body_node(&mut self.graph, &view, h, &mut sink);
            }
            self.groups.disturb(&mut self.graph, n);
        }
        self.coherence
            .take_dropped(&mut self.graph, &mut self.groups);

        if let Some(s) = &mut self.speedups {
            s.track(
                &self.graph,
                &view,
                self.coherence.refreshed_nodes(),
                self.coherence.sleep_changes(),
                &mut self.logic.hooks.mods,
            );
        }
        if let Some(s) = &self.speedups {
            if s.config().subgroup {
                for &h in &s.sleepy_changed {
                    if let Some(n) = self.graph.node_of_body(h) {
                        self.groups.disturb(&mut self.graph, n);
                    }
                }
            }
        }
        let (grouping, subgroup) = match &self.speedups {
            Some(s) if !s.is_detached() => (s.config().groups, s.config().subgroup),
            _ => (true, false),
        };
        if !grouping && !self.groups.is_empty() {
            // Groups switched off: forget them (once).
            let ids: Vec<_> = self.groups.iter().map(|(id, _)| id).collect();
            for id in ids {
                self.groups.dissolve(&mut self.graph, id);
            }
            self.groups.clear_roots();
        }
        if grouping {
            let speedups = self.speedups.as_ref();
            self.groups.rebuild(&mut self.graph, step, &|g, n| {
                let Some(node) = g.node(n) else { return false };
                node.kind().is_insulator()
                    || (subgroup
                        && node
                            .body()
                            .is_some_and(|h| speedups.is_some_and(|s| s.is_sleepy(h))))
            });
            self.groups
                .apply_contact_deltas(&self.graph, self.coherence.touched_edges(), step);
        }
        if let Some(s) = &mut self.speedups {
            s.decide(
                &self.graph,
                &view,
                &self.groups,
                self.coherence.refreshed_nodes(),
                self.coherence.touched_edges(),
                !self.coherence.removed_nodes().is_empty(),
                step,
            );
            if s.is_detached() && s.is_idle() {
                self.speedups = None;
            }
        }

        // The monitor (reads the world; repairs are applied in the next pre-step).
        let mut violations = 0;
        if let Some(mut m) = self.monitor.take() {
            let held = |h: RigidBodyHandle| self.holds(view.bodies, h);
            let pushed = std::mem::take(&mut m.pushed);
            m.monitor.check_with_quarantine(
                self.analysis_view(),
                &view,
                &held,
                &|h| pushed.contains(&h),
                view.quarantined,
            );
            violations = m.monitor.last_count();
            let released: Vec<RigidBodyHandle> = self
                .speedups
                .as_ref()
                .map(|s| s.pending_releases().to_vec())
                .unwrap_or_default();
            self.monitor_events.clear();
            let want = self
                .bus
                .wanted()
                .intersects(crate::events::KindSet::MONITOR);
            m.plan(
                step,
                &self.graph,
                &self.groups,
                &view,
                self.coherence.refreshed_nodes(),
                &released,
                &mut self.monitor_events,
                want,
            );
            self.monitor = Some(m);
        }

        self.ticks.clear();
        if !self.logic.timers.is_empty() {
            self.logic.timers.advance(view.dt, &mut self.ticks);
        }

        self.events.clear();
        if !self.bus.is_empty() {
            let marks = crate::events::collect::StepMarks {
                step,
                graph: &self.graph,
                removed_edges: self.coherence.removed_edges(),
                touched: self.coherence.touched_edges(),
                sleep_changes: self.coherence.sleep_changes(),
                ticks: &self.ticks,
                removed_nodes: self.coherence.removed_nodes(),
            };
            crate::events::collect::collect(&marks, self.bus.wanted(), &mut self.events);
            let wanted = self.bus.wanted();
            self.events.extend(
                self.monitor_events
                    .drain(..)
                    .filter(|e| wanted.contains(e.kind)),
            );
            self.bus.dispatch(&self.events, &self.graph);
        }

        self.stats = StepStats {
            step,
            nodes: self.graph.node_count(),
            edges: self.graph.edge_count(),
            awake_bodies: view.islands.num_active_bodies(),
            walk: self.coherence.counters(),
            groups: self.groups.stats(),
            events: self.events.len(),
            violations,
        };
        self.stats
    }

    // ── Events ─────────────────────────────────────────────────────────

    /// Subscribes to the events matching `filter` on an unbounded channel (see the
    /// contract in [`crate::events`]). O(1).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{events::{EventKind, Filter, KindSet}, ContactLayer};
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.5, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// let touches = layer.subscribe(Filter::kinds(KindSet::of(&[EventKind::TouchBegin])));
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert_eq!(touches.try_iter().count(), 1, "the ball landed once");
    /// ```
    pub fn subscribe(&mut self, filter: Filter) -> Receiver<Event> {
        self.bus.subscribe(filter).1
    }

    /// Subscribes on a channel of at most `capacity` events: when it is full, the newest
    /// events are dropped and counted ([`EventBus::dropped`]); the step never blocks.
    /// A capacity of 0 or above [`crate::events::MAX_CAPACITY`], or a filter naming a
    /// stale node, is an error. O(1).
    pub fn subscribe_bounded(
        &mut self,
        filter: Filter,
        capacity: usize,
    ) -> Result<Receiver<Event>> {
        if let Some(nodes) = filter.nodes() {
            for &n in nodes {
                self.graph.try_node(n)?;
            }
        }
        Ok(self.bus.subscribe_bounded(filter, capacity)?.1)
    }

    /// Subscribes and returns the subscription's id too (to unsubscribe or read its
    /// drop count).
    pub fn subscribe_with_id(&mut self, filter: Filter) -> (SubscriptionId, Receiver<Event>) {
        self.bus.subscribe(filter)
    }

    /// Removes a subscription (dropping the receiver does it too, lazily).
    pub fn unsubscribe(&mut self, id: SubscriptionId) -> bool {
        self.bus.unsubscribe(id)
    }

    /// The subscriptions and their counters.
    pub fn event_bus(&self) -> &EventBus {
        &self.bus
    }

    /// The events generated in the last step (of the kinds some subscription wants).
    pub fn last_events(&self) -> &[Event] {
        &self.events
    }

    // ── Rules ──────────────────────────────────────────────────────────

    fn check_rule_member(&self, n: NodeId) -> Result<()> {
        let node = self.graph.try_node(n)?;
        if node.kind().category() != Category::Physical && node.kind() != NodeKind::Trigger {
            return Err(Error::WrongKind {
                node: n,
                expected: "a body or a trigger (rules apply to those)",
            });
        }
        Ok(())
    }

    /// Adds a rule: a `Rule` node with a logical edge to each body it names. Pairs it
    /// ignores stop interacting at the next step (their bodies are woken so that resting
    /// pairs are released too), and their edges end. Every named node must be live and
    /// a body or trigger, else an error and nothing changes. O(members).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{ContactLayer, Rule};
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (floor, _) = world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let (ghost, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let (f, g) = (layer.node_of_body(floor).unwrap(), layer.node_of_body(ghost).unwrap());
    /// layer.add_rule(Rule::ignore_pair(f, g)).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert!(world.bodies[ghost].translation().y < -1.0, "it fell through the floor");
    /// ```
    pub fn add_rule(&mut self, rule: Rule) -> Result<NodeId> {
        let members = rule.members();
        if members.is_empty() {
            return Err(Error::InvalidParameter {
                name: "rule",
                reason: "names no node".into(),
            });
        }
        for &m in &members {
            self.check_rule_member(m)?;
        }
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Rule, NodeSource::Layer(serial));
        for &m in &members {
            self.graph
                .ensure_edge(node, m, EdgeKind::Logical, self.coherence.step());
        }
        self.logic.rules.insert(node, rule);
        self.logic.rules_changed(&members, &self.graph);
        Ok(node)
    }

    /// Removes a rule; the pairs it ignored interact again from the next step.
    pub fn remove_rule(&mut self, rule: NodeId) -> Result<Rule> {
        let kind = self.graph.try_node(rule)?.kind();
        if kind != NodeKind::Rule {
            return Err(Error::WrongKind {
                node: rule,
                expected: "a rule",
            });
        }
        let r = self
            .logic
            .rules
            .remove(&rule)
            .ok_or(Error::StaleNode(rule))?;
        self.graph.remove_node(rule);
        let members = r.members();
        self.logic.rules_changed(&members, &self.graph);
        Ok(r)
    }

    /// The rule of a rule node.
    pub fn rule(&self, node: NodeId) -> Option<&Rule> {
        self.logic.rules.get(&node)
    }

    /// The number of colliders carrying hook flags set by the layer (0 without rules).
    pub fn flagged_colliders(&self) -> usize {
        self.logic.flagged_colliders()
    }

    // ── Timers ─────────────────────────────────────────────────────────

    /// Adds a timer of `period` simulated seconds; it ticks `TimerTick` events (tick 1
    /// one period after now). A period that is not finite and positive is an error.
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.integration_parameters.dt = 0.01;
    /// let mut layer = ContactLayer::new();
    /// let timer = layer.add_timer(0.25).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert_eq!(layer.timer_ticks(timer).unwrap(), 4);
    /// assert!(layer.add_timer(-1.0).is_err());
    /// ```
    pub fn add_timer(&mut self, period: f64) -> Result<NodeId> {
        if !period.is_finite() || period < crate::logic::MIN_TIMER_PERIOD {
            return Err(Error::InvalidParameter {
                name: "period",
                reason: format!(
                    "must be finite and at least {} s, got {period}",
                    crate::logic::MIN_TIMER_PERIOD
                ),
            });
        }
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Timer, NodeSource::Layer(serial));
        self.logic.timers.add(node, period);
        Ok(node)
    }

    /// Removes a timer.
    pub fn remove_timer(&mut self, timer: NodeId) -> Result<()> {
        let kind = self.graph.try_node(timer)?.kind();
        if kind != NodeKind::Timer || !self.logic.timers.remove(timer) {
            return Err(Error::WrongKind {
                node: timer,
                expected: "a timer",
            });
        }
        self.graph.remove_node(timer);
        Ok(())
    }

    /// The ticks a timer has fired so far.
    pub fn timer_ticks(&self, timer: NodeId) -> Result<u64> {
        self.graph.try_node(timer)?;
        self.logic.timers.ticks(timer).ok_or(Error::WrongKind {
            node: timer,
            expected: "a timer",
        })
    }

    /// The period of a timer.
    pub fn timer_period(&self, timer: NodeId) -> Result<f64> {
        self.graph.try_node(timer)?;
        self.logic.timers.period(timer).ok_or(Error::WrongKind {
            node: timer,
            expected: "a timer",
        })
    }

    /// Simulated seconds analysed while a timer existed (the timers' clock).
    pub fn simulated_time(&self) -> f64 {
        self.logic.timers.time()
    }

    // ── Passive bodies ─────────────────────────────────────────────────

    /// Makes a body passive (or active again) without deallocating it (paper §3.2): it
    /// keeps its node, handle and user data, but takes part in nothing. Rapier's enabled
    /// flag is cleared in the pre-step, its edges end at the next analysis, and no
    /// event names it while passive. Its impulse joints are disabled while it is
    /// passive (`JointEnabled::Disabled`), joints added later included, and enabled
    /// again in the pre-step once both their bodies are active: Rapier 0.36 panics on an
    /// enabled joint between a disabled body and a fixed or disabled one, and its own
    /// `DisabledByAttachedBody` marks are undone whenever the other body is inserted or
    /// enabled. A joint the user disabled stays disabled. O(1).
    ///
    /// # Errors
    /// - [`Error::UnknownBody`] for a body without node (removed, or not analysed yet);
    /// - [`Error::Unsupported`] for `passive = true` on a dynamic multibody member (a
    ///   `Link` node at the last analysis): Rapier 0.36 does not carry a disabled
    ///   multibody member and panics in its next step. The body is left as it is.
    ///
    /// The pre-step checks again what the world holds by then: a queued change for a
    /// body that became a dynamic multibody member meanwhile is refused, and a passive
    /// body that became one is made active again. Both are reported by
    /// [`Self::refusals`] after that pre-step.
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let (ball, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// layer.set_passive(ball, true).unwrap();
    /// layer.step(&mut world);
    /// let node = layer.node_of_body(ball).unwrap(); // same node, same handle
    /// assert!(layer.graph().node(node).unwrap().is_passive());
    /// assert_eq!(layer.graph().node(node).unwrap().degree(), 0);
    /// ```
    pub fn set_passive(&mut self, body: RigidBodyHandle, passive: bool) -> Result<()> {
        let node = self.graph.try_node_of_body(body)?;
        if passive && self.graph.node(node).map(|n| n.kind()) == Some(NodeKind::Link) {
            return Err(Error::Unsupported {
                what: "set_passive(true) on a multibody link",
                reason: "Rapier 0.36 panics in its next step on a disabled multibody \
                         root while its links are enabled, and does not disable a \
                         multibody with its members",
            });
        }
        self.logic.queue_passive(body, node, passive);
        Ok(())
    }

    /// What the last pre-step refused or undid because Rapier 0.36 would panic on it,
    /// each with the body and an [`Error::Unsupported`] saying why: a queued
    /// [`Self::set_passive`] of a body that had become a dynamic multibody member, or a
    /// passive body that the user joined to a multibody (made active again). Empty
    /// almost always; cleared by every pre-step. O(1).
    pub fn refusals(&self) -> &[(RigidBodyHandle, Error)] {
        &self.logic.refusals
    }

    // ── Containers ─────────────────────────────────────────────────────

    /// Declares bodies rigidly attached by the user (not by Rapier joints) as a
    /// `Composite` node with structural edges to them: contact groups then treat them as
    /// one. Members must be live dynamic bodies (`Rigid`), else an error. O(members).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// let a = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5)).0;
    /// let b = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 0.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// ).0;
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let (na, nb) = (layer.node_of_body(a).unwrap(), layer.node_of_body(b).unwrap());
    /// layer.declare_composite(&[na, nb]).unwrap();
    /// layer.step(&mut world);
    /// let group = |n| layer.graph().node(n).unwrap().group();
    /// assert_eq!(group(na), group(nb), "one group through the composite");
    /// ```
    pub fn declare_composite(&mut self, bodies: &[NodeId]) -> Result<NodeId> {
        if bodies.is_empty() {
            return Err(Error::InvalidParameter {
                name: "bodies",
                reason: "a composite needs at least one body".into(),
            });
        }
        for &b in bodies {
            let kind = self.graph.try_node(b)?.kind();
            if kind != NodeKind::Rigid {
                return Err(Error::WrongKind {
                    node: b,
                    expected: "a dynamic rigid body",
                });
            }
        }
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Composite, NodeSource::Layer(serial));
        for &b in bodies {
            self.graph
                .ensure_edge(node, b, EdgeKind::Structural, self.coherence.step());
            self.groups.disturb(&mut self.graph, b);
        }
        self.logic.declared.insert(node, bodies.to_vec());
        Ok(node)
    }

    /// Removes a declared composite (not one derived from joints).
    pub fn remove_composite(&mut self, composite: NodeId) -> Result<()> {
        self.graph.try_node(composite)?;
        let members = self
            .logic
            .declared
            .remove(&composite)
            .ok_or(Error::WrongKind {
                node: composite,
                expected: "a declared composite",
            })?;
        if let Some(g) = self.graph.node(composite).and_then(|n| n.group()) {
            self.groups.dissolve(&mut self.graph, g);
        }
        self.graph.remove_node(composite);
        for b in members {
            self.groups.disturb(&mut self.graph, b);
        }
        Ok(())
    }

    /// Widens the collision types of sensor colliders to all body-type pairs (the
    /// default, so triggers on fixed, kinematic and dynamic bodies see bodies of every
    /// type), or leaves sensors as the user built them (`false`; set before the first
    /// step).
    ///
    /// Widening happens in the pre-step before a sensor's first Rapier step. Rapier
    /// pairs colliders that do not move only when they appear, so a sensor that was
    /// stepped before the layer saw it does not see fixed bodies already inside it;
    /// attach the layer before the first step, or build such sensors with
    /// `ActiveCollisionTypes::all()`.
    pub fn set_trigger_widening(&mut self, on: bool) {
        self.logic.widen_sensors = on;
    }

    /// The contact graph.
    pub fn graph(&self) -> &ContactGraph {
        &self.graph
    }

    /// The contact groups.
    pub fn groups(&self) -> &Groups {
        &self.groups
    }

    /// The statistics of the last step.
    pub fn stats(&self) -> StepStats {
        self.stats
    }

    /// The index of the last analysed step.
    pub fn current_step(&self) -> u64 {
        self.coherence.step()
    }

    /// Edges refreshed in the last step (their marks are valid), in the deterministic
    /// order of [`Coherence::touched_edges`].
    pub fn touched_edges(&self) -> impl Iterator<Item = (EdgeId, &Edge)> + '_ {
        self.coherence
            .touched_edges()
            .iter()
            .filter_map(|&id| Some((id, self.graph.edge(id)?)))
    }

    /// Edges removed in the last step with a node that left the world, each with a
    /// final `Vanished` mark for the state it had.
    pub fn removed_edges(&self) -> &[Edge] {
        self.coherence.removed_edges()
    }

    /// Nodes removed in the last step.
    pub fn removed_nodes(&self) -> &[RemovedNode] {
        self.coherence.removed_nodes()
    }

    /// Counters and lists of the last analysis.
    pub fn coherence(&self) -> &Coherence {
        &self.coherence
    }

    /// What the plausibility monitor reads of the last analysis (graph, groups,
    /// analysis, speed-ups). O(1).
    pub fn analysis_view(&self) -> crate::monitor::AnalysisView<'_> {
        crate::monitor::AnalysisView {
            graph: &self.graph,
            groups: &self.groups,
            coherence: &self.coherence,
            speedups: self.speedups(),
        }
    }

    /// The analysis state, for its settings ([`Coherence::set_scan_policy`], ...).
    pub fn coherence_mut(&mut self) -> &mut Coherence {
        &mut self.coherence
    }

    /// Turns the per-edge contact details on (the default) or off; see
    /// [`Coherence::set_contact_details`]. A scene that needs only the marks, the
    /// touching state and the groups pays less per contact pair with them off.
    /// Support queries need the details (the contact normals).
    pub fn set_contact_details(&mut self, on: bool) {
        self.coherence.set_contact_details(on);
    }

    /// Asks for a full scan of bodies and colliders at the next update, which also
    /// reads every node's pairs and every trigger again. Needed only after changing a
    /// *sleeping, fixed or passive* body, or static geometry, in place in a way Rapier
    /// does not wake it for (its type, moving a fixed body or a parentless collider, a
    /// sensor flag); adding and removing bodies and colliders is detected, and so is a
    /// moved trigger. That update costs O(nodes + pairs).
    pub fn request_full_sync(&mut self) {
        self.coherence.request_full_sync();
    }

    /// The node of a body. O(1).
    pub fn node_of_body(&self, body: RigidBodyHandle) -> Result<NodeId> {
        self.graph.try_node_of_body(body)
    }

    /// The node of a collider: the trigger node of a sensor, else its parent body's
    /// node, or its own for a parentless collider. O(1).
    pub fn node_of_collider(
        &self,
        world: &PhysicsWorld,
        collider: ColliderHandle,
    ) -> Result<NodeId> {
        let c = world
            .colliders
            .get(collider)
            .ok_or(crate::Error::UnknownCollider(collider))?;
        if let Some(t) = self.graph.node_of_sensor(collider) {
            return Ok(t);
        }
        match c.parent() {
            Some(b) => self.graph.try_node_of_body(b),
            None => self
                .graph
                .node_of_static_collider(collider)
                .ok_or(crate::Error::UnknownCollider(collider)),
        }
    }

    /// Whether a node is supported against the gravity of the last analysed world
    /// (see [`ContactGraph::try_is_supported`]; any upward push counts). O(degree).
    pub fn is_supported(&self, node: NodeId) -> Result<bool> {
        self.graph.try_is_supported(node, self.gravity, 0.0)
    }

    /// Whether `node` is of a given kind; an error for a stale id. O(1).
    pub fn kind_of(&self, node: NodeId) -> Result<NodeKind> {
        Ok(self.graph.try_node(node)?.kind())
    }

    /// Checks every invariant: the graph's own ([`ContactGraph::validate`]), the
    /// groups', and the graph against the world — one node per body and per static
    /// collider with the right kind, an edge with proximity for every Rapier pair of
    /// two nodes that Table 2 allows, the touching state equal to Rapier's, and no
    /// proximate edge without its Rapier pair. O(nodes + edges + Rapier pairs).
    pub fn validate(&self, world: &PhysicsWorld) -> Result<()> {
        crate::validate::validate_layer(self, &WorldView::from(world))
    }

    /// Whether groups are computed (the `groups` switch of the speed-ups; on without
    /// speed-ups).
    pub fn grouping(&self) -> bool {
        match self.speedups() {
            Some(s) => s.config().groups,
            None => true,
        }
    }

    /// Whether a node insulates groups: fixed and scripted bodies, and sleepy bodies
    /// under subgrouping.
    pub fn insulates(&self, n: NodeId) -> bool {
        let Some(node) = self.graph.node(n) else {
            return false;
        };
        node.kind().is_insulator()
            || match self.speedups() {
                Some(s) if s.config().subgroup => node.body().is_some_and(|h| s.is_sleepy(h)),
                _ => false,
            }
    }

    /// The rules in force (for validation).
    pub(crate) fn rule_table(&self) -> &crate::logic::RuleTable {
        self.logic.hooks.table()
    }

    /// [`Self::validate`] for a world given by its parts.
    pub fn validate_view(&self, view: &WorldView) -> Result<()> {
        crate::validate::validate_layer(self, view)
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
