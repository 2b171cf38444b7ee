//! The operations a Rapier user does behind the layer's back: their own calls on any
//! body, held or parked ones included ([`Op::User`]); steps of Rapier the layer does
//! not see ([`Op::Unseen`]); a second layer on the same world taking turns with the
//! first ([`Op::Second`]). What Rapier itself would panic on is skipped (each place
//! says why).
//!
//! [`Op::User`]: super::Op::User
//! [`Op::Unseen`]: super::Op::Unseen
//! [`Op::Second`]: super::Op::Second

use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, WorldMut};

use super::ops::{pick, raw, vel};
use super::oracle::touching_agrees;
use super::{Asked, Call, Config, Harness, Second, Who};

/// Every sensor's collision types, in slot order.
fn sensor_types(world: &PhysicsWorld) -> Vec<(ColliderHandle, ActiveCollisionTypes)> {
    world
        .colliders
        .iter()
        .filter(|(_, c)| c.is_sensor())
        .map(|(h, c)| (h, c.active_collision_types()))
        .collect()
}

impl Harness {
    /// The body a user's call goes to: parked, held or any, each falling back to the
    /// next when there is none.
    fn target(&self, who: Who) -> Option<RigidBodyHandle> {
        let all: Vec<RigidBodyHandle> = self.world.bodies.iter().map(|(h, _)| h).collect();
        let held: Vec<RigidBodyHandle> = all
            .iter()
            .copied()
            .filter(|&h| self.layer.analysis().holds(&self.world.bodies, h))
            .collect();
        let parked: Vec<RigidBodyHandle> = self
            .layer
            .speedups()
            .map(|s| all.iter().copied().filter(|&h| s.is_parked(h)).collect())
            .unwrap_or_default();
        match who {
            Who::Parked(i) => pick(&parked, i)
                .or_else(|| pick(&held, i))
                .or_else(|| pick(&all, i)),
            Who::Held(i) => pick(&held, i).or_else(|| pick(&all, i)),
            Who::Any(i) => pick(&all, i),
        }
    }

    /// Whether the body is a multibody link or has an impulse joint to a body that is
    /// not an enabled dynamic one: Rapier panics on a disabled multibody link, and in
    /// its solver on a joint between a disabled body and one that is disabled, fixed
    /// or kinematic (the layer guards only the bodies it made passive itself).
    fn jointed_to_disabled_or_link(&self, h: RigidBodyHandle) -> bool {
        self.world.multibody_joints.rigid_body_link(h).is_some()
            || self.jointed_to(h, |rb| !rb.is_enabled() || !rb.is_dynamic())
    }

    /// Whether an impulse joint ties `h` to a body that `is` says yes to.
    pub(super) fn jointed_to(&self, h: RigidBodyHandle, is: impl Fn(&RigidBody) -> bool) -> bool {
        self.world
            .impulse_joints
            .attached_joints(h)
            .any(|(b1, b2, ..)| {
                let other = if b1 == h { b2 } else { b1 };
                self.world.bodies.get(other).is_some_and(&is)
            })
    }

    /// A user's own Rapier call on a body: the layer is not told.
    pub(super) fn user_call(&mut self, who: Who, call: Call) -> Result<(), String> {
        let Some(h) = self.target(who) else {
            return Ok(());
        };
        self.counters.user_calls += 1;
        if self.layer.analysis().holds(&self.world.bodies, h) {
            self.counters.user_calls_held += 1;
        }
        match call {
            Call::Impulse { x, y, z } => {
                let v = Vector::new(vel(x), vel(y), vel(z));
                self.both(|w| {
                    let rb = &mut w.bodies[h];
                    let m = rb.mass();
                    rb.apply_impulse(v * m, true);
                });
            }
            Call::Linvel { x, y, z } => {
                let v = Vector::new(vel(x), vel(y), vel(z));
                self.both(|w| w.bodies[h].set_linvel(v, true));
            }
            Call::Type(ty) => {
                // Rapier asserts that a multibody's non-root links are dynamic.
                if self.non_root_link(h) {
                    return Ok(());
                }
                // As the docs ask: a full sync after changing a sleeping, fixed or
                // passive body's type; not for a held body, which is dynamic to its
                // user (the layer answers the user's type itself: rule 4 of
                // "Releasing held bodies").
                let sync = self.needs_sync(h) && !self.held(h);
                self.both(|w| w.bodies[h].set_body_type(ty.rapier(), true));
                if sync {
                    self.full_sync();
                }
            }
            Call::Enabled(on) => {
                // Not disabled in its parking step: the layer enables it again, a
                // documented limit
                // (`limit_a_held_body_the_user_disables_while_parking_stays_disabled` in
                // `tests/fuzz_regressions_held.rs`).
                let parking = self
                    .layer
                    .speedups()
                    .is_some_and(|s| s.parking().any(|p| p == h));
                if self.jointed_to_disabled_or_link(h) || (!on && self.steer && parking) {
                    return Ok(());
                }
                // The docs ask for a full sync after changing a sleeping, fixed or
                // disabled body in place (Rapier wakes nothing for it); not for a held
                // body, which is dynamic to its user (the layer finds it:
                // `fixed_a_held_body_the_user_disables_is_passive_in_the_graph`).
                let sync = self.needs_sync(h) && !self.held(h);
                self.both(|w| w.bodies[h].set_enabled(on));
                if sync {
                    self.full_sync();
                }
                // A `set_body_disabled` since the last step is applied after this
                // call, at the next pre-step: it stays the last word.
                if !self.pending.contains_key(&raw(h)) {
                    let asked = Asked {
                        handle: h,
                        disabled: !on,
                        by_layer: false,
                    };
                    self.passive.insert(raw(h), asked);
                }
            }
            Call::Sleep => {
                self.both(|w| w.bodies[h].sleep());
            }
            Call::Wake => self.both(|w| w.bodies[h].wake_up(true)),
            Call::Remove { keep_colliders } => {
                self.both(|w| {
                    w.bodies.remove(
                        h,
                        &mut w.islands,
                        &mut w.colliders,
                        &mut w.impulse_joints,
                        &mut w.multibody_joints,
                        &mut w.soft_bodies,
                        !keep_colliders,
                    );
                });
            }
        }
        Ok(())
    }

    /// Whether steps one layer does not see are left out now (in
    /// `tests/fuzz_regressions_unseen.rs` and `tests/fuzz_regressions_held.rs`):
    /// - while a joint the layer has not guarded yet has a disabled body, Rapier
    ///   panics without the layer's pre-step, a documented limit
    ///   (`limit_an_unseen_step_with_a_new_joint_to_a_passive_body_does_not_panic`);
    /// - while a held body is a multibody link, Rapier asserts without the layer's
    ///   pre-step, which releases it, a documented limit
    ///   (`limit_an_unseen_step_with_a_held_body_joined_to_a_multibody_panics_rapier`);
    ///   and while a multibody holds a disabled body, the same without the pre-step
    ///   that makes a passive body joined to a multibody active again
    ///   (`limit_an_unseen_step_with_a_passive_body_in_a_multibody_does_not_panic`);
    /// - while the layer has rules: a step without the layer's hooks applies none, and
    ///   where nothing moves the layer does not notice it missed one, a documented
    ///   limit (`limit_a_rule_holds_across_an_unseen_step_where_nothing_moves`);
    /// - while no awake dynamic body moves, under the speed-ups or with a multibody
    ///   link awake: no sleep timer grows under the speed-ups' sleep, nor a link's held
    ///   still by its joint, so a step where every sampled body rests exactly shows
    ///   nothing; and the speed-ups' sleep lets Rapier put a body back to sleep two
    ///   steps after it wakes, so a body the user wakes (a teleport) can wake and sleep
    ///   within the missed steps: documented limits (`limit_an_unseen_step_where_every_sampled_body_rests_exactly_under_the_speed_ups`,
    ///   `limit_an_unseen_step_where_a_multibody_link_rests_exactly`,
    ///   `limit_an_unseen_step_where_a_woken_body_sleeps_again_under_the_speed_ups`).
    pub(super) fn unseen_avoided(&self) -> bool {
        if !self.steer {
            return false;
        }
        let fixed_link = || {
            self.world.bodies.iter().any(|(h, rb)| {
                !rb.is_dynamic()
                    && self
                        .world
                        .multibody_joints
                        .rigid_body_link(h)
                        .is_some_and(|l| l.id != 0)
            })
        };
        let disabled =
            |h: RigidBodyHandle| self.world.bodies.get(h).is_some_and(|rb| !rb.is_enabled());
        let unguarded_joint = || {
            self.world.impulse_joints.iter().any(|(_, j)| {
                j.data.enabled != JointEnabled::Disabled
                    && (disabled(j.body1()) || disabled(j.body2()))
            })
        };
        let disabled_member = || {
            self.world.bodies.iter().any(|(h, rb)| {
                !rb.is_enabled() && self.world.multibody_joints.rigid_body_link(h).is_some()
            })
        };
        // A multibody link held still by its joints shows no step under any
        // configuration (its sleep timer does not grow either).
        let link_at_rest = || {
            self.world
                .islands
                .active_bodies()
                .any(|h| self.world.multibody_joints.rigid_body_link(h).is_some())
        };
        let nothing_moves = || {
            (matches!(self.config, Config::SpeedUps(_)) || link_at_rest())
                && !self.world.islands.active_bodies().any(|h| {
                    self.world.bodies.get(h).is_some_and(|rb| {
                        rb.is_dynamic()
                            && rb.is_enabled()
                            && (rb.linvel() != Vector::ZERO || rb.angvel() != Vector::ZERO)
                    })
                })
        };
        !self.rules.is_empty()
            || unguarded_joint()
            || fixed_link()
            || disabled_member()
            || nothing_moves()
    }

    /// One step of Rapier alone (`PhysicsWorld::step`): the layer does not see it.
    /// Nothing of the layer is checked (it has not analysed); the twin is.
    pub(super) fn unseen_step(&mut self) -> Result<(), String> {
        if self.unseen_avoided() {
            return Ok(());
        }
        self.world.step();
        self.counters.unseen_steps += 1;
        self.quarantined
            .extend(self.world.quarantine().bodies().iter().map(|&h| raw(h)));
        self.step_twin()
            .map_err(|e| format!("after an unseen step: {e}"))
    }

    /// The second layer: attached, detached, or stepping instead of the first.
    pub(super) fn second(&mut self, op: Second) -> Result<(), String> {
        match op {
            Second::Attach => {
                if self.second.is_none() {
                    let mut l = ContactLayer::new();
                    // Under the proximity configuration both layers read every pair.
                    if self.config == Config::Proximity {
                        l.set_tracking(Tracking::Proximity);
                    }
                    self.second = Some(l);
                }
            }
            Second::Detach => {
                if let Some(l) = self.second.take() {
                    l.detach(WorldMut::from(&mut self.world));
                    // `detach` takes its flags off with `ColliderSet::get_mut`, which
                    // puts each collider in Rapier's modified list now, ahead of what
                    // the user changes before the next step; Rapier handles that list
                    // in order, so a later change to one of them lands in another
                    // place than in a world never layered (`ContactLayer::detach`'s
                    // docs; `limit_a_collider_changed_after_detach_keeps_the_place_of_the_layers_write`).
                    // The twin is given the same accesses in the same order.
                    let flagged = std::mem::take(&mut self.second_flagged);
                    if self.mirror_detach {
                        if let Some(t) = &mut self.twin {
                            for c in flagged.into_values() {
                                let _ = t.colliders.get_mut(c);
                            }
                        }
                    }
                    // It took off the `COLLISION_EVENTS` flags it added, which the
                    // first layer may have found set and relied on: the docs ask for a
                    // full sync after such flags go.
                    self.full_sync();
                }
            }
            Second::Step(n) => {
                for _ in 0..n.clamp(1, 5) {
                    self.second_step()?;
                }
            }
        }
        Ok(())
    }

    /// One step of the second layer (if attached), then its checks: `validate()`, the
    /// touching oracle, the twin.
    fn second_step(&mut self) -> Result<(), String> {
        if self.unseen_avoided() {
            return Ok(());
        }
        let Some(l) = self.second.as_mut() else {
            return Ok(());
        };
        // The first layer's widening is a change in place to the second, which
        // `set_trigger_widening`'s docs ask its `request_full_sync` for
        // (`limit_a_second_layer_sees_a_new_sensor_the_first_widened` in
        // `tests/fuzz_regressions_unseen.rs`).
        let types = sensor_types(&self.world);
        if self.steer && types != self.second_types {
            l.analysis_mut().request_full_sync();
        }
        let before = collider_events(&self.world);
        l.step(&mut self.world);
        // The colliders it flagged (its own map, in collider order), for `detach`.
        for (c, events) in before {
            let flagged = self
                .world
                .colliders
                .get(c)
                .is_some_and(|co| gained_touch_flag(events, co.active_events()));
            if flagged {
                self.second_flagged.insert(c.into_raw_parts(), c);
            }
        }
        self.second_types = sensor_types(&self.world);
        let step = l.analysis().current_step();
        self.counters.second_steps += 1;
        self.quarantined
            .extend(self.world.quarantine().bodies().iter().map(|&h| raw(h)));
        let l = self.second.as_ref().expect("attached");
        let checked = l
            .validate(&self.world)
            .map_err(|e| format!("validate() failed: {e}"))
            .and_then(|()| touching_agrees(l, &self.world));
        let pairs = checked.map_err(|e| format!("second layer, after its step {step}: {e}"))?;
        self.counters.touching_pairs += pairs;
        self.step_twin()
            .map_err(|e| format!("second layer, after its step {step}: {e}"))
    }
}

/// Whether a collider's events gained the `COLLISION_EVENTS` flag.
fn gained_touch_flag(before: ActiveEvents, after: ActiveEvents) -> bool {
    !before.contains(ActiveEvents::COLLISION_EVENTS)
        && after.contains(ActiveEvents::COLLISION_EVENTS)
}

/// Every collider's active events, in collider order.
fn collider_events(world: &PhysicsWorld) -> Vec<(ColliderHandle, ActiveEvents)> {
    world
        .colliders
        .iter()
        .map(|(c, co)| (c, co.active_events()))
        .collect()
}
