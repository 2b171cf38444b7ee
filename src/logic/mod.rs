//! The logic layer (paper §2's logical and container nodes, §3.2's logical testing):
//! rules, triggers, timers, passive bodies, containers.
//!
//! # When changes take effect
//! The graph changes at once: `add_rule` returns the rule's node, with its logical
//! edges, immediately. What must touch the Rapier world (hook flags, enabling or
//! disabling a passive body, sensor collision types) is queued and applied in the
//! *pre-step* (paper §5, Fig. 11: step 1): [`crate::ContactLayer::step`] does it before
//! Rapier's step; users who step Rapier themselves call
//! [`crate::ContactLayer::pre_step`]. Their effect on edges and events shows after
//! that step's analysis.
//!
//! # Passive bodies and Rapier's own panics
//! A passive body is a disabled Rapier body, and Rapier 0.36.1 panics in its step on
//! two states around disabled bodies (reproduced with plain Rapier; see
//! `docs/audit.md`, "Rapier's own panics"): a disabled multibody member the solver needs, and
//! an enabled impulse joint between a disabled body and a fixed or disabled one. The
//! pre-step guards the bodies the layer made passive, checking the world as it is
//! then (the user may have joined bodies since `set_body_disabled`):
//! - chosen: a dynamic multibody member is never made passive (`set_body_disabled` refuses
//!   a `Link` node; the pre-step refuses a queued change, and makes a passive body the
//!   user joined to a multibody active again, listed in `refusals()`); rejected:
//!   disabling the whole multibody (it would make bodies passive the user did not
//!   name), and disabling non-root links only (Rapier then still moves them with the
//!   multibody: they are not passive);
//! - chosen: a passive body's joints are held `JointEnabled::Disabled` and enabled
//!   again when both ends are active; rejected: Rapier's own `DisabledByAttachedBody`
//!   (Rapier enables those joints whenever a body at either end is inserted or
//!   enabled, whatever the other end), and refusing `set_body_disabled` on jointed bodies (a
//!   joint can be added later, and passive jointed bodies would be lost).
//!
//! # Pay for what you use
//! A scene without rules gets no hook flag; without timers no timer work; sensor
//! collision types are widened only when asked for (`set_trigger_widening`), and then
//! only on sensor colliders (which never push bodies, so motion is unchanged).

pub(crate) mod containers;
pub mod hooks;
pub(crate) mod rules;
#[cfg(feature = "serde")]
pub(crate) mod serde_rules;
pub(crate) mod timers;

use std::collections::{BTreeMap, HashMap};

use rapier3d::dynamics::JointEnabled;
use rapier3d::prelude::{
    ActiveCollisionTypes, ActiveHooks, ColliderHandle, ColliderSet, ImpulseJointHandle,
    ImpulseJointSet, IntegrationParameters, IslandManager, MultibodyJointSet, PhysicsWorld,
    RigidBodyHandle, RigidBodySet,
};

pub use crate::graph::ContainerSource;
pub use rules::{IgnorePredicate, Rule, RuleTable};

use crate::graph::{ContactGraph, NodeId, NodeSource};

/// The shortest timer period accepted, in simulated seconds.
pub const MIN_TIMER_PERIOD: f64 = 1e-6;

/// Mutable parts of a Rapier world that the pre-step changes.
pub struct WorldMut<'a> {
    /// Rigid bodies (enabled flags of passive bodies).
    pub bodies: &'a mut RigidBodySet,
    /// Colliders (hook flags, sensor collision types).
    pub colliders: &'a mut ColliderSet,
    /// Islands (to wake the bodies a rule change concerns).
    pub islands: &'a mut IslandManager,
    /// Integration parameters (solver iterations, caching: the speed-ups).
    pub integration_parameters: &'a mut IntegrationParameters,
    /// Impulse joints (the joints of a passive body are disabled while it is passive).
    pub impulse_joints: &'a mut ImpulseJointSet,
    /// Multibody joints, read only (multibody members are neither made passive nor
    /// fixated: Rapier 0.36 panics on both).
    pub multibody_joints: &'a MultibodyJointSet,
}

impl<'a> From<&'a mut PhysicsWorld> for WorldMut<'a> {
    fn from(w: &'a mut PhysicsWorld) -> Self {
        Self {
            bodies: &mut w.bodies,
            colliders: &mut w.colliders,
            islands: &mut w.islands,
            integration_parameters: &mut w.integration_parameters,
            impulse_joints: &mut w.impulse_joints,
            multibody_joints: &w.multibody_joints,
        }
    }
}

/// Whether a body's slot holds a body of another generation (the body was removed).
fn slot_reused_body(bodies: &RigidBodySet, h: RigidBodyHandle) -> bool {
    let (i, g) = h.into_raw_parts();
    bodies
        .get_unknown_gen(i)
        .is_some_and(|(_, other)| other.into_raw_parts().1 != g)
}

/// The refusal of a passive dynamic multibody member.
fn multibody_refusal(what: &'static str) -> crate::Error {
    crate::Error::Unsupported {
        what,
        reason: "a dynamic multibody member cannot be passive: Rapier 0.36 panics in its \
                 next step on a disabled multibody root while its links are enabled \
                 (the body is left active)",
    }
}

/// The flags a rule member's colliders get.
pub(crate) const RULE_HOOKS: ActiveHooks =
    ActiveHooks::FILTER_CONTACT_PAIRS.union(ActiveHooks::FILTER_INTERSECTION_PAIR);

/// The state of the logic layer.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Logic {
    #[cfg_attr(feature = "serde", serde(with = "crate::logic::serde_rules::rules"))]
    pub(crate) rules: BTreeMap<NodeId, Rule>,
    #[cfg_attr(
        feature = "serde",
        serde(with = "crate::logic::serde_rules::layer_hooks")
    )]
    pub(crate) hooks: crate::logic::hooks::LayerHooks,
    rules_dirty: bool,
    /// Colliders we flagged, with the flags they had before.
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    flagged: HashMap<ColliderHandle, ActiveHooks>,
    /// Sensors we widened, with the collision types they had before.
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_map"))]
    widened: HashMap<ColliderHandle, ActiveCollisionTypes>,
    /// The signature of the colliders the rules flagged (see `pre_step`).
    #[cfg_attr(feature = "serde", serde(default))]
    flagged_sig: u64,
    pub(crate) widen_sensors: bool,
    pub(crate) timers: timers::Timers,
    pub(crate) containers: containers::Containers,
    /// Declared composites: container node → members.
    pub(crate) declared: BTreeMap<NodeId, Vec<NodeId>>,
    /// Passive changes to apply in the pre-step.
    passive_queue: Vec<(RigidBodyHandle, bool)>,
    /// The bodies the layer holds passive (disabled in Rapier), by raw handle.
    pub(crate) passive: BTreeMap<(u32, u32), RigidBodyHandle>,
    /// What the last pre-step refused or undid (see [`Logic::pre_step`]). A report of
    /// one pre-step, not state: not part of a snapshot.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) refusals: Vec<(RigidBodyHandle, crate::Error)>,
    /// Impulse joints the layer disabled because an end is passive, by raw handle:
    /// enabled again once both ends are enabled and not passive.
    held_joints: BTreeMap<(u32, u32), ImpulseJointHandle>,
    /// Scratch: joints of passive bodies to disable.
    scratch_joints: Vec<ImpulseJointHandle>,
    /// Bodies to wake in the pre-step (members of changed rules).
    wake_queue: Vec<RigidBodyHandle>,
    /// Nodes the next analysis must refresh even if asleep.
    pub(crate) force: Vec<NodeId>,
    next_serial: u64,
}

impl Logic {
    pub(crate) fn new() -> Self {
        Self {
            widen_sensors: false,
            ..Self::default()
        }
    }

    pub(crate) fn serial(&mut self) -> u64 {
        self.next_serial += 1;
        self.next_serial
    }

    pub(crate) fn rules_changed(&mut self, members: &[NodeId], graph: &ContactGraph) {
        self.rules_dirty = true;
        for &n in members {
            self.force.push(n);
            if let Some(h) = graph.body_of(n) {
                self.wake_queue.push(h);
            }
        }
    }

    /// Forgets a body removed from the world (its node was removed by the analysis).
    pub(crate) fn forget_body(&mut self, body: RigidBodyHandle) {
        self.passive.remove(&body.into_raw_parts());
    }

    pub(crate) fn queue_passive(&mut self, body: RigidBodyHandle, node: NodeId, passive: bool) {
        self.passive_queue.push((body, passive));
        self.force.push(node);
    }

    /// Rebuilds the rule table (for the hooks and the logical test) from the rules and
    /// the graph. O(rule members).
    fn rebuild_table(&mut self) {
        self.hooks
            .rules
            .rebuild(self.rules.iter().map(|(n, r)| (*n, r.clone())));
    }

    /// The colliders that need the rule hook flags: every collider of every body a rule
    /// names, and named static colliders and sensors.
    fn colliders_needing_flags(
        &self,
        graph: &ContactGraph,
        bodies: &RigidBodySet,
    ) -> Vec<ColliderHandle> {
        let mut out = Vec::new();
        for rule in self.rules.values() {
            for n in rule.members() {
                match graph.node(n).map(|x| x.source()) {
                    Some(NodeSource::Body(h)) => {
                        if let Some(rb) = bodies.get(h) {
                            out.extend(rb.colliders().iter().copied());
                        }
                    }
                    Some(NodeSource::StaticCollider(c)) | Some(NodeSource::Sensor(c)) => {
                        out.push(c);
                    }
                    _ => {}
                }
            }
        }
        out.sort_by_key(|c| c.into_raw_parts());
        out.dedup();
        out
    }

    /// Applies the queued changes to the world. `new_nodes` are the nodes the last
    /// analysis created (its new triggers are widened). Cost: O(1) without rules,
    /// passive bodies or widened sensors; with rules, O(rule members + their
    /// colliders · log) per step to see a member's collider list change; plus
    /// O(new nodes + widened sensors), plus O(colliders) when their count changed.
    // Long: the queued changes are applied in one borrow of the world, phase by phase (commented).
    pub(crate) fn pre_step(
        &mut self,
        graph: &ContactGraph,
        world: &mut WorldMut,
        colliders_changed: bool,
        new_nodes: &[NodeId],
        held: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        // The members' colliders, when rules exist: a member that gained one collider
        // and lost another (the count unchanged), or had one moved to it in place,
        // shows a new signature. O(rule members + their colliders · log) per step
        // with rules, O(1) without.
        let need = if self.rules.is_empty() {
            Vec::new()
        } else {
            self.colliders_needing_flags(graph, world.bodies)
        };
        let need_sig = crate::graph::mirror::colliders_sig(&need);
        let members_changed = need_sig != self.flagged_sig;
        self.flagged_sig = need_sig;
        if self.rules_dirty || (colliders_changed && !self.rules.is_empty()) || members_changed {
            self.rules_dirty = false;
            self.rebuild_table();
            // Restore colliders no longer concerned (and forget removed ones).
            let mut had: Vec<ColliderHandle> = self.flagged.keys().copied().collect();
            had.sort_by_key(|c| c.into_raw_parts());
            for c in had {
                if need
                    .binary_search_by_key(&c.into_raw_parts(), |x| x.into_raw_parts())
                    .is_err()
                {
                    let original = self.flagged.remove(&c).unwrap_or(ActiveHooks::empty());
                    unflag(world.colliders, c, original);
                }
            }
            for c in need {
                if let Some(col) = world.colliders.get_mut(c) {
                    self.flagged.entry(c).or_insert(col.active_hooks());
                    let flags = col.active_hooks() | RULE_HOOKS;
                    if flags != col.active_hooks() {
                        col.set_active_hooks(flags);
                    }
                    // Rapier re-evaluates the pairs only if asked (a resting pair or
                    // a fixed member's would keep its contact), on every rule change.
                    crate::util::rapier::reevaluate_pairs(col);
                }
            }
            // A rule must act on resting pairs too: wake the bodies it concerns.
            let mut wake = std::mem::take(&mut self.wake_queue);
            wake.sort_by_key(|h| h.into_raw_parts());
            wake.dedup();
            for h in wake {
                if world.bodies.contains(h) {
                    world.islands.wake_up(&mut *world.bodies, h, true);
                }
            }
        }
        self.refusals.clear();
        if !self.passive_queue.is_empty()
            || !self.passive.is_empty()
            || !self.held_joints.is_empty()
        {
            self.apply_passive(graph, world, held);
        }
        // Sensors are widened before their first Rapier step: Rapier pairs colliders
        // that do not move only when they appear, so widening later would miss
        // triggers on fixed bodies. Scanned only when the collider count changed; a
        // collider turned into a sensor in place (no count change) is widened once the
        // analysis has made its trigger node.
        if self.widen_sensors && colliders_changed {
            // Read first: `ColliderSet::get_mut` (and `iter_mut`) marks a collider
            // modified for Rapier's step, so only the sensors to widen are written.
            let todo: Vec<ColliderHandle> = world
                .colliders
                .iter()
                .filter(|(c, col)| col.is_sensor() && !self.widened.contains_key(c))
                .map(|(c, _)| c)
                .collect();
            for c in todo {
                let Some(col) = world.colliders.get_mut(c) else {
                    continue;
                };
                self.widened.insert(c, col.active_collision_types());
                col.set_active_collision_types(ActiveCollisionTypes::all());
                crate::util::rapier::reevaluate_pairs(col);
                // Its intersections change in Rapier's step: the trigger (if it has
                // a node already) is read at the next analysis, even if nothing
                // that carries or meets it is refreshed.
                if let Some(t) = graph.node_of_sensor(c) {
                    self.force.push(t);
                }
            }
        }
        if self.widen_sensors {
            for &t in new_nodes {
                let Some(NodeSource::Sensor(c)) = graph.node(t).map(|n| n.source()) else {
                    continue;
                };
                if self.widened.contains_key(&c) {
                    continue;
                }
                let Some(types) = world
                    .colliders
                    .get(c)
                    .filter(|c| c.is_sensor())
                    .map(|c| c.active_collision_types())
                else {
                    continue;
                };
                self.widened.insert(c, types);
                if types != ActiveCollisionTypes::all() {
                    if let Some(col) = world.colliders.get_mut(c) {
                        col.set_active_collision_types(ActiveCollisionTypes::all());
                        crate::util::rapier::reevaluate_pairs(col);
                    }
                    self.force.push(t);
                }
            }
        }
        if !self.widened.is_empty() {
            self.unwiden(graph, world.colliders, !self.widen_sensors);
        }
    }

    /// Gives widened colliders their collision types back where the widening no longer
    /// applies: widening switched off, the collider turned solid in place, or gone.
    /// Types the user changed since are the user's: left as they are. O(widened
    /// sensors) per step while some are widened.
    fn unwiden(&mut self, graph: &ContactGraph, colliders: &mut ColliderSet, all: bool) {
        let mut done: Vec<ColliderHandle> = self
            .widened
            .keys()
            .copied()
            .filter(|&c| all || colliders.get(c).is_none_or(|col| !col.is_sensor()))
            .collect();
        done.sort_by_key(|c| c.into_raw_parts());
        for c in done {
            let Some(original) = self.widened.remove(&c) else {
                continue;
            };
            let ours = colliders
                .get(c)
                .is_some_and(|col| col.active_collision_types() == ActiveCollisionTypes::all());
            if let Some(col) = colliders.get_mut(c).filter(|_| ours) {
                col.set_active_collision_types(original);
                crate::util::rapier::reevaluate_pairs(col);
                // Its intersections change in Rapier's step: read it again after.
                if let Some(t) = graph.node_of_sensor(c) {
                    self.force.push(t);
                }
            }
        }
    }

    /// Undoes everything the logic layer changed in the world, at once: the rules'
    /// hook flags (only the bits the layer added), the sensors' collision types (where
    /// still as the layer set them), the passive bodies (enabled again) and the joints
    /// held disabled for them (enabled again). Rules, timers and containers stay
    /// defined; the next pre-step would apply them again. O(flagged colliders +
    /// widened sensors + passive bodies + held joints).
    pub(crate) fn release(&mut self, graph: &ContactGraph, world: &mut WorldMut) {
        let mut had: Vec<(ColliderHandle, ActiveHooks)> = self.flagged.drain().collect();
        had.sort_by_key(|(c, _)| c.into_raw_parts());
        for (c, original) in had {
            unflag(world.colliders, c, original);
        }
        self.flagged_sig = 0;
        self.rules_dirty = true;
        self.unwiden(graph, world.colliders, true);
        let passive: Vec<RigidBodyHandle> = self.passive.values().copied().collect();
        for h in passive {
            self.passive_queue.push((h, false));
        }
        self.apply_passive(graph, world, &|_| false);
    }

    /// Applies the queued passive changes, then guards the passive bodies against what
    /// Rapier 0.36 panics on. Called by the pre-step when a change is queued, a body is
    /// passive or a joint is held disabled. Cost: O(queued changes + passive bodies +
    /// held joints), the joint part only when the world has impulse joints and the
    /// multibody part only when it has multibodies; O(1) per passive body (plus its
    /// joints).
    ///
    /// Why a guard and not only a check in `set_body_disabled`: the user can change the world
    /// between `set_body_disabled` and the pre-step, or after it, with calls the layer does
    /// not see (a joint added to a passive body). Rapier panics in its next step on:
    /// - a disabled multibody member that the solver needs (the root, or the first link
    ///   under a fixed root) while other links are enabled ("Matrix slicing out of
    ///   bounds" in the contact solver: Rapier does not propagate `set_enabled` to
    ///   multibodies, a `FIXME` in its `user_changes.rs`). Guard: a dynamic multibody
    ///   member is never made passive, and a passive body that became one is made
    ///   active again; both are reported in [`Logic::refusals`].
    /// - an enabled impulse joint between a disabled body and a fixed or disabled one
    ///   ("unreachable" in `interaction_groups.rs`). Rapier marks a disabled body's
    ///   joints `DisabledByAttachedBody` when the body is disabled, but not a joint
    ///   added later, and it enables every `DisabledByAttachedBody` joint of a body
    ///   that is inserted or enabled, whatever the other end (a new fixed body jointed
    ///   to a passive one panics so). Guard: each pre-step, the layer disables every
    ///   joint of a passive body that the user did not disable (`Disabled`, which
    ///   Rapier never changes) and remembers it; it enables it again once both its
    ///   bodies are enabled and not passive. Nothing is lost; a joint the user disabled
    ///   stays disabled.
    ///
    /// `held` tells the bodies the speed-ups hold (fixed to Rapier, dynamic to the
    /// user): they count as dynamic here, since the speed-ups give them back dynamic.
    // Long: disabling and enabling bodies with their joints is one sequence, ordered against Rapier's panics.
    fn apply_passive(
        &mut self,
        graph: &ContactGraph,
        world: &mut WorldMut,
        held: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        let dynamic_member = |world: &WorldMut, h: RigidBodyHandle| {
            world.multibody_joints.rigid_body_link(h).is_some()
                && world
                    .bodies
                    .get(h)
                    .is_some_and(|rb| rb.is_dynamic() || held(h))
        };
        for (h, passive) in std::mem::take(&mut self.passive_queue) {
            if !world.bodies.contains(h) {
                continue; // removed (or another world): skipped
            }
            if passive && dynamic_member(world, h) {
                // Nothing changes: the body stays as it is (active, or passive if it
                // was; a passive member is made active just below).
                self.refusals
                    .push((h, multibody_refusal("set_body_disabled(true)")));
                continue;
            }
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_enabled(!passive);
            }
            if passive {
                self.passive.insert(h.into_raw_parts(), h);
            } else {
                self.passive.remove(&h.into_raw_parts());
            }
        }
        let has_multibodies = world.multibody_joints.multibodies().next().is_some();
        let has_joints = !world.impulse_joints.is_empty();
        let mut undo = Vec::new();
        let mut joints = std::mem::take(&mut self.scratch_joints);
        joints.clear();
        self.passive.retain(|_, &mut h| match world.bodies.get(h) {
            // Removed: forgotten once its slot holds another body (or when the analysis
            // reports the node removed); a world without it (another world handed to
            // the pre-step) loses nothing.
            None => !slot_reused_body(world.bodies, h),
            Some(rb) if rb.is_enabled() => false, // enabled by the user meanwhile
            Some(_) if has_multibodies && dynamic_member(world, h) => {
                undo.push(h);
                false
            }
            Some(_) => {
                if has_joints {
                    for (_, _, j, joint) in world.impulse_joints.attached_joints(h) {
                        if joint.data.enabled != JointEnabled::Disabled {
                            joints.push(j);
                        }
                    }
                }
                true
            }
        });
        for h in undo {
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_enabled(true);
            }
            if let Some(n) = graph.node_of_body(h) {
                self.force.push(n);
            }
            self.refusals
                .push((h, multibody_refusal("a passive body joined to a multibody")));
        }
        joints.sort_by_key(|j| j.into_raw_parts());
        joints.dedup();
        for &j in &joints {
            if let Some(joint) = world.impulse_joints.get_mut(j, false) {
                joint.data.enabled = JointEnabled::Disabled;
                self.held_joints.insert(j.into_raw_parts(), j);
            }
        }
        // Held joints whose two bodies are enabled and not passive are enabled again;
        // removed joints are forgotten.
        joints.clear();
        let passive = &self.passive;
        self.held_joints.retain(|_, &mut j| {
            let Some(joint) = world.impulse_joints.get(j) else {
                // As for passive bodies: forgotten once the slot holds another joint.
                let (i, g) = j.into_raw_parts();
                return world
                    .impulse_joints
                    .get_unknown_gen(i)
                    .is_none_or(|(_, h)| h.into_raw_parts().1 == g);
            };
            let free = |h: RigidBodyHandle| {
                world.bodies.get(h).is_some_and(|rb| rb.is_enabled())
                    && !passive.contains_key(&h.into_raw_parts())
            };
            if free(joint.body1()) && free(joint.body2()) {
                joints.push(j);
                false
            } else {
                true
            }
        });
        for &j in &joints {
            if let Some(joint) = world.impulse_joints.get_mut(j, false) {
                if joint.data.enabled == JointEnabled::Disabled {
                    joint.data.enabled = JointEnabled::Enabled;
                }
            }
        }
        self.scratch_joints = joints;
    }

    /// The colliders the rules flagged, with the hook flags they had before.
    pub(crate) fn rule_flagged(&self) -> &HashMap<ColliderHandle, ActiveHooks> {
        &self.flagged
    }

    /// The sensors the layer widened, with the collision types the user gave them.
    pub(crate) fn widened(&self) -> &HashMap<ColliderHandle, ActiveCollisionTypes> {
        &self.widened
    }

    /// Whether any collider carries a flag set by the layer (rules).
    pub(crate) fn flagged_colliders(&self) -> usize {
        self.flagged.len()
    }
}

/// Takes the rule flags off a collider: only the bits the layer added (those it did
/// not have before), so flags the user set since stay. O(1).
fn unflag(colliders: &mut ColliderSet, c: ColliderHandle, original: ActiveHooks) {
    let added = RULE_HOOKS - original;
    let now = colliders.get(c).map(|col| col.active_hooks());
    if let Some(now) = now.filter(|now| now.intersects(added)) {
        if let Some(col) = colliders.get_mut(c) {
            col.set_active_hooks(now - added);
            crate::util::rapier::reevaluate_pairs(col);
        }
    }
}
