//! [`Harness::apply`]: what each world operation does (to the world and its twin), and
//! steps; the layer's operations are in `apply_layer.rs`, the user's own calls behind
//! the layer's back in `apply_user.rs`. Indices are taken modulo the live objects;
//! what Rapier itself would panic on is skipped (each place says why), and
//! `request_full_sync` is called where the docs ask for it.

use rapier_contact_graph::rapier3d::prelude::*;

use super::ops::{grid, pick, raw, vel, Ty};
use super::{Harness, Op};

impl Harness {
    /// Whether no collider is attached to, or moved onto, body `h` now, nor its type
    /// changed: a disabled multibody member (Rapier's solver panics in its warm start,
    /// with or without the layer:
    /// `limit_a_collider_moved_onto_a_quarantined_multibody_root_panics_rapier` in
    /// `tests/fuzz_regressions_held.rs`; its solver graph check fails after a type
    /// change: `limit_a_disabled_multibody_root_with_a_collider_moved_onto_it_given_a_type`
    /// in `tests/fuzz_regressions_joints.rs`).
    fn member_steered_off(&self, h: RigidBodyHandle) -> bool {
        self.steer
            && self.world.multibody_joints.rigid_body_link(h).is_some()
            && self.world.bodies.get(h).is_some_and(|rb| !rb.is_enabled())
    }

    pub(super) fn bodies(&self) -> Vec<RigidBodyHandle> {
        self.world.bodies.iter().map(|(h, _)| h).collect()
    }

    pub(super) fn body(&self, i: u8) -> Option<RigidBodyHandle> {
        pick(&self.bodies(), i)
    }

    pub(super) fn collider(&self, i: u8) -> Option<ColliderHandle> {
        let v: Vec<_> = self.world.colliders.iter().map(|(h, _)| h).collect();
        pick(&v, i)
    }

    /// Whether changing this body in place needs `request_full_sync` per the docs:
    /// it is sleeping, fixed or disabled (passive).
    pub(super) fn needs_sync(&self, h: RigidBodyHandle) -> bool {
        // Asleep as the layer last saw it counts too: a sleeping body woken (by a
        // teleport) and turned fixed before the next step never shows in Rapier's
        // active set, so the layer cannot see the change.
        let seen_asleep = self
            .layer
            .graph()
            .try_node_of_body(h)
            .ok()
            .and_then(|n| self.layer.graph().node(n))
            .is_some_and(|n| !n.is_awake());
        seen_asleep
            || self
                .world
                .bodies
                .get(h)
                .is_none_or(|rb| rb.is_sleeping() || rb.is_fixed() || !rb.is_enabled())
    }

    /// Disabled in Rapier though not made passive by the layer: Rapier quarantined it
    /// (a non-finite state), or the user disabled it with Rapier's own `set_enabled`.
    /// The layer guards the joints of the bodies it made passive only; a joint to
    /// such a body makes Rapier panic on its own.
    pub(super) fn rapier_disabled(&self, h: RigidBodyHandle) -> bool {
        // (A request of the layer not applied yet does not count: it may be refused.)
        !self.world.bodies[h].is_enabled()
            && !(self
                .passive
                .get(&raw(h))
                .is_some_and(|a| a.disabled && a.by_layer)
                && !self.pending.contains_key(&raw(h)))
    }

    /// `request_full_sync()` where the docs ask for it: on every layer on the world
    /// (each is told of a change in place, as its own user would tell it).
    pub(super) fn full_sync(&mut self) {
        self.layer.analysis_mut().request_full_sync();
        if let Some(l) = &mut self.second {
            l.analysis_mut().request_full_sync();
        }
    }

    /// Whether the speed-ups hold a body fixed: to its user, it is still dynamic.
    pub(super) fn held(&self, h: RigidBodyHandle) -> bool {
        self.layer.speedups().is_some_and(|s| s.is_fixated(h))
    }

    /// A multibody link other than the root: Rapier asserts that such a body is
    /// dynamic (multibody.rs), so its type is never changed.
    pub(super) fn non_root_link(&self, h: RigidBodyHandle) -> bool {
        self.world
            .multibody_joints
            .rigid_body_link(h)
            .is_some_and(|l| l.id != 0)
    }

    fn insert_dynamic(&mut self, at: Vector, shape: ColliderBuilder) {
        self.both(|w| {
            w.insert(RigidBodyBuilder::dynamic().translation(at), shape.clone());
        });
    }

    /// Applies one operation; steps are checked. An error is a failed check.
    pub fn apply(&mut self, op: &Op) -> Result<(), String> {
        if self.trace {
            eprintln!("  op {op:?}");
        }
        self.counters.ops += 1;
        let (bodies, colliders) = (self.world.bodies.len(), self.world.colliders.len());
        self.apply_op(op)?;
        // Both an insertion and a removal since the last step: the layer finds the
        // change within `slots / verify_budget()` steps only, or at once after
        // `request_full_sync()` (documented in `audit`, B1): request it, as a user
        // who wants `validate()` to hold after every step.
        let grew = self.world.bodies.len() > bodies || self.world.colliders.len() > colliders;
        let shrank = self.world.bodies.len() < bodies || self.world.colliders.len() < colliders;
        self.added |= grew;
        self.removed |= shrank;
        if self.added && self.removed && (grew || shrank) {
            self.full_sync();
        }
        Ok(())
    }

    fn apply_op(&mut self, op: &Op) -> Result<(), String> {
        match *op {
            Op::Ball { x, y, z, r } => {
                let radius = 0.25 + 0.1 * f32::from(r % 4);
                self.insert_dynamic(grid(x, y, z), ColliderBuilder::ball(radius));
            }
            Op::Cube { x, y, z, r } => {
                let h = 0.25 + 0.1 * f32::from(r % 4);
                self.insert_dynamic(grid(x, y, z), ColliderBuilder::cuboid(h, h, h));
            }
            Op::FixedBody { x, y, z } => self.both(|w| {
                w.insert(
                    RigidBodyBuilder::fixed().translation(grid(x, y, z)),
                    ColliderBuilder::cuboid(0.4, 0.4, 0.4),
                );
            }),
            Op::Static { x, y, z } => self.both(|w| {
                w.insert_collider(
                    ColliderBuilder::cuboid(0.4, 0.25, 0.4).translation(grid(x, y, z)),
                    None,
                );
            }),
            Op::Kinematic {
                x,
                y,
                z,
                vx,
                vz,
                velocity_based,
            } => {
                let b = if velocity_based {
                    RigidBodyBuilder::kinematic_velocity_based()
                } else {
                    RigidBodyBuilder::kinematic_position_based()
                };
                let b = b
                    .translation(grid(x, y, z))
                    .linvel(Vector::new(vel(vx), 0.0, vel(vz)));
                self.both(|w| {
                    w.insert(b.clone(), ColliderBuilder::cuboid(0.5, 0.2, 0.5));
                });
            }
            Op::Sensor { on, x, y, z } => {
                let sensor = ColliderBuilder::ball(0.6).sensor(true);
                match on {
                    Some(i) => {
                        if let Some(h) = self.body(i) {
                            self.both(|w| {
                                w.insert_collider(sensor.clone(), Some(h));
                            });
                        }
                    }
                    None => self.both(|w| {
                        w.insert_collider(sensor.clone().translation(grid(x, y, z)), None);
                    }),
                }
            }
            Op::ExtraCollider { on, x } => {
                if let Some(h) = self.body(on).filter(|&h| !self.member_steered_off(h)) {
                    let off = Vector::new(f32::from(x.clamp(-2, 2)) * 0.25, 0.0, 0.0);
                    self.both(|w| {
                        w.insert_collider(ColliderBuilder::ball(0.3).translation(off), Some(h));
                    });
                }
            }
            Op::RemoveBody(i) => {
                if let Some(h) = self.body(i) {
                    self.both(|w| {
                        w.remove_body(h);
                    });
                }
            }
            Op::RemoveCollider(i) => {
                if let Some(c) = self.collider(i) {
                    self.both(|w| {
                        w.remove_collider(c);
                    });
                }
            }
            Op::ToggleSensor(i) => {
                if let Some(c) = self.collider(i) {
                    // As the docs ask: a full sync after changing a sleeping, fixed
                    // or passive body (or static geometry) in place; none for an
                    // awake body (`fixed_a_collider_of_an_awake_body_turned_sensor_gets_its_trigger_at_once`).
                    let sync = self.world.colliders[c]
                        .parent()
                        .is_none_or(|p| self.needs_sync(p));
                    self.both(|w| {
                        let col = &mut w.colliders[c];
                        col.set_sensor(!col.is_sensor());
                    });
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::SetParent(i, to) => {
                let parent = to.and_then(|b| self.body(b));
                if parent.is_some_and(|p| self.member_steered_off(p)) {
                    return Ok(());
                }
                if let Some(c) = self.collider(i) {
                    let old = self.world.colliders[c].parent();
                    // As the docs ask: a full sync when either side would not be
                    // refreshed (sleeping, fixed, passive, or static geometry).
                    let sync = old.is_none_or(|p| self.needs_sync(p))
                        || parent.is_none_or(|p| self.needs_sync(p));
                    self.both(|w| w.colliders.set_parent(c, parent, &mut w.bodies));
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::CollisionGroups(i, m)
            | Op::SolverGroups(i, m)
            | Op::UserHooks(i, m)
            | Op::SetShape(i, m) => {
                if let Some(c) = self.collider(i) {
                    let sync = self.world.colliders[c]
                        .parent()
                        .is_none_or(|p| self.needs_sync(p));
                    let groups = InteractionGroups::new(
                        Group::from_bits_truncate(u32::from(m & 0x0f) | 1),
                        Group::from_bits_truncate(u32::from(m >> 4) | 1),
                        InteractionTestMode::And,
                    );
                    self.both(|w| {
                        let col = &mut w.colliders[c];
                        match op {
                            Op::CollisionGroups(..) => col.set_collision_groups(groups),
                            Op::SolverGroups(..) => col.set_solver_groups(groups),
                            Op::UserHooks(..) => {
                                col.set_active_hooks(ActiveHooks::from_bits_truncate(u32::from(m)))
                            }
                            _ => col.set_shape(SharedShape::ball(0.2 + 0.1 * f32::from(m % 4))),
                        }
                    });
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::ColliderEnabled(i, on) => {
                if let Some(c) = self.collider(i) {
                    let sync = self.world.colliders[c]
                        .parent()
                        .is_none_or(|p| self.needs_sync(p));
                    self.both(|w| w.colliders[c].set_enabled(on));
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::UserEvents(i, on) => {
                if let Some(c) = self.collider(i) {
                    self.both(|w| {
                        let col = &mut w.colliders[c];
                        let f = if on {
                            col.active_events() | ActiveEvents::COLLISION_EVENTS
                        } else {
                            col.active_events() - ActiveEvents::COLLISION_EVENTS
                        };
                        col.set_active_events(f);
                    });
                }
            }
            Op::SetType(i, ty) => {
                // Rapier asserts that a multibody's non-root links are dynamic, and
                // panics on a joint between a disabled body and a fixed (or
                // kinematic) one.
                // A disabled multibody member's type is left alone: with a collider
                // moved onto it, Rapier's solver graph check fails in its next step
                // (`limit_a_disabled_multibody_root_with_a_collider_moved_onto_it_given_a_type`
                // in `tests/fuzz_regressions_joints.rs`).
                let refused = |h: RigidBodyHandle| {
                    self.non_root_link(h)
                        || (!matches!(ty, Ty::Dynamic) && self.jointed_to(h, |rb| !rb.is_enabled()))
                        || self.member_steered_off(h)
                };
                if let Some(h) = self.body(i).filter(|&h| !refused(h)) {
                    let sync = self.needs_sync(h);
                    self.both(|w| w.bodies[h].set_body_type(ty.rapier(), true));
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::Teleport { body, x, y, z } => {
                if let Some(h) = self.body(body) {
                    let sync =
                        self.world.bodies[h].is_fixed() || !self.world.bodies[h].is_enabled();
                    self.both(|w| w.bodies[h].set_translation(grid(x, y, z), true));
                    if sync {
                        self.full_sync();
                    }
                }
            }
            Op::MoveStatic { collider, x, y, z } => {
                if let Some(c) = self.collider(collider) {
                    if self.world.colliders[c].parent().is_none() {
                        self.both(|w| w.colliders[c].set_translation(grid(x, y, z)));
                        self.full_sync();
                    }
                }
            }
            Op::Velocity { body, vx, vy, vz } => {
                if let Some(h) = self.body(body) {
                    let v = Vector::new(vel(vx), vel(vy), vel(vz));
                    self.both(|w| w.bodies[h].set_linvel(v, true));
                }
            }
            Op::Sleep(i) => {
                // Any body, at any time (it was restricted to dynamic bodies in an
                // unchanged world while the bugs fixed with
                // `fixed_a_moved_fixed_sensor_meets_static_geometry_and_sleeping_bodies`
                // were open).
                if let Some(h) = self.body(i) {
                    self.both(|w| w.bodies[h].sleep());
                }
            }
            Op::Wake(i) => {
                if let Some(h) = self.body(i) {
                    self.both(|w| w.wake_up(h, true));
                }
            }
            Op::Joint { a, b, revolute } => {
                if let (Some(b1), Some(b2)) = (self.body(a), self.body(b)) {
                    // Not to a body Rapier disabled itself: see `rapier_disabled`.
                    if b1 != b2 && !self.rapier_disabled(b1) && !self.rapier_disabled(b2) {
                        self.both(|w| {
                            if revolute {
                                w.insert_impulse_joint(
                                    b1,
                                    b2,
                                    RevoluteJointBuilder::new(Vector::Z),
                                );
                            } else {
                                w.insert_impulse_joint(b1, b2, FixedJointBuilder::new());
                            }
                        });
                    }
                }
            }
            Op::RemoveJoint(i) => {
                let v: Vec<_> = self.world.impulse_joints.iter().map(|(h, _)| h).collect();
                if let Some(j) = pick(&v, i) {
                    self.both(|w| {
                        w.remove_impulse_joint(j);
                    });
                }
            }
            Op::Multibody { a, b } => {
                if let (Some(b1), Some(b2)) = (self.body(a), self.body(b)) {
                    // No held body joins a multibody: in debug builds Rapier's island
                    // manager may assert later
                    // (`limit_a_quarantined_body_beside_a_rule_trips_rapiers_island_assertion`
                    // in `tests/fuzz_regressions_held.rs`).
                    // Rapier asserts that a multibody's non-root links are dynamic (a
                    // body the speed-ups hold fixed, and still fixed, is dynamic to its
                    // user: the layer releases it, see
                    // `fixed_a_deferred_fixation_of_a_new_multibody_link_is_skipped`).
                    // A passive body may join: the layer makes it active again
                    // (`fixed_a_passive_body_joined_to_a_multibody_is_made_active_again`).
                    // A rejected insertion (a link that already has a parent)
                    // corrupts Rapier's bookkeeping: removing the root later panics
                    // in `MultibodyJointSet::remove` (upstream; not this crate's).
                    if b1 != b2
                        && (self.world.bodies[b2].is_dynamic()
                            || (self.held(b2) && self.world.bodies[b2].is_fixed()))
                        && self.world.multibody_joints.rigid_body_link(b2).is_none()
                        && !self.rapier_disabled(b1)
                        && !self.rapier_disabled(b2)
                        && !(self.steer && (self.held(b1) || self.held(b2)))
                    {
                        self.both(|w| {
                            let _ = w.insert_multibody_joint(
                                b1,
                                b2,
                                RevoluteJointBuilder::new(Vector::Z)
                                    .local_anchor2(Vector::new(0.0, 0.6, 0.0)),
                            );
                        });
                    }
                }
            }
            Op::RemoveMultibody(i) => {
                let v: Vec<_> = self
                    .world
                    .multibody_joints
                    .iter()
                    .map(|(h, ..)| h)
                    .collect();
                if let Some(j) = pick(&v, i) {
                    self.both(|w| w.remove_multibody_joint(j));
                }
            }
            Op::Step(n) => {
                for _ in 0..n.clamp(1, 40) {
                    self.step()?;
                }
            }
            _ => self.apply_layer_op(op)?,
        }
        Ok(())
    }
}
