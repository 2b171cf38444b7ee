//! The physics hooks the layer gives Rapier: rules (pair filters) and the contact
//! speed-ups (`deepest_contact_only`, `no_restitution_at_rest`) — one object, because Rapier takes one.
//!
//! Rapier calls a hook only for pairs where one collider carries the hook's
//! `ActiveHooks` flag, and a flagged pair is never contact-recycled, so flags go only
//! where a feature needs them: rule members' colliders for the filters, and for the
//! contact modifications the colliders the speed-up concerns (all dynamic colliders
//! for `deepest_contact_only`; sleepy bodies' colliders for `no_restitution_at_rest`). Without rules and speed-ups no flag
//! is set, the hooks are never called and results are bit-identical to `&()`.

use rapier3d::pipeline::{
    ActiveHooks, ContactModificationContext, PairFilterContext, PhysicsHooks,
};
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle, SolverFlags};

use crate::graph::{ContactGraph, NodeId};
use crate::logic::RuleTable;

/// The contact modifications of the speed-ups, read by the hooks during a step.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactMods {
    /// Keep only the deepest solver contact of pairs penetrating deeper than this
    /// (metres); `None`: off.
    pub deepest_contact_depth: Option<f32>,
    /// Zero the restitution of pairs with a sleepy body.
    pub no_restitution_at_rest: bool,
    /// Sleepy bodies by handle index (with generation), for `no_restitution_at_rest`.
    pub(crate) sleepy: Vec<Option<u32>>,
}

impl ContactMods {
    pub(crate) fn set_sleepy(&mut self, h: RigidBodyHandle, sleepy: bool) {
        let (i, g) = h.into_raw_parts();
        let i = i as usize;
        if self.sleepy.len() <= i {
            self.sleepy.resize(i + 1, None);
        }
        self.sleepy[i] = sleepy.then_some(g);
    }

    /// Whether a body is marked sleepy for the hooks. O(1).
    pub fn is_sleepy(&self, h: RigidBodyHandle) -> bool {
        let (i, g) = h.into_raw_parts();
        self.sleepy.get(i as usize).copied().flatten() == Some(g)
    }
}

/// The state of the layer's physics hooks (rules and contact modifications). Rapier is
/// handed a [`HooksView`] of it, which also sees the graph.
#[derive(Clone, Debug, Default)]
pub struct LayerHooks {
    pub(crate) rules: RuleTable,
    pub(crate) mods: ContactMods,
}

impl LayerHooks {
    /// The rules in force.
    pub fn table(&self) -> &RuleTable {
        &self.rules
    }
    /// The contact modifications in force.
    pub fn mods(&self) -> &ContactMods {
        &self.mods
    }
}

/// The physics hooks the layer gives Rapier: its hook state plus the graph, so that a
/// rule can be asked about any pair of nodes (a predicate rule's member against a body
/// the rule does not name). Get one with [`crate::ContactLayer::hooks`] when stepping
/// Rapier yourself:
///
/// ```
/// use rapier3d::prelude::*;
/// use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};
///
/// let mut world = PhysicsWorld::new();
/// let mut layer = ContactLayer::new();
/// layer.pre_step(WorldMut::from(&mut world));
/// world.step_with_events(&layer.hooks(), &());
/// layer.analyze(WorldView::from(&world));
/// ```
#[derive(Clone, Copy)]
pub struct HooksView<'a> {
    pub(crate) state: &'a LayerHooks,
    pub(crate) graph: &'a ContactGraph,
}

impl<'a> HooksView<'a> {
    /// The rules in force.
    pub fn table(&self) -> &'a RuleTable {
        &self.state.rules
    }
    /// The contact modifications in force.
    pub fn mods(&self) -> &'a ContactMods {
        &self.state.mods
    }

    /// The node a collider stands for in a rule: a sensor's trigger (none before the
    /// analysis made it: never its carrier body, whose rules do not reach the trigger
    /// it carries), a static collider's own node, else its body's.
    fn node_of(
        &self,
        ctx: &PairFilterContext,
        body: Option<RigidBodyHandle>,
        collider: ColliderHandle,
    ) -> Option<NodeId> {
        if ctx.colliders.get(collider).is_some_and(|c| c.is_sensor()) {
            return self.graph.node_of_sensor(collider);
        }
        // Rapier's parent, not the graph's last view: a collider moved in place
        // (`set_parent`) since the last analysis belongs to its new body already.
        match body {
            Some(b) => self.graph.node_of_body(b),
            None => self.graph.node_of_static_collider(collider),
        }
    }

    fn ignores(&self, ctx: &PairFilterContext) -> bool {
        let rules = &self.state.rules;
        if rules.is_empty() {
            return false;
        }
        match (
            self.node_of(ctx, ctx.rigid_body1, ctx.collider1),
            self.node_of(ctx, ctx.rigid_body2, ctx.collider2),
        ) {
            (Some(a), Some(b)) => rules.ignores(a, b),
            _ => false,
        }
    }
}

impl PhysicsHooks for HooksView<'_> {
    fn filter_contact_pair(&self, ctx: &PairFilterContext) -> Option<SolverFlags> {
        if self.ignores(ctx) {
            None
        } else {
            Some(SolverFlags::default())
        }
    }

    fn filter_intersection_pair(&self, ctx: &PairFilterContext) -> bool {
        !self.ignores(ctx)
    }

    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        let mods = &self.state.mods;
        let zero = mods.no_restitution_at_rest
            && (ctx.rigid_body1.is_some_and(|h| mods.is_sleepy(h))
                || ctx.rigid_body2.is_some_and(|h| mods.is_sleepy(h)));
        let reduce = mods.deepest_contact_depth;
        let Some(m) = ctx.rigid_mut() else { return };
        if zero {
            *m.restitution = 0.0;
        }
        if let Some(depth) = reduce {
            if m.solver_contacts.len() > 1 {
                // Keep the single deepest contact of a deeply penetrating pair (§7).
                let mut deepest = 0;
                for (i, c) in m.solver_contacts.iter().enumerate() {
                    if c.dist < m.solver_contacts[deepest].dist {
                        deepest = i;
                    }
                }
                if -m.solver_contacts[deepest].dist > depth {
                    m.solver_contacts.swap(0, deepest);
                    m.solver_contacts.truncate(1);
                }
            }
        }
    }
}

/// The layer's hooks together with the user's own `PhysicsHooks`, for users who step
/// Rapier themselves (Rapier takes one hooks object). Made by
/// [`crate::ContactLayer::hooks_with`].
///
/// The contract, hook by hook (a collider is *user-flagged* for a hook when it carries
/// the hook's `ActiveHooks` flag by the user's doing, not only because the layer added
/// it for a rule or a speed-up):
/// - `filter_contact_pair` / `filter_intersection_pair`: a pair a rule of the layer
///   ignores is filtered out (the user's hook is not asked: the pair does not exist for
///   the simulation). Otherwise the user's hook decides if either collider is
///   user-flagged, and the pair is kept as Rapier would keep it if neither is.
/// - `modify_solver_contacts`: the user's hook runs first if either collider is
///   user-flagged for it, then the speed-ups' modifications if the layer flagged one.
///
/// So the user's hooks are called for exactly the pairs the user flagged (a rule
/// aside), as without the layer. With no rule and no speed-up the layer flags nothing
/// and the composition behaves exactly as the user's hooks alone (tested bit for bit).
/// Cost: O(1) per call, plus two hash lookups per collider of a flagged pair.
pub struct HooksWith<'a, H: ?Sized> {
    pub(crate) layer: HooksView<'a>,
    /// Colliders the rules flagged, with the hook flags they had before.
    pub(crate) rule_flagged: &'a std::collections::HashMap<ColliderHandle, ActiveHooks>,
    /// Colliders the speed-ups flagged for contact modification, with their former
    /// flags.
    pub(crate) modify_flagged:
        Option<&'a std::collections::BTreeMap<(u32, u32), (ColliderHandle, ActiveHooks)>>,
    pub(crate) user: &'a H,
}

impl<H: ?Sized> HooksWith<'_, H> {
    /// Whether the layer added `flag` to the collider (it did not carry it before).
    fn layer_added(&self, c: ColliderHandle, flag: ActiveHooks) -> bool {
        let by_rule = self.rule_flagged.get(&c).is_some_and(|before| {
            crate::logic::RULE_HOOKS.contains(flag) && !before.contains(flag)
        });
        let by_speedups = self.modify_flagged.is_some_and(|m| {
            flag == ActiveHooks::MODIFY_SOLVER_CONTACTS
                && m.get(&c.into_raw_parts())
                    .is_some_and(|(_, before)| !before.contains(flag))
        });
        by_rule || by_speedups
    }

    /// Whether the collider carries `flag` by the user's doing.
    fn user_flagged(
        &self,
        colliders: &rapier3d::geometry::ColliderSet,
        c: ColliderHandle,
        flag: ActiveHooks,
    ) -> bool {
        colliders
            .get(c)
            .is_some_and(|co| co.active_hooks().contains(flag))
            && !self.layer_added(c, flag)
    }

    /// Whether either collider of the pair carries `flag` by the user's doing.
    fn users_pair(&self, ctx: &PairFilterContext, flag: ActiveHooks) -> bool {
        self.user_flagged(ctx.colliders, ctx.collider1, flag)
            || self.user_flagged(ctx.colliders, ctx.collider2, flag)
    }

    /// Whether the layer flagged the collider for contact modification.
    fn layer_modifies(&self, c: ColliderHandle) -> bool {
        self.modify_flagged
            .is_some_and(|m| m.contains_key(&c.into_raw_parts()))
    }
}

impl<H: PhysicsHooks + ?Sized> PhysicsHooks for HooksWith<'_, H> {
    fn filter_contact_pair(&self, ctx: &PairFilterContext) -> Option<SolverFlags> {
        if self.layer.ignores(ctx) {
            return None;
        }
        if self.users_pair(ctx, ActiveHooks::FILTER_CONTACT_PAIRS) {
            self.user.filter_contact_pair(ctx)
        } else {
            Some(SolverFlags::default())
        }
    }

    fn filter_intersection_pair(&self, ctx: &PairFilterContext) -> bool {
        if self.layer.ignores(ctx) {
            return false;
        }
        if self.users_pair(ctx, ActiveHooks::FILTER_INTERSECTION_PAIR) {
            self.user.filter_intersection_pair(ctx)
        } else {
            true
        }
    }

    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        let flag = ActiveHooks::MODIFY_SOLVER_CONTACTS;
        let (c1, c2) = (ctx.collider1, ctx.collider2);
        if self.user_flagged(ctx.colliders, c1, flag) || self.user_flagged(ctx.colliders, c2, flag)
        {
            self.user.modify_solver_contacts(ctx);
        }
        if self.layer_modifies(c1) || self.layer_modifies(c2) {
            self.layer.modify_solver_contacts(ctx);
        }
    }
}
