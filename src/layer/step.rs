//! One step of the layer: the pre-step (queued logical changes, timers, speed-up
//! decisions applied), Rapier's step with the layer's hooks, and the analysis
//! (paper §3, §5, Fig. 11), with the events sent at its end (§4's safe point).

use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle};

use crate::coherence::Screen;
use crate::graph::NodeSource;
use crate::logic::WorldMut;
use crate::WorldView;

use super::{ContactLayer, StepStats};

impl ContactLayer {
    /// Runs the pre-step ([`Self::pre_step`]), one Rapier step with the layer's hooks,
    /// then the analysis ([`Self::analyze`]), and gives back at once the held bodies
    /// the analysis released (see [`LayerAnalysis::given_back`](super::LayerAnalysis::given_back)):
    /// a hand-written loop gives them back at its next pre-step instead, with the
    /// same result unless the user writes to the world in between (Rapier handles
    /// the bodies written before a step in the order they were written).
    ///
    /// Cost: Rapier's step, plus the analysis: O(pairs of awake bodies + events) (with
    /// touching tracking O(awake bodies + touch events)), plus the groups' changes
    /// (O(smaller group) per merge, a bounded local search per ended touch, O(members)
    /// of a rebuilt group), plus O(bodies + colliders) on a step where their count
    /// changed, plus the round-robin verification's few slots
    /// ([`crate::coherence::Coherence::verify_budget`]). An idle step (nothing awake, no
    /// change: see the `coherence` module docs) costs O(1) beyond that and the watches
    /// no Rapier list replaces (held bodies' static supporters, joints), plus, while
    /// the speed-ups hold bodies, O(held) to find those the user wrote to.
    pub fn step(&mut self, world: &mut PhysicsWorld) -> StepStats {
        // This step hands Rapier the layer's event handler: touching tracking may
        // start with it (see `Tracking`).
        self.coherence.set_feed_connected(true);
        self.pre_step(WorldMut::from(&mut *world));
        world.step_with_events(&self.hooks(), self.event_handler());
        let stats = self.analyze(WorldView::from(&*world));
        // The releases just decided are given back now rather than at the next
        // pre-step: the step that first solves the released bodies then pays Rapier's
        // part of a release alone, and this step, whose pile stood still, the rest.
        self.apply_decided(&mut WorldMut::from(&mut *world));
        stats
    }

    /// Applies the speed-ups' decisions of the last analysis that need no pre-step
    /// (sleep eligibility, releases), before anything else the next step writes
    /// ([`Self::step`] right after its analysis, a hand-written loop at the start of
    /// its pre-step). O(decisions · log held).
    fn apply_decided(&mut self, world: &mut WorldMut) {
        if let Some(s) = &mut self.speedups {
            let passive = &self.logic.passive;
            s.apply_decided(world, &mut self.logic.hooks.mods, &|h| {
                passive.contains_key(&h.into_raw_parts())
            });
        }
    }

    /// Applies the queued logical changes to the world (hook flags of rule members,
    /// passive bodies, trigger collision types, the speed-ups' fixations), after
    /// checking them against the world as it is now: what Rapier would panic on is
    /// refused or guarded (see
    /// [`LayerLogicMut::set_body_disabled`](super::LayerLogicMut::set_body_disabled) and
    /// [`LayerLogic::refusals`](super::LayerLogic::refusals)).
    /// [`Self::step`] calls it; users who step Rapier themselves call it before each
    /// step and pass [`Self::hooks`] to Rapier. O(1) when nothing is queued and no body
    /// is passive; O(passive bodies) while some are (their joints are checked when the
    /// world has impulse joints, their multibody membership when it has multibodies).
    ///
    /// It first gives back the held bodies the last analysis released and writes its
    /// sleep decisions, unless [`Self::step`] did already. O(those decisions).
    ///
    /// It also tells whether Rapier stepped since the last analysis without the
    /// layer (the user's own `world.step()`, another layer's step): the next
    /// analysis then reads the world in full once and reports
    /// `StepStats::walk.unseen_step` (`docs/ARCHITECTURE.md`, "Steps the layer did not
    /// see", lists the supported loops). O(1) for that look.
    pub fn pre_step(&mut self, mut world: WorldMut) {
        self.coherence
            .check_unseen_step(world.bodies, world.islands);
        // Before the layer writes anything: a held body flagged now was written by the user.
        if let Some(s) = &mut self.speedups {
            s.release_written(world.bodies, self.coherence.unseen_step_pending());
        }
        self.apply_decided(&mut world);
        // The collision-event flags, once touching tracking was asked for, are kept
        // while the layer's handler reaches Rapier's step, whatever the tracking in
        // effect: a flag written to a collider Rapier has stepped counts as a change
        // to Rapier and alters the order it handles pairs in, so flags are written
        // before a collider's first step and not taken off when proximity tracking
        // takes over (only when the handler no longer reaches the step, and at
        // `detach`). A layer that only ever tracked proximity sets none.
        let flagged = !self.coherence.touch_flagged().is_empty();
        let wanted = self.coherence.requested_tracking() == crate::coherence::Tracking::Touching;
        let keep = self.coherence.feed_connected() && (wanted || flagged);
        if keep || flagged {
            self.coherence.sync_touch_flags(world.colliders, keep);
        }
        let colliders_changed = world.colliders.len() != self.colliders_seen;
        self.colliders_seen = world.colliders.len();
        let speedups = self.speedups.as_ref();
        self.logic.pre_step(
            &self.graph,
            &mut world,
            colliders_changed,
            self.coherence.created_nodes(),
            &|h| speedups.is_some_and(|s| s.is_fixated(h)),
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
                if s.config().insulate_sleepy {
                    // Woken bodies stop insulating: regroup them.
                    for n in woken {
                        self.groups.membership_changed(n);
                    }
                }
            }
        }
        if let Some(s) = &mut self.speedups {
            let passive = &self.logic.passive;
            s.pre_step(&mut world, &mut self.logic.hooks.mods, &|h| {
                passive.contains_key(&h.into_raw_parts())
            });
        }
    }

    /// Gives the world back as the user left it, and drops the layer. Everything the
    /// layer changed in the world is undone at once, and nothing else:
    /// - the speed-ups' held bodies are dynamic again with their velocities; the
    ///   dampings, sleep thresholds and solver parameters (iterations, contact
    ///   recycling, warm start) are the user's own again;
    /// - the monitor's changes are undone (as when it is switched off);
    /// - the flags the layer added (rule hooks, `MODIFY_SOLVER_CONTACTS`,
    ///   `COLLISION_EVENTS`) are taken off: only those bits, so flags the user set
    ///   since stay; sensors' collision types are the user's again where they are
    ///   still as the layer set them;
    /// - bodies made passive are enabled again, with the joints held disabled for
    ///   them.
    ///
    /// What the simulation did meanwhile (poses, velocities, sleep, a monitor's
    /// repairs) stays: it is the world's state, not a setting. Tested by recording
    /// every collider's and body's settings before attaching, running rules, triggers,
    /// every speed-up and the monitor, and comparing after `detach`
    /// (`tests/detach_restores_the_world.rs`). O(bodies + colliders).
    ///
    /// Detach after changing the world, right before the next step. Each write goes
    /// through `ColliderSet::get_mut` (Rapier has no other), which puts the collider
    /// in Rapier's list of modified colliders for the next step, in collider order;
    /// a collider the user changes after `detach` keeps that place in the list, and
    /// Rapier handles the list in order, so the next steps can differ in their last
    /// bits from a world never layered. Changes made before `detach` keep their
    /// order.
    pub fn detach(mut self, mut world: WorldMut) {
        if let Some(s) = &mut self.speedups {
            s.detach();
            let passive = &self.logic.passive;
            s.pre_step(&mut world, &mut self.logic.hooks.mods, &|h| {
                passive.contains_key(&h.into_raw_parts())
            });
        }
        if let Some(mut m) = self.monitor_restore.take() {
            m.restore(&mut world);
        }
        if let Some(mut m) = self.monitor.take() {
            m.restore(&mut world);
        }
        self.coherence.sync_touch_flags(world.colliders, false);
        self.logic.release(&self.graph, &mut world);
    }

    /// The post-step analysis alone, for users who step Rapier themselves (their own
    /// `PhysicsPipeline::step` or `PhysicsWorld::step_with_events`). Call it once after
    /// every step. Cost: as [`Self::step`]'s analysis.
    pub fn analyze(&mut self, view: WorldView) -> StepStats {
        self.gravity = view.gravity;
        let force = std::mem::take(&mut self.logic.force);
        let screen = Screen {
            rules: self.logic.hooks.table(),
            force: &force,
        };
        match &self.speedups {
            Some(s) => self.coherence.set_parking(s.parking(), s.parked_now()),
            None => self.coherence.set_parking(std::iter::empty(), &[]),
        }
        // Touching tracking: the transitions Rapier sent to the layer's event handler,
        // if it was handed out for this step. If not, nothing says what changed: the
        // update then tracks proximity, which reads everything once.
        let lent = self
            .feed_lent
            .swap(false, std::sync::atomic::Ordering::Relaxed);
        let mut touch_events = std::mem::take(&mut self.touch_events);
        self.touch_feed.drain(&mut touch_events);
        // (A step whose pre-step set no flags is still tracked by touching when the
        // feed reached it: the switch reads the touching pairs once.)
        let touch = (lent && self.touching_wanted()).then_some(touch_events.as_slice());
        self.coherence.set_feed_connected(lent);
        if let Some(s) = &self.speedups {
            self.coherence.mark_held(&mut self.graph, &s.hold_changes);
        }
        self.coherence
            .update(&mut self.graph, &mut self.groups, &view, &screen, touch);
        // Under proximity tracking the flags (kept, see the pre-step) still bring
        // Rapier's events: unused, they are not kept.
        if self.coherence.tracking() != crate::coherence::Tracking::Touching {
            touch_events.clear();
        }
        self.touch_events = touch_events;
        if let Some(s) = &mut self.speedups {
            let changes = std::mem::take(&mut s.hold_changes);
            self.coherence.note_hold_changes(&mut self.graph, &changes);
        }
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
            if s.config().insulate_sleepy {
                for &h in &s.sleepy_changed {
                    if let Some(n) = self.graph.node_of_body(h) {
                        self.groups.membership_changed(n);
                    }
                }
            }
        }
        let grouping = self.grouping();
        if !grouping {
            // Groups switched off: forget them (once), and the step's queued changes.
            if !self.groups.is_empty() {
                let ids: Vec<_> = self.groups.iter().map(|(id, _)| id).collect();
                for id in ids {
                    self.groups.dissolve(&mut self.graph, id);
                }
            }
            self.groups.clear_queued();
        }
        if grouping {
            let speedups = self.speedups.as_ref();
            self.groups.update(
                &mut self.graph,
                step,
                &|g, n| insulates(g, n, speedups),
                self.coherence.touched_edges(),
            );
        }
        // The removed edges' records are the groups' alone.
        self.graph.left.clear();
        if let Some(s) = &mut self.speedups {
            let changes = crate::speedups::StepChanges {
                refreshed: self.coherence.refreshed_nodes(),
                touched: self.coherence.touched_edges(),
                removed: self.coherence.removed_edges(),
                nodes_removed: !self.coherence.removed_nodes().is_empty(),
                step,
            };
            s.decide(&self.graph, &view, &self.groups, &changes);
            // The contacts the decided fixations will freeze, read while Rapier
            // still has them.
            let fixing: Vec<_> = s
                .pending_fixations()
                .filter_map(|h| self.graph.node_of_body(h))
                .collect();
            if !fixing.is_empty() {
                crate::coherence::held::keep_frozen_details(&mut self.graph, &view, &fixing);
            }
            // The flags Rapier's step left: not the user's.
            s.note_flags(view.bodies);
            if s.is_detached() && s.is_idle() {
                self.speedups = None;
            }
        }

        // The monitor (reads the world; repairs are applied in the next pre-step).
        let mut violations = 0;
        if let Some(mut m) = self.monitor.take() {
            // Held in place by the layer: the speed-ups' fixated bodies (a body asleep
            // in Rapier is the monitor's own look).
            let held = |h: RigidBodyHandle| self.fixates(h);
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
                view: &view,
                details: self.coherence.details_kept(),
            };
            // Touching tracking keeps no proximity edges and reads no unchanged pair:
            // no proximity or persist events.
            let wanted = match self.coherence.tracking() {
                crate::coherence::Tracking::Touching => self
                    .bus
                    .wanted()
                    .without(crate::events::KindSet::NEEDS_EVERY_PAIR),
                crate::coherence::Tracking::Proximity => self.bus.wanted(),
            };
            crate::events::collect::collect(&marks, wanted, &mut self.events);
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
            awake_bodies: self.coherence.integrated_bodies(),
            walk: self.coherence.counters(),
            groups: self.groups.stats(),
            events: self.events.len(),
            violations,
        };
        self.stats
    }
}

/// Whether node `n` insulates groups: fixed and scripted bodies, and sleepy bodies
/// under subgrouping (speed-ups on and not being detached).
pub(super) fn insulates(
    g: &crate::ContactGraph,
    n: crate::NodeId,
    speedups: Option<&crate::speedups::SpeedUpState>,
) -> bool {
    let Some(node) = g.node(n) else { return false };
    node.kind().is_insulator()
        || speedups.is_some_and(|s| {
            !s.is_detached()
                && s.config().insulate_sleepy
                && node.body().is_some_and(|h| s.is_sleepy(h))
        })
}
