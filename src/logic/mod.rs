//! The logic layer (paper §2's logical and container nodes, §3.2's logical testing):
//! rules, triggers, timers, passive bodies, containers.
//!
//! # When changes take effect
//! The graph changes at once: `add_rule` returns the rule's node, with its logical
//! edges, immediately. What must touch the Rapier world (hook flags, enabling or
//! disabling a passive body, sensor collision types) is queued and applied in the
//! *pre-step* (DESIGN §2, step 1): [`crate::ContactLayer::step`] does it before
//! Rapier's step; users who step Rapier themselves call
//! [`crate::ContactLayer::pre_step`]. Their effect on edges and events shows after
//! that step's analysis.
//!
//! # Pay for what you use
//! A scene without rules gets no hook flag; without timers no timer work; the sensor
//! collision types are widened only on sensor colliders (which never push bodies, so
//! motion is unchanged).

pub(crate) mod containers;
pub(crate) mod rules;
pub(crate) mod timers;

use std::collections::{BTreeMap, HashMap};

use rapier3d::prelude::{
    ActiveCollisionTypes, ActiveHooks, ColliderHandle, ColliderSet, IntegrationParameters,
    IslandManager, PhysicsWorld, RigidBodyHandle, RigidBodySet,
};

pub use containers::ContainerSource;
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
}

impl<'a> From<&'a mut PhysicsWorld> for WorldMut<'a> {
    fn from(w: &'a mut PhysicsWorld) -> Self {
        Self {
            bodies: &mut w.bodies,
            colliders: &mut w.colliders,
            islands: &mut w.islands,
            integration_parameters: &mut w.integration_parameters,
        }
    }
}

/// The flags a rule member's colliders get.
const RULE_HOOKS: ActiveHooks =
    ActiveHooks::FILTER_CONTACT_PAIRS.union(ActiveHooks::FILTER_INTERSECTION_PAIR);

/// The state of the logic layer.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Logic {
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::rules"))]
    pub(crate) rules: BTreeMap<NodeId, Rule>,
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::layer_hooks"))]
    pub(crate) hooks: crate::hooks::LayerHooks,
    rules_dirty: bool,
    /// Colliders we flagged, with the flags they had before.
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::sorted_map"))]
    flagged: HashMap<ColliderHandle, ActiveHooks>,
    /// Sensors we widened, with the collision types they had before.
    #[cfg_attr(feature = "serde", serde(with = "crate::snapshot::sorted_map"))]
    widened: HashMap<ColliderHandle, ActiveCollisionTypes>,
    pub(crate) widen_sensors: bool,
    pub(crate) timers: timers::Timers,
    pub(crate) containers: containers::Containers,
    /// Declared composites: container node → members.
    pub(crate) declared: BTreeMap<NodeId, Vec<NodeId>>,
    /// Passive changes to apply in the pre-step.
    passive_queue: Vec<(RigidBodyHandle, bool)>,
    /// Bodies to wake in the pre-step (members of changed rules).
    wake_queue: Vec<RigidBodyHandle>,
    /// Nodes the next analysis must refresh even if asleep.
    pub(crate) force: Vec<NodeId>,
    next_serial: u64,
}

impl Logic {
    pub(crate) fn new() -> Self {
        Self {
            widen_sensors: true,
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

    /// Applies the queued changes to the world. Cost: O(1) when nothing is queued, else
    /// O(rule members + their colliders).
    pub(crate) fn pre_step(
        &mut self,
        graph: &ContactGraph,
        world: &mut WorldMut,
        colliders_changed: bool,
    ) {
        if self.rules_dirty || (colliders_changed && !self.rules.is_empty()) {
            self.rules_dirty = false;
            self.rebuild_table();
            let need = self.colliders_needing_flags(graph, world.bodies);
            // Restore colliders no longer concerned (and forget removed ones).
            let mut had: Vec<ColliderHandle> = self.flagged.keys().copied().collect();
            had.sort_by_key(|c| c.into_raw_parts());
            for c in had {
                if need
                    .binary_search_by_key(&c.into_raw_parts(), |x| x.into_raw_parts())
                    .is_err()
                {
                    let original = self.flagged.remove(&c).unwrap_or(ActiveHooks::empty());
                    if let Some(col) = world.colliders.get_mut(c) {
                        col.set_active_hooks(original);
                    }
                }
            }
            for c in need {
                if let Some(col) = world.colliders.get_mut(c) {
                    self.flagged.entry(c).or_insert(col.active_hooks());
                    let flags = col.active_hooks() | RULE_HOOKS;
                    if flags != col.active_hooks() {
                        col.set_active_hooks(flags);
                    }
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
        for (h, passive) in std::mem::take(&mut self.passive_queue) {
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_enabled(!passive);
            }
        }
        // Sensors are widened before their first Rapier step: Rapier pairs colliders
        // that do not move only when they appear, so widening later would miss
        // triggers on fixed bodies. Scanned only when the collider count changed.
        if self.widen_sensors && colliders_changed {
            for (c, col) in world.colliders.iter_mut() {
                if col.is_sensor() && !self.widened.contains_key(&c) {
                    self.widened.insert(c, col.active_collision_types());
                    col.set_active_collision_types(ActiveCollisionTypes::all());
                }
            }
        }
    }

    /// Whether any collider carries a flag set by the layer.
    pub(crate) fn flagged_colliders(&self) -> usize {
        self.flagged.len()
    }
}
