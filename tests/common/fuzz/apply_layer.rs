//! [`Harness::apply_layer_op`]: what each layer operation does (passive bodies, rules,
//! timers, composites, subscriptions, speed-ups, tracking), and the operations of
//! [`super::apply_user`] dispatched from here.

use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{Category, Error, Filter, NodeId, NodeKind, Rule};

use super::ops::{kinds_of, pick, pick_mask, raw};
use super::{Asked, Harness, Op, Sub};

impl Harness {
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

    /// Applies a layer operation (or one of [`super::apply_user`]'s); the world
    /// operations and steps are [`Harness::apply`]'s.
    pub(super) fn apply_layer_op(&mut self, op: &Op) -> Result<(), String> {
        match *op {
            Op::Passive(i, on) => {
                // Any body may be asked passive: the layer refuses a dynamic
                // multibody member (a `Link` node: Rapier panics on a disabled one,
                // `fixed_set_passive_on_a_multibody_member_is_refused`), and guards
                // the joints of passive bodies
                // (`fixed_a_joint_to_a_passive_body_is_disabled_while_it_is_passive`).
                // No multibody member is made active: Rapier may have quarantined it
                // (disabled), and re-enabling one panics in Rapier's step.
                // A held multibody member asked passive is refused too
                // (`fixed_a_held_passive_body_joined_to_a_multibody_does_not_panic`).
                let ok = |h: RigidBodyHandle| {
                    on || self.world.multibody_joints.rigid_body_link(h).is_none()
                };
                if let Some(h) = self.body(i).filter(|&h| ok(h)) {
                    // A passive body changes motion: no twin from now on.
                    self.diverge();
                    // An error only for a body the layer has not seen yet, or for a
                    // `Link` node (refused).
                    let node = self.layer.graph().try_node_of_body(h).ok();
                    let link = node
                        .and_then(|n| self.layer.graph().node(n))
                        .map(|n| n.kind())
                        == Some(NodeKind::Link);
                    match self
                        .layer
                        .logic_mut()
                        .set_body_disabled(&self.world.bodies, h, on)
                    {
                        Ok(()) if on && link => {
                            return Err(format!("set_body_disabled({h:?}, true) on a link: Ok"))
                        }
                        Ok(()) => {
                            let asked = Asked {
                                handle: h,
                                disabled: on,
                                by_layer: true,
                            };
                            let before = self.passive.insert(raw(h), asked);
                            self.pending.entry(raw(h)).or_insert(before);
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
            Op::IgnorePair(a, b) => {
                let c = self.candidates();
                let pair = (pick(&c, a), pick(&c, b));
                if let (Some(x), Some(y)) = pair
                    .0
                    .zip(pair.1)
                    .filter(|(x, y)| self.rule_ok(&[*x, *y]))
                    .unzip()
                {
                    self.diverge();
                    let r = self
                        .layer
                        .logic_mut()
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
                    self.diverge();
                    let r = self
                        .layer
                        .logic_mut()
                        .add_rule(Rule::ignore_between(&x, &y))
                        .map_err(|e| format!("add_rule(ignore_between({x:?}, {y:?})): {e}"))?;
                    self.rules.push(r);
                }
            }
            Op::RemoveRule(i) => {
                if let Some(r) = pick(&self.rules, i) {
                    self.layer
                        .logic_mut()
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
                        .logic_mut()
                        .declare_composite_nodes(&members)
                        .map_err(|e| format!("declare_composite({members:?}): {e}"))?;
                    self.composites.push(c);
                }
            }
            Op::RemoveComposite(i) => {
                if let Some(c) = pick(&self.composites, i) {
                    self.layer
                        .logic_mut()
                        .remove_composite(c)
                        .map_err(|e| format!("remove_composite({c:?}): {e}"))?;
                    self.composites.retain(|&x| x != c);
                }
            }
            Op::Timer(p) => {
                let t = self
                    .layer
                    .logic_mut()
                    .add_timer(0.02 * f64::from(p % 10 + 1))
                    .map_err(|e| format!("add_timer: {e}"))?;
                self.timers.push(t);
            }
            Op::RemoveTimer(i) => {
                if let Some(t) = pick(&self.timers, i) {
                    self.layer
                        .logic_mut()
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
                if bits.is_some() {
                    self.diverge();
                }
                self.layer
                    .speedups_mut()
                    .set(bits.map(rcg_lab::table5::combination))
                    .map_err(|e| format!("speedups_mut().set: {e}"))?;
            }
            Op::Monitor(on) => {
                let mode = if on {
                    MonitorMode::Repair
                } else {
                    MonitorMode::Off
                };
                self.layer
                    .monitor_mut()
                    .set(mode, MonitorConfig::default(), RepairConfig::default())
                    .map_err(|e| format!("monitor_mut().set: {e}"))?;
            }
            Op::Preset => {
                self.layer
                    .speedups_mut()
                    .set(self.config.speedups())
                    .map_err(|e| format!("speedups_mut().set: {e}"))?;
            }
            Op::User(who, call) => self.user_call(who, call)?,
            Op::Unseen(n) => {
                for _ in 0..n.clamp(1, 3) {
                    self.unseen_step()?;
                }
            }
            Op::Second(op) => self.second(op)?,
            Op::Touching(on) => self.layer.set_tracking(if on {
                rapier_contact_graph::coherence::Tracking::Touching
            } else {
                rapier_contact_graph::coherence::Tracking::Proximity
            }),
            Op::FullSync => self.layer.analysis_mut().request_full_sync(),
            _ => unreachable!("a world operation: {op:?}"),
        }
        Ok(())
    }
}
