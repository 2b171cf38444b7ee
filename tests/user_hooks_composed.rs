//! The user's own `PhysicsHooks` composed with the layer's (`ContactLayer::hooks_with`),
//! stepping Rapier by hand as a Rapier user does: the user's hooks are called for
//! exactly the pairs the user flagged, whatever the layer flags for its rules and
//! speed-ups.

mod common;

use std::collections::BTreeSet;
use std::sync::Mutex;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Rule, WorldMut, WorldView};

use common::build::*;

type PairSet = BTreeSet<((u32, u32), (u32, u32))>;

/// The user's hooks: filter out contacts between the two "ghost" colliders, zero the
/// restitution of its own flagged pairs; record every call.
#[derive(Default)]
struct UserHooks {
    ghosts: Vec<ColliderHandle>,
    filtered: Mutex<Vec<(ColliderHandle, ColliderHandle)>>,
    modified: Mutex<Vec<(ColliderHandle, ColliderHandle)>>,
}

impl PhysicsHooks for UserHooks {
    fn filter_contact_pair(&self, ctx: &PairFilterContext) -> Option<SolverFlags> {
        self.filtered
            .lock()
            .unwrap()
            .push((ctx.collider1, ctx.collider2));
        let ghost = |c| self.ghosts.contains(&c);
        if ghost(ctx.collider1) && ghost(ctx.collider2) {
            None
        } else {
            Some(SolverFlags::default())
        }
    }

    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        self.modified
            .lock()
            .unwrap()
            .push((ctx.collider1, ctx.collider2));
        if let Some(m) = ctx.rigid_mut() {
            *m.restitution = 0.0;
        }
    }
}

/// A pile of balls on the ground; two ghost balls the user's filter lets through each
/// other, and two bouncy balls whose contacts the user modifies.
fn world() -> (
    PhysicsWorld,
    Vec<RigidBodyHandle>,
    UserHooks,
    Vec<ColliderHandle>,
) {
    let (mut world, _) = world_with_ground();
    let mut bodies = Vec::new();
    let mut colliders = Vec::new();
    for i in 0..16 {
        let at = [(i % 4) as f32 * 0.7 - 1.0, 0.8 + (i / 4) as f32 * 0.7, 0.0];
        let (h, c) = ball_at(&mut world, at, 0.3);
        bodies.push(h);
        colliders.push(c);
    }
    let mut hooks = UserHooks::default();
    for &c in &colliders[..2] {
        world.colliders[c].set_active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
        hooks.ghosts.push(c);
    }
    for &c in &colliders[2..4] {
        world.colliders[c].set_restitution(0.9);
        world.colliders[c].set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
    }
    (world, bodies, hooks, colliders)
}

fn calls(
    v: &Mutex<Vec<(ColliderHandle, ColliderHandle)>>,
) -> Vec<(ColliderHandle, ColliderHandle)> {
    std::mem::take(&mut *v.lock().unwrap())
}

/// An observe-only layer composed with the user's hooks: the same hook calls, in the
/// same order, and the same trajectories as the user's hooks alone, bit for bit.
#[test]
fn an_observing_layer_leaves_the_users_hooks_exactly_as_they_were() {
    let (mut plain, _, mine, _) = world();
    let (mut layered, _, theirs, _) = world();
    let mut layer = ContactLayer::new();
    for step in 0..200 {
        plain.step_with_events(&mine, &());
        layer.pre_step(WorldMut::from(&mut layered));
        layered.step_with_events(&layer.hooks_with(&theirs), &layer.event_handler_with(&()));
        layer.analyze(WorldView::from(&layered));
        layer.validate(&layered).unwrap();
        assert_eq!(
            calls(&mine.filtered),
            calls(&theirs.filtered),
            "step {step}"
        );
        assert_eq!(
            calls(&mine.modified),
            calls(&theirs.modified),
            "step {step}"
        );
        assert_eq!(
            common::pose_bits(&plain),
            common::pose_bits(&layered),
            "step {step}"
        );
    }
}

/// With a rule and every contact speed-up on (the layer flags many colliders), the
/// user's hooks are still called only for pairs with a collider the user flagged, and
/// for every touching pair the user flagged; the rule's pair is filtered; `validate()`
/// passes (rule screening checked against Rapier).
#[test]
fn the_users_hooks_see_only_their_pairs_beside_rules_and_speedups() {
    let (mut world, bodies, hooks, colliders) = world();
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let node = |h| layer.graph().try_node_of_body(h).unwrap();
    let rule = Rule::ignore_pair(node(bodies[8]), node(bodies[12]));
    layer.logic_mut().add_rule(rule).unwrap();
    // reduce and zero flag every dynamic collider for contact modification.
    let mut config = SpeedUps::default();
    config.deepest_contact_only = true;
    config.no_restitution_at_rest = true;
    config.cache = true;
    layer.speedups_mut().set(Some(config)).unwrap();
    let user_filter: Vec<ColliderHandle> = colliders[..2].to_vec();
    let user_modify: Vec<ColliderHandle> = colliders[2..4].to_vec();
    let mut seen_filter: PairSet = BTreeSet::new();
    let mut seen_modify: PairSet = BTreeSet::new();
    for step in 0..240 {
        layer.pre_step(WorldMut::from(&mut world));
        world.step_with_events(&layer.hooks_with(&hooks), &layer.event_handler_with(&()));
        layer.analyze(WorldView::from(&world));
        layer
            .validate(&world)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        for (a, b) in calls(&hooks.filtered) {
            assert!(
                user_filter.contains(&a) || user_filter.contains(&b),
                "step {step}: the user's filter was asked about {a:?}–{b:?}, which the user did not flag"
            );
            seen_filter.insert((a.into_raw_parts(), b.into_raw_parts()));
        }
        for (a, b) in calls(&hooks.modified) {
            assert!(
                user_modify.contains(&a) || user_modify.contains(&b),
                "step {step}: the user's modifier was called for {a:?}–{b:?}, which the user did not flag"
            );
            seen_modify.insert((a.into_raw_parts(), b.into_raw_parts()));
        }
        // Every touching pair the user flagged for modification reached the user's hook.
        for pair in world.narrow_phase.contact_pairs() {
            let user =
                user_modify.contains(&pair.collider1) || user_modify.contains(&pair.collider2);
            if user && pair.has_any_active_contact() {
                let key = (
                    pair.collider1.into_raw_parts(),
                    pair.collider2.into_raw_parts(),
                );
                assert!(
                    seen_modify.contains(&key),
                    "step {step}: {key:?} never reached the user's hook"
                );
            }
        }
    }
    assert!(
        !seen_filter.is_empty() && !seen_modify.is_empty(),
        "the user's hooks ran"
    );
    let (c8, c12) = (colliders[8], colliders[12]);
    let ruled = world
        .narrow_phase
        .contact_pair(c8, c12)
        .is_some_and(|p| p.has_any_active_contact());
    assert!(!ruled, "the rule's pair is filtered");
}
