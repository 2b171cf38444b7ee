//! The speed-ups' life: created, reconfigured, detached, and the world given back
//! as the user had it once they are switched off.

use std::collections::BTreeMap;

use rapier3d::math::Vector;
use rapier3d::prelude::RigidBodyHandle;

use super::{SpeedUpState, SpeedUpStats, SpeedUps};
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;

impl SpeedUpState {
    /// A new state for `config`: the first pre-step applies it to the whole world.
    pub(crate) fn new(config: SpeedUps) -> Self {
        Self {
            config,
            dirty: true,
            known_bodies: usize::MAX,
            known_colliders: usize::MAX,
            rest: Vec::new(),
            eligibility: Vec::new(),
            to_fix: Vec::new(),
            to_release: Vec::new(),
            later: Vec::new(),
            to_park: Vec::new(),
            unparked: Default::default(),
            flagged_before_user: Vec::new(),
            bodies_noted: 0,
            parking_now: Vec::new(),
            parked_now: Vec::new(),
            hold_changes: Vec::new(),
            held: BTreeMap::new(),
            unsupported: Default::default(),
            rest_based: Default::default(),
            support_partial_ok: false,
            support_dirty: true,
            released: Vec::new(),
            newly_held: Vec::new(),
            dependents: Default::default(),
            linked: Default::default(),
            support_up: Vector::ZERO,
            support_watch: Vec::new(),
            suspend_thinning: false,
            flagged: BTreeMap::new(),
            zero_flags: Vec::new(),
            damped: BTreeMap::new(),
            activations: BTreeMap::new(),
            user_params: None,
            iterations_written: None,
            cache_written: None,
            stats: SpeedUpStats::default(),
            sleepy_changed: Vec::new(),
            waves: Default::default(),
            held_boxes: Default::default(),
            detached: false,
            restored: false,
        }
    }

    /// Switches to `config`: the next pre-step applies it to the whole world.
    pub(crate) fn reconfigure(&mut self, config: SpeedUps) {
        self.config = config;
        self.dirty = true;
        self.detached = false;
        self.restored = false;
    }

    /// Switches the speed-ups off: the next pre-step restores the world.
    pub(crate) fn detach(&mut self) {
        self.detached = true;
        self.restored = false;
    }

    /// Whether the speed-ups are switched off.
    pub(crate) fn is_detached(&self) -> bool {
        self.detached
    }

    /// Detached and the world restored: the state can be dropped.
    pub(crate) fn is_idle(&self) -> bool {
        self.detached && self.restored
    }

    /// Undoes everything the speed-ups changed in the world.
    pub(super) fn restore(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        self.held_boxes = Default::default();
        for (_, held) in std::mem::take(&mut self.held) {
            held.give_back(world, user_passive);
            self.hold_changes.push((held.handle, true));
        }
        self.dependents.clear();
        self.linked.clear();
        self.set_modify_flags(world, &[]);
        self.undamp(world);
        // The user's own sleep thresholds and solver parameters, as they were.
        for (_, (h, [linear, angular, time])) in std::mem::take(&mut self.activations) {
            if let Some(rb) = world.bodies.get_mut(h) {
                let a = rb.activation_mut();
                a.normalized_linear_threshold = linear;
                a.angular_threshold = angular;
                a.time_until_sleep = time;
            }
        }
        self.iterations_written = None;
        self.cache_written = None;
        if let Some((iterations, recycling, warmstart)) = self.user_params.take() {
            let p = &mut *world.integration_parameters;
            p.num_solver_iterations = iterations;
            p.contact_recycling = recycling;
            p.warmstart_coefficient = warmstart;
        }
        mods.deepest_contact_depth = None;
        mods.no_restitution_at_rest = false;
        mods.sleepy.clear();
        self.rest.clear();
        self.eligibility.clear();
        self.to_fix.clear();
        self.to_release.clear();
        self.later.clear();
        self.to_park.clear();
        self.unparked.clear();
        self.parking_now.clear();
        self.parked_now.clear();
        self.unsupported.clear();
        self.rest_based.clear();
        self.released.clear();
        self.support_partial_ok = false;
        self.zero_flags.clear();
        self.restored = true;
    }

    /// The configuration.
    pub fn config(&self) -> &SpeedUps {
        &self.config
    }

    /// The counters of the last step.
    pub fn stats(&self) -> SpeedUpStats {
        self.stats
    }
}
