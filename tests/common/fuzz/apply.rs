//! [`Harness::apply`]: what each operation does to the world or the layer. Indices
//! are taken modulo the live objects; what Rapier itself would panic on is skipped
//! (each place says why), and `request_full_sync` is called where the docs ask for it.

use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{Category, Error, Filter, NodeId, NodeKind, Rule};

use super::ops::{grid, kinds_of, pick, pick_mask, raw, vel};
use super::{Harness, Op, Sub};

impl Harness {
    fn bodies(&self) -> Vec<RigidBodyHandle> {
        self.world.bodies.iter().map(|(h, _)| h).collect()
    }

    fn body(&self, i: u8) -> Option<RigidBodyHandle> {
        pick(&self.bodies(), i)
    }

    fn collider(&self, i: u8) -> Option<ColliderHandle> {
        let v: Vec<_> = self.world.colliders.iter().map(|(h, _)| h).collect();
        pick(&v, i)
    }

    /// Live nodes a rule may name: bodies, static colliders, triggers.
    fn candidates(&self) -> Vec<NodeId> {
        let mut v: Vec<NodeId> = self
            .layer
            .graph()
            .nodes()
            .filter(|(_, n)| {
                n.kind().category() == Category::Physical || n.kind() == NodeKind::Sensor
            })
            .map(|(id, _)| id)
            .collect();
        v.sort();
        v
    }

    /// Any rule is fine (a rule naming a trigger and static geometry was a bug,
    /// see `fixed_a_rule_between_a_trigger_and_static_geometry_ends_their_edge`).
    fn rule_ok(&self, _members: &[NodeId]) -> bool {
        true
    }

    /// Whether changing this body in place needs `request_full_sync` per the docs:
    /// it is sleeping, fixed or disabled (passive).
    fn needs_sync(&self, h: RigidBodyHandle) -> bool {
        // Asleep as the layer last saw it counts too: a sleeping body woken (by a
        // teleport) and turned fixed before the next step never shows in Rapier's
        // active set, so the layer cannot see the change.
        let seen_asleep = self
            .layer
            .node_of_body(h)
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

    /// Disabled in Rapier though not asked passive: Rapier quarantined it (a
    /// non-finite state). The layer guards the joints of the bodies it made
    /// passive only; a joint to such a body makes Rapier panic on its own.
    fn rapier_disabled(&self, h: RigidBodyHandle) -> bool {
        !self.world.bodies[h].is_enabled() && !self.passive.get(&raw(h)).is_some_and(|p| p.1)
    }

    /// Whether the speed-ups hold a body fixed: to its user, it is still dynamic.
    fn held(&self, h: RigidBodyHandle) -> bool {
        self.layer.speedups().is_some_and(|s| s.is_fixated(h))
    }

    /// A multibody link other than the root: Rapier asserts that such a body is
    /// dynamic (multibody.rs), so its type is never changed.
    fn non_root_link(&self, h: RigidBodyHandle) -> bool {
        self.world
            .multibody_joints
            .rigid_body_link(h)
            .is_some_and(|l| l.id != 0)
    }

    fn insert_dynamic(&mut self, at: Vector, shape: ColliderBuilder) {
        self.world
            .insert(RigidBodyBuilder::dynamic().translation(at), shape);
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
            self.layer.request_full_sync();
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
            Op::FixedBody { x, y, z } => {
                self.world.insert(
                    RigidBodyBuilder::fixed().translation(grid(x, y, z)),
                    ColliderBuilder::cuboid(0.4, 0.4, 0.4),
                );
            }
            Op::Static { x, y, z } => {
                self.world.insert_collider(
                    ColliderBuilder::cuboid(0.4, 0.25, 0.4).translation(grid(x, y, z)),
                    None,
                );
            }
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
                self.world.insert(
                    b.translation(grid(x, y, z))
                        .linvel(Vector::new(vel(vx), 0.0, vel(vz))),
                    ColliderBuilder::cuboid(0.5, 0.2, 0.5),
                );
            }
            Op::Sensor { on, x, y, z } => {
                let sensor = ColliderBuilder::ball(0.6).sensor(true);
                match on {
                    Some(i) => {
                        if let Some(h) = self.body(i) {
                            self.world.insert_collider(sensor, Some(h));
                        }
                    }
                    None => {
                        self.world
                            .insert_collider(sensor.translation(grid(x, y, z)), None);
                    }
                }
            }
            Op::ExtraCollider { on, x } => {
                if let Some(h) = self.body(on) {
                    let off = Vector::new(f32::from(x.clamp(-2, 2)) * 0.25, 0.0, 0.0);
                    self.world
                        .insert_collider(ColliderBuilder::ball(0.3).translation(off), Some(h));
                }
            }
            Op::RemoveBody(i) => {
                if let Some(h) = self.body(i) {
                    self.world.remove_body(h);
                }
            }
            Op::RemoveCollider(i) => {
                if let Some(c) = self.collider(i) {
                    self.world.remove_collider(c);
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
                    let col = &mut self.world.colliders[c];
                    col.set_sensor(!col.is_sensor());
                    if sync {
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::SetParent(i, to) => {
                let parent = to.and_then(|b| self.body(b));
                if let Some(c) = self.collider(i) {
                    let old = self.world.colliders[c].parent();
                    // As the docs ask: a full sync when either side would not be
                    // refreshed (sleeping, fixed, passive, or static geometry).
                    let sync = old.is_none_or(|p| self.needs_sync(p))
                        || parent.is_none_or(|p| self.needs_sync(p));
                    self.world
                        .colliders
                        .set_parent(c, parent, &mut self.world.bodies);
                    if sync {
                        self.layer.request_full_sync();
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
                    let col = &mut self.world.colliders[c];
                    match op {
                        Op::CollisionGroups(..) => col.set_collision_groups(groups),
                        Op::SolverGroups(..) => col.set_solver_groups(groups),
                        Op::UserHooks(..) => {
                            col.set_active_hooks(ActiveHooks::from_bits_truncate(u32::from(m)))
                        }
                        _ => col.set_shape(SharedShape::ball(0.2 + 0.1 * f32::from(m % 4))),
                    }
                    if sync {
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::ColliderEnabled(i, on) => {
                if let Some(c) = self.collider(i) {
                    let sync = self.world.colliders[c]
                        .parent()
                        .is_none_or(|p| self.needs_sync(p));
                    self.world.colliders[c].set_enabled(on);
                    if sync {
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::UserEvents(i, on) => {
                if let Some(c) = self.collider(i) {
                    let col = &mut self.world.colliders[c];
                    let f = if on {
                        col.active_events() | ActiveEvents::COLLISION_EVENTS
                    } else {
                        col.active_events() - ActiveEvents::COLLISION_EVENTS
                    };
                    col.set_active_events(f);
                }
            }
            Op::SetType(i, ty) => {
                // Rapier asserts that a multibody's non-root links are dynamic.
                if let Some(h) = self.body(i).filter(|&h| !self.non_root_link(h)) {
                    let sync = self.needs_sync(h);
                    self.world.bodies[h].set_body_type(ty.rapier(), true);
                    if sync {
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::Teleport { body, x, y, z } => {
                if let Some(h) = self.body(body) {
                    let sync =
                        self.world.bodies[h].is_fixed() || !self.world.bodies[h].is_enabled();
                    self.world.bodies[h].set_translation(grid(x, y, z), true);
                    if sync {
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::MoveStatic { collider, x, y, z } => {
                if let Some(c) = self.collider(collider) {
                    if self.world.colliders[c].parent().is_none() {
                        self.world.colliders[c].set_translation(grid(x, y, z));
                        self.layer.request_full_sync();
                    }
                }
            }
            Op::Velocity { body, vx, vy, vz } => {
                if let Some(h) = self.body(body) {
                    self.world.bodies[h].set_linvel(Vector::new(vel(vx), vel(vy), vel(vz)), true);
                }
            }
            Op::Sleep(i) => {
                // Any body, at any time (it was restricted to dynamic bodies in an
                // unchanged world while the bugs fixed with
                // `fixed_a_moved_fixed_sensor_meets_static_geometry_and_sleeping_bodies`
                // were open).
                if let Some(h) = self.body(i) {
                    self.world.bodies[h].sleep();
                }
            }
            Op::Wake(i) => {
                if let Some(h) = self.body(i) {
                    self.world.wake_up(h, true);
                }
            }
            Op::Passive(i, on) => {
                // Any body may be asked passive: the layer refuses a dynamic
                // multibody member (a `Link` node: Rapier panics on a disabled one,
                // `fixed_set_passive_on_a_multibody_member_is_refused`), and guards
                // the joints of passive bodies
                // (`fixed_a_joint_to_a_passive_body_is_disabled_while_it_is_passive`).
                // No multibody member is made active: Rapier may have quarantined it
                // (disabled), and re-enabling one panics in Rapier's step.
                let ok = |h: RigidBodyHandle| {
                    on || self.world.multibody_joints.rigid_body_link(h).is_none()
                };
                if let Some(h) = self.body(i).filter(|&h| ok(h)) {
                    // An error only for a body the layer has not seen yet, or for a
                    // `Link` node (refused).
                    let node = self.layer.node_of_body(h).ok();
                    let link = node
                        .and_then(|n| self.layer.graph().node(n))
                        .map(|n| n.kind())
                        == Some(NodeKind::Link);
                    match self.layer.set_body_disabled(h, on) {
                        Ok(()) if on && link => {
                            return Err(format!("set_body_disabled({h:?}, true) on a link: Ok"))
                        }
                        Ok(()) => {
                            self.passive.insert(raw(h), (h, on));
                        }
                        Err(Error::Unsupported { .. }) if on && link => {
                            self.counters.refused += 1;
                        }
                        Err(e) if node.is_some() => {
                            return Err(format!("set_body_disabled({h:?}, {on}) failed: {e}"))
                        }
                        Err(_) => {}
                    }
                }
            }
            Op::Joint { a, b, revolute } => {
                if let (Some(b1), Some(b2)) = (self.body(a), self.body(b)) {
                    // Not to a body Rapier disabled itself: see `rapier_disabled`.
                    if b1 != b2 && !self.rapier_disabled(b1) && !self.rapier_disabled(b2) {
                        if revolute {
                            self.world.insert_impulse_joint(
                                b1,
                                b2,
                                RevoluteJointBuilder::new(Vector::Z),
                            );
                        } else {
                            self.world
                                .insert_impulse_joint(b1, b2, FixedJointBuilder::new());
                        }
                    }
                }
            }
            Op::RemoveJoint(i) => {
                let v: Vec<_> = self.world.impulse_joints.iter().map(|(h, _)| h).collect();
                if let Some(j) = pick(&v, i) {
                    self.world.remove_impulse_joint(j);
                }
            }
            Op::Multibody { a, b } => {
                if let (Some(b1), Some(b2)) = (self.body(a), self.body(b)) {
                    // Rapier asserts that a multibody's non-root links are dynamic (a
                    // body the speed-ups hold fixed is dynamic to its user: the layer
                    // releases it, see
                    // `fixed_a_deferred_fixation_of_a_new_multibody_link_is_skipped`).
                    // A passive body may join: the layer makes it active again
                    // (`fixed_a_passive_body_joined_to_a_multibody_is_made_active_again`).
                    // A rejected insertion (a link that already has a parent)
                    // corrupts Rapier's bookkeeping: removing the root later panics
                    // in `MultibodyJointSet::remove` (upstream; not this crate's).
                    if b1 != b2
                        && (self.world.bodies[b2].is_dynamic() || self.held(b2))
                        && self.world.multibody_joints.rigid_body_link(b2).is_none()
                        && !self.rapier_disabled(b1)
                        && !self.rapier_disabled(b2)
                    {
                        let _ = self.world.insert_multibody_joint(
                            b1,
                            b2,
                            RevoluteJointBuilder::new(Vector::Z)
                                .local_anchor2(Vector::new(0.0, 0.6, 0.0)),
                        );
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
                    self.world.remove_multibody_joint(j);
                }
            }
            Op::IgnorePair(a, b) => {
                let c = self.candidates();
                let pair = (pick(&c, a), pick(&c, b));
                if let (Some(x), Some(y)) = pair
                    .0
                    .zip(pair.1)
                    .filter(|(x, y)| self.rule_ok(&[*x, *y]))
                    .unzip()
                {
                    let r = self
                        .layer
                        .add_rule(Rule::ignore_pair(x, y))
                        .map_err(|e| format!("add_rule(ignore_pair({x:?}, {y:?})): {e}"))?;
                    self.rules.push(r);
                }
            }
            Op::IgnoreBetween(mx, my) => {
                let c = self.candidates();
                let (x, y) = (pick_mask(&c, mx), pick_mask(&c, my));
                let all: Vec<NodeId> = x.iter().chain(&y).copied().collect();
                if !all.is_empty() && self.rule_ok(&all) {
                    let r = self
                        .layer
                        .add_rule(Rule::ignore_between(&x, &y))
                        .map_err(|e| format!("add_rule(ignore_between({x:?}, {y:?})): {e}"))?;
                    self.rules.push(r);
                }
            }
            Op::RemoveRule(i) => {
                if let Some(r) = pick(&self.rules, i) {
                    self.layer
                        .remove_rule(r)
                        .map_err(|e| format!("remove_rule({r:?}): {e}"))?;
                    self.rules.retain(|&x| x != r);
                }
            }
            Op::Composite(mask) => {
                let mut rigid: Vec<NodeId> = self
                    .layer
                    .graph()
                    .nodes_of_kind(NodeKind::Dynamic)
                    .map(|(id, _)| id)
                    .collect();
                rigid.sort();
                let members = pick_mask(&rigid, mask);
                if !members.is_empty() {
                    let c = self
                        .layer
                        .declare_composite(&members)
                        .map_err(|e| format!("declare_composite({members:?}): {e}"))?;
                    self.composites.push(c);
                }
            }
            Op::RemoveComposite(i) => {
                if let Some(c) = pick(&self.composites, i) {
                    self.layer
                        .remove_composite(c)
                        .map_err(|e| format!("remove_composite({c:?}): {e}"))?;
                    self.composites.retain(|&x| x != c);
                }
            }
            Op::Timer(p) => {
                let t = self
                    .layer
                    .add_timer(0.02 * f64::from(p % 10 + 1))
                    .map_err(|e| format!("add_timer: {e}"))?;
                self.timers.push(t);
            }
            Op::RemoveTimer(i) => {
                if let Some(t) = pick(&self.timers, i) {
                    self.layer
                        .remove_timer(t)
                        .map_err(|e| format!("remove_timer({t:?}): {e}"))?;
                    self.timers.retain(|&x| x != t);
                }
            }
            Op::Subscribe {
                kinds,
                capacity,
                node,
            } => {
                let mut filter = Filter::kinds(kinds_of(kinds));
                if let Some(i) = node {
                    let mut all: Vec<NodeId> =
                        self.layer.graph().nodes().map(|(id, _)| id).collect();
                    all.sort();
                    if let Some(n) = pick(&all, i) {
                        filter = filter.with_nodes(&[n]);
                    }
                }
                let capacity = usize::from(capacity % 9);
                let (id, rx) = if capacity == 0 {
                    let (id, rx) = self.layer.subscribe_with_id(filter.clone());
                    (Some(id), rx)
                } else {
                    // `subscribe_bounded` returns no id: bounded subscriptions
                    // are only dropped, never unsubscribed.
                    let rx = self
                        .layer
                        .subscribe_bounded(filter.clone(), capacity)
                        .map_err(|e| format!("subscribe_bounded: {e}"))?;
                    (None, rx)
                };
                self.subs.push(Sub {
                    id,
                    rx,
                    filter,
                    capacity,
                });
            }
            Op::SubscribeHandle {
                kinds,
                body,
                collider,
            } => {
                let mut filter = Filter::kinds(kinds_of(kinds));
                if let Some(b) = body.and_then(|i| self.body(i)) {
                    filter = filter.with_bodies(&[b]);
                }
                if let Some(c) = collider.and_then(|i| self.collider(i)) {
                    filter = filter.with_colliders(&[c]);
                }
                let (id, rx) = self.layer.subscribe_with_id(filter.clone());
                self.subs.push(Sub {
                    id: Some(id),
                    rx,
                    filter,
                    capacity: 0,
                });
            }
            Op::Unsubscribe(i) => {
                let n = self.subs.len();
                if n > 0 {
                    let s = self.subs.remove(usize::from(i) % n);
                    if let Some(id) = s.id {
                        if !self.layer.unsubscribe(id) {
                            return Err(format!(
                                "unsubscribe({id:?}) of a live subscription failed"
                            ));
                        }
                    }
                }
            }
            Op::DropReceiver(i) => {
                let n = self.subs.len();
                if n > 0 {
                    drop(self.subs.remove(usize::from(i) % n));
                }
            }
            Op::SpeedUps(bits) => {
                self.layer
                    .set_speedups(bits.map(SpeedUps::combination))
                    .map_err(|e| format!("set_speedups: {e}"))?;
            }
            Op::Touching(on) => self.layer.set_tracking(if on {
                rapier_contact_graph::coherence::Tracking::Touching
            } else {
                rapier_contact_graph::coherence::Tracking::Proximity
            }),
            Op::FullSync => self.layer.request_full_sync(),
            Op::Step(n) => {
                for _ in 0..n.clamp(1, 40) {
                    self.step()?;
                }
            }
        }
        Ok(())
    }
}
