//! The speed-ups (paper §7) and the plausibility monitor (§8) switched on the layer,
//! and the hooks object the layer hands Rapier.

use rapier3d::prelude::RigidBodyHandle;

use crate::logic::hooks::HooksView;
use crate::monitor::{LayerMonitor, MonitorConfig, MonitorMode, RepairConfig};
use crate::speedups::{SpeedUpState, SpeedUps};
use crate::{Result, WorldView};

use super::ContactLayer;

/// The speed-ups switched on, off or reconfigured: [`ContactLayer::speedups_mut`]
/// (read them with [`ContactLayer::speedups`]).
#[derive(Debug)]
pub struct SpeedUpsMut<'a> {
    layer: &'a mut ContactLayer,
}

/// The layer's plausibility monitor set and fed: [`ContactLayer::monitor_mut`] (read
/// it with [`ContactLayer::monitor`]).
#[derive(Debug)]
pub struct MonitorMut<'a> {
    layer: &'a mut ContactLayer,
}

impl SpeedUpsMut<'_> {
    /// Switches the paper's speed-ups on (`Some`) or off (`None`), at any time. The
    /// configuration is validated first: invalid parameters are an error and change
    /// nothing. See [`crate::speedups`] for what each switch does to the world.
    ///
    /// Switching them off releases fixated bodies and restores the hook flags,
    /// damping, sleep thresholds and solver parameters the speed-ups changed to the
    /// user's own, in the next pre-step (see [`crate::speedups::SpeedUps`] for every
    /// setting a preset changes). O(1), plus O(groups) when the subgrouping switch
    /// changes (the groups are rebuilt at the next analysis).
    pub fn set(&mut self, config: Option<SpeedUps>) -> Result<()> {
        match config {
            Some(c) => {
                c.validate()?;
                let was = self.layer.speedups().map(|s| s.config().insulate_sleepy);
                if was.unwrap_or(false) != c.insulate_sleepy {
                    self.layer.regroup_all();
                }
                match &mut self.layer.speedups {
                    Some(s) => s.reconfigure(c),
                    None => self.layer.speedups = Some(SpeedUpState::new(c)),
                }
            }
            None => {
                if self
                    .layer
                    .speedups()
                    .is_some_and(|s| s.config().insulate_sleepy)
                {
                    self.layer.regroup_all();
                }
                if let Some(s) = &mut self.layer.speedups {
                    s.detach();
                }
            }
        }
        Ok(())
    }
}

impl MonitorMut<'_> {
    /// Sets the plausibility monitor ([`crate::monitor`], paper §8) the layer runs
    /// after each analysis: [`MonitorMode::Off`] removes it; [`MonitorMode::Report`]
    /// counts violations ([`StepStats::violations`](crate::StepStats::violations)) and sends them as
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
    ///     .monitor_mut()
    ///     .set(MonitorMode::Repair, MonitorConfig::default(), RepairConfig::default())
    ///     .unwrap();
    /// for _ in 0..100 {
    ///     assert_eq!(layer.step(&mut world).violations, 0);
    /// }
    /// assert_eq!(layer.monitor().unwrap().monitor().totals().total(), 0);
    /// ```
    pub fn set(
        &mut self,
        mode: MonitorMode,
        config: MonitorConfig,
        repair: RepairConfig,
    ) -> Result<()> {
        config.validate()?;
        repair.validate()?;
        if mode == MonitorMode::Off {
            if let Some(m) = self.layer.monitor.take() {
                self.layer.monitor_restore = Some(m);
            }
            return Ok(());
        }
        match &mut self.layer.monitor {
            Some(m) if m.monitor.config() == &config && m.repair_config() == &repair => {
                m.set_mode(mode);
            }
            _ => {
                if let Some(old) = self.layer.monitor.take() {
                    self.layer.monitor_restore = Some(old);
                }
                self.layer.monitor = Some(LayerMonitor::new(mode, config, repair)?);
            }
        }
        Ok(())
    }

    /// Primes the monitor's launch check with the world as it is now (see
    /// [`crate::monitor::Monitor::prime`]): call it before the first step. No-op with
    /// the monitor off. O(bodies).
    pub fn prime<'w>(&mut self, world: impl Into<WorldView<'w>>) {
        if let Some(m) = &mut self.layer.monitor {
            m.monitor.prime(&world.into());
        }
    }

    /// Tells the monitor that the caller pushed `body` before this step (set its
    /// velocity, applied an impulse or a force): its contact group gets no launch check
    /// in the step's analysis. Stale handles are ignored. O(1).
    pub fn mark_pushed(&mut self, body: RigidBodyHandle) {
        if let Some(m) = &mut self.layer.monitor {
            m.pushed.push(body);
        }
    }
}

impl ContactLayer {
    /// The speed-ups switched on, off or reconfigured (see [`SpeedUpsMut`]). O(1).
    pub fn speedups_mut(&mut self) -> SpeedUpsMut<'_> {
        SpeedUpsMut { layer: self }
    }

    /// The plausibility monitor set, primed and told of pushes (see [`MonitorMut`]).
    /// O(1).
    pub fn monitor_mut(&mut self) -> MonitorMut<'_> {
        MonitorMut { layer: self }
    }

    /// The layer's monitor, if it is on: its detectors' totals
    /// (`monitor().map(|m| m.monitor().totals())`), mode and repairs. O(1).
    pub fn monitor(&self) -> Option<&LayerMonitor> {
        self.monitor.as_ref()
    }

    /// Dissolves every group (their bodies are regrouped at the next analysis), when
    /// what insulates changes. O(groups).
    fn regroup_all(&mut self) {
        let ids: Vec<_> = self.groups.iter().map(|(id, _)| id).collect();
        for id in ids {
            self.groups.dissolve(&mut self.graph, id);
        }
    }

    /// Whether the speed-ups hold `h` by fixation now, switched off or not (they give
    /// their bodies back at the next pre-step). O(log held).
    pub(crate) fn fixates(&self, h: RigidBodyHandle) -> bool {
        self.speedups.as_ref().is_some_and(|s| s.is_fixated(h))
    }

    /// The speed-ups' state, if they are on: configuration, held and sleepy bodies.
    /// O(1).
    pub fn speedups(&self) -> Option<&SpeedUpState> {
        self.speedups.as_ref().filter(|s| !s.is_detached())
    }

    /// The physics hooks to give Rapier when stepping it yourself (see
    /// [`HooksView`]). Rapier calls them only for colliders the layer flagged (rule
    /// members, and the colliders a contact speed-up concerns). O(1) to make.
    pub fn hooks(&self) -> HooksView<'_> {
        HooksView {
            state: &self.logic.hooks,
            graph: &self.graph,
        }
    }

    /// The layer's hooks together with the user's own, for users who step Rapier
    /// themselves: the user's hooks are called for exactly the pairs the user flagged,
    /// the layer's rules and speed-ups act where the layer flagged (see
    /// [`HooksWith`](crate::logic::hooks::HooksWith) for the contract). Pass it to
    /// Rapier's step with [`Self::event_handler_with`]. O(1) to make.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};
    ///
    /// struct NoBounce; // the user's own hooks
    /// impl PhysicsHooks for NoBounce {
    ///     fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
    ///         if let Some(m) = ctx.rigid_mut() {
    ///             *m.restitution = 0.0;
    ///         }
    ///     }
    /// }
    ///
    /// let mut world = PhysicsWorld::new();
    /// let mut layer = ContactLayer::new();
    /// let events = (); // the user's own event handler
    /// layer.pre_step(WorldMut::from(&mut world));
    /// world.step_with_events(&layer.hooks_with(&NoBounce), &layer.event_handler_with(&events));
    /// layer.analyze(WorldView::from(&world));
    /// ```
    pub fn hooks_with<'a, H: rapier3d::pipeline::PhysicsHooks + ?Sized>(
        &'a self,
        user: &'a H,
    ) -> crate::logic::hooks::HooksWith<'a, H> {
        crate::logic::hooks::HooksWith {
            layer: self.hooks(),
            rule_flagged: self.logic.rule_flagged(),
            modify_flagged: self.speedups.as_ref().map(|s| s.modify_flagged()),
            user,
        }
    }
}
