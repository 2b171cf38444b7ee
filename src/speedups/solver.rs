//! The solver's side of the speed-ups: the iterations (`fewer_iterations`), contact recycling and
//! warm start (cache) over the user's own parameters, linear damping (`viscous_damping`), and the
//! `modify_solver_contacts` flags (`deepest_contact_only`, `no_restitution_at_rest`); the configuration part of the
//! pre-step.

use std::collections::BTreeMap;

use rapier3d::prelude::{ActiveHooks, ColliderHandle, RigidBodyHandle};

use super::sleep::{never_activation, remember_activation};
use super::{key, SpeedUpState, SpeedUps};
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;

impl SpeedUpState {
    /// The colliders flagged for contact modification, with their former flags.
    pub(crate) fn modify_flagged(&self) -> &BTreeMap<(u32, u32), (ColliderHandle, ActiveHooks)> {
        &self.flagged
    }

    /// Flags exactly the colliders `want` (sorted) for contact modification, taking
    /// the flag off the others flagged before. O(flagged + want · log).
    pub(super) fn set_modify_flags(&mut self, world: &mut WorldMut, want: &[ColliderHandle]) {
        let current: Vec<(u32, u32)> = self.flagged.keys().copied().collect();
        for k in current {
            let keep = want
                .binary_search_by_key(&k, |c| c.into_raw_parts())
                .is_ok();
            if !keep {
                if let Some((ch, _)) = self.flagged.get(&k).copied() {
                    self.flag_one(world, ch, false);
                }
            }
        }
        for &ch in want {
            self.flag_one(world, ch, true);
        }
    }

    /// Adds (`on`) or takes back the contact-modification flag of one collider,
    /// leaving the user's own flag as it was. O(log flagged).
    fn flag_one(&mut self, world: &mut WorldMut, ch: ColliderHandle, on: bool) {
        let k = ch.into_raw_parts();
        let Some(col) = world.colliders.get_mut(ch) else {
            self.flagged.remove(&k);
            return;
        };
        if on {
            self.flagged.entry(k).or_insert((ch, col.active_hooks()));
            let f = col.active_hooks() | ActiveHooks::MODIFY_SOLVER_CONTACTS;
            if f != col.active_hooks() {
                col.set_active_hooks(f);
            }
        } else if let Some((_, original)) = self.flagged.remove(&k) {
            let f = (col.active_hooks() - ActiveHooks::MODIFY_SOLVER_CONTACTS)
                | (original & ActiveHooks::MODIFY_SOLVER_CONTACTS);
            if f != col.active_hooks() {
                col.set_active_hooks(f);
            }
        }
    }

    /// Sets the solver's iterations, contact recycling and warm start from the
    /// configuration (recording the user's own the first time), and the contact
    /// modifications' switches. O(1).
    pub(super) fn apply_solver_params(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        c: &SpeedUps,
    ) {
        let params = &mut *world.integration_parameters;
        if self.user_params.is_none() {
            self.user_params = Some((
                params.num_solver_iterations,
                params.contact_recycling,
                params.warmstart_coefficient,
            ));
        }
        // The monitor's repair of a contact going deep: the solver at full strength
        // for a while (no fewer iterations, no deepest-contact-only, warm start and recycling on, twice the
        // iterations).
        let thin = !self.suspend_thinning;
        // The user's own iterations: as recorded, or as the user set them since the
        // layer last wrote them.
        let mut user_iterations = params.num_solver_iterations;
        if let Some(p) = &mut self.user_params {
            if self
                .iterations_written
                .is_some_and(|w| w != params.num_solver_iterations)
            {
                p.0 = params.num_solver_iterations;
            }
            user_iterations = p.0;
        }
        let base = c.iterations.unwrap_or(user_iterations);
        params.num_solver_iterations = if !thin {
            base.saturating_mul(2)
        } else if c.fewer_iterations {
            c.fewer_iterations_count
        } else {
            base
        };
        self.iterations_written = Some(params.num_solver_iterations);
        // The user's own recycling and warm start: as recorded, or as the user set
        // them since the layer last wrote them.
        if let (Some(p), Some(written)) = (&mut self.user_params, self.cache_written) {
            if written.0 != params.contact_recycling {
                p.1 = params.contact_recycling;
            }
            if written.1.to_bits() != params.warmstart_coefficient.to_bits() {
                p.2 = params.warmstart_coefficient;
            }
        }
        let cache = c.cache || !thin;
        // On: the user's own recycling and warm start (recorded above), or both fully
        // on for the monitor's repair; off: both off.
        let (recycling, warmstart) = match self.user_params {
            Some((_, recycling, warmstart)) if thin => (recycling, warmstart),
            _ => (true, 1.0),
        };
        params.contact_recycling = cache && recycling;
        params.warmstart_coefficient = if cache { warmstart } else { 0.0 };
        self.cache_written = Some((params.contact_recycling, params.warmstart_coefficient));
        mods.deepest_contact_depth =
            (c.deepest_contact_only && thin).then_some(c.deepest_contact_depth);
        mods.no_restitution_at_rest = c.no_restitution_at_rest;
    }

    /// Applies the configuration to every body and collider when it or the body or
    /// collider count changed (O(bodies + colliders)), else the no-restitution flags of the
    /// bodies whose sleepy state changed (O(their colliders)). Returns whether the
    /// counts changed.
    pub(super) fn apply_config_to_bodies(&mut self, world: &mut WorldMut, c: &SpeedUps) -> bool {
        let counts_changed = world.bodies.len() != self.known_bodies
            || world.colliders.len() != self.known_colliders;
        if self.dirty || counts_changed {
            let dynamic = self.configure_bodies(world, c);
            self.flag_bodies(world, c, &dynamic);
        } else if c.no_restitution_at_rest && !c.deepest_contact_only && !self.zero_flags.is_empty()
        {
            self.flag_zero_changes(world);
        }
        self.zero_flags.clear();
        counts_changed
    }

    /// Every dynamic body never sleep-eligible unless the layer said so, and damped
    /// (or given its damping back); the dynamic bodies, in handle order.
    /// O(bodies · log).
    fn configure_bodies(&mut self, world: &mut WorldMut, c: &SpeedUps) -> Vec<RigidBodyHandle> {
        self.dirty = false;
        self.known_bodies = world.bodies.len();
        self.known_colliders = world.colliders.len();
        let bodies = &*world.bodies;
        self.activations.retain(|_, (h, _)| bodies.contains(*h));
        let mut dynamic: Vec<RigidBodyHandle> = world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        dynamic.sort_by_key(|h| key(*h));
        for &h in &dynamic {
            let eligible = self.rest_of(h).is_some_and(|r| r.eligible);
            let rb = &mut world.bodies[h];
            // The layer owns sleeping: never eligible unless it says so.
            if !eligible {
                remember_activation(&mut self.activations, h, rb);
                never_activation(rb.activation_mut());
            }
            if c.viscous_damping {
                self.damped
                    .entry(key(h))
                    .or_insert((h, rb.linear_damping()));
                if rb.linear_damping() != c.damping {
                    rb.set_linear_damping(c.damping);
                }
            }
        }
        if !c.viscous_damping {
            self.undamp(world);
        }
        dynamic
    }

    /// Gives the damped bodies their own linear damping back. O(damped).
    pub(super) fn undamp(&mut self, world: &mut WorldMut) {
        for (_, (h, original)) in std::mem::take(&mut self.damped) {
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_linear_damping(original);
            }
        }
    }

    /// The contact-modification flag on the colliders of the `dynamic` bodies (`deepest_contact_only`)
    /// or of the sleepy ones (`no_restitution_at_rest`), off every other. O(their colliders · log).
    fn flag_bodies(&mut self, world: &mut WorldMut, c: &SpeedUps, dynamic: &[RigidBodyHandle]) {
        // Reduce: the contact-modification flag on every dynamic collider.
        let mut want: Vec<ColliderHandle> = Vec::new();
        if c.deepest_contact_only {
            for &h in dynamic {
                want.extend(world.bodies[h].colliders().iter().copied());
            }
        }
        if c.no_restitution_at_rest {
            for &h in dynamic {
                if self.is_sleepy(h) {
                    want.extend(world.bodies[h].colliders().iter().copied());
                }
            }
        }
        want.sort_by_key(|c| c.into_raw_parts());
        want.dedup();
        self.set_modify_flags(world, &want);
        self.zero_flags.clear();
    }

    /// The no-restitution flag on or off the colliders of the bodies whose sleepy state changed.
    /// O(their colliders · log).
    fn flag_zero_changes(&mut self, world: &mut WorldMut) {
        for (h, on) in std::mem::take(&mut self.zero_flags) {
            let Some(rb) = world.bodies.get(h) else {
                continue;
            };
            let colliders: Vec<ColliderHandle> = rb.colliders().to_vec();
            for ch in colliders {
                self.flag_one(world, ch, on);
            }
        }
    }
}
