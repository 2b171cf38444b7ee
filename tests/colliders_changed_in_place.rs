//! Colliders changed in place between two steps: moved to another body, detached,
//! turned into sensors, and one layer handed a different world. The graph follows
//! without a full sync where Rapier wakes what the change concerns, and always after
//! `request_full_sync`; `validate()` after every step.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::{ContactLayer, Rule, WorldMut, WorldView};

use common::build::*;

fn run(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize, what: &str) {
    for i in 0..steps {
        layer.step(world);
        if let Err(e) = layer.validate(&*world) {
            panic!("{what}: step {i}: {e}");
        }
    }
}

fn both_trackings(test: impl Fn(Tracking)) {
    test(Tracking::Proximity);
    test(Tracking::Touching);
}

/// A collider moved from one resting box to another (`ColliderSet::set_parent`): the
/// edges follow it. Failed before the owner cache was checked against the body's own
/// collider list ("Rapier pair ... has no edge").
#[test]
fn a_collider_moved_to_another_body_takes_its_contacts_along() {
    both_trackings(|tracking| {
        let (mut world, _) = world_with_ground();
        let (a, _) = box_at(&mut world, [-1.0, 1.0, 0.0], 0.4);
        let (b, _) = box_at(&mut world, [1.0, 1.0, 0.0], 0.4);
        let extra = world.insert_collider(
            ColliderBuilder::ball(0.3).translation(Vector::new(0.0, -0.3, 0.6)),
            Some(a),
        );
        let mut layer = ContactLayer::new();
        layer.set_tracking(tracking);
        run(&mut layer, &mut world, 60, "settle");
        world
            .colliders
            .set_parent(extra, Some(b), &mut world.bodies);
        run(&mut layer, &mut world, 60, "moved to b");
        world.colliders.set_parent(extra, None, &mut world.bodies);
        run(&mut layer, &mut world, 60, "detached");
        world
            .colliders
            .set_parent(extra, Some(a), &mut world.bodies);
        run(&mut layer, &mut world, 60, "back on a");
    });
}

/// A collider moved between two sleeping bodies, then a full sync: always exact.
/// Failed before a full sync cleared the owner cache.
#[test]
fn a_full_sync_after_set_parent_on_sleeping_bodies_gives_the_exact_graph() {
    both_trackings(|tracking| {
        let (mut world, ground) = world_with_ground();
        let (a, _) = box_at(&mut world, [-1.0, 1.0, 0.0], 0.4);
        let extra = world.insert_collider(
            ColliderBuilder::cuboid(0.2, 0.2, 0.2).translation(Vector::new(0.0, -0.2, 0.0)),
            Some(a),
        );
        let mut layer = ContactLayer::new();
        layer.set_tracking(tracking);
        run(&mut layer, &mut world, 300, "settle");
        assert!(world.bodies[a].is_sleeping());
        world
            .colliders
            .set_parent(extra, Some(ground), &mut world.bodies);
        layer.analysis_mut().request_full_sync();
        run(&mut layer, &mut world, 30, "to the ground, synced");
    });
}

/// A body that gains one collider and loses another in the same step (the collider
/// count unchanged) keeps an exact graph.
#[test]
fn a_body_swapping_colliders_in_one_step_keeps_an_exact_graph() {
    both_trackings(|tracking| {
        let (mut world, _) = world_with_ground();
        let (a, first) = box_at(&mut world, [0.0, 1.0, 0.0], 0.4);
        let mut layer = ContactLayer::new();
        layer.set_tracking(tracking);
        run(&mut layer, &mut world, 40, "settle");
        world.remove_collider(first);
        world.insert_collider(ColliderBuilder::ball(0.45), Some(a));
        run(&mut layer, &mut world, 40, "swapped");
    });
}

/// A collider of a fixed body over fixed ground turned into a sensor in place, with
/// and without a full sync.
#[test]
fn a_fixed_bodys_collider_turned_sensor_over_fixed_ground_validates() {
    for (sync, static_ground, widen) in [
        (false, false, true),
        (true, false, true),
        (false, true, true),
        (true, true, true),
        (true, false, false),
        (true, true, false),
    ] {
        both_trackings(|tracking| {
            let mut world = PhysicsWorld::new();
            if static_ground {
                common::build::static_ground(&mut world);
            } else {
                ground(&mut world);
            }
            let (_, post) = fixed_box_at(&mut world, [0.0, 0.9, 0.0], 0.5);
            ball_at(&mut world, [0.0, 3.0, 0.0], 0.3);
            let mut layer = ContactLayer::new();
            layer.logic_mut().set_trigger_widening(widen);
            layer.set_tracking(tracking);
            run(&mut layer, &mut world, 5, "before");
            world.colliders[post].set_sensor(true);
            if sync {
                layer.analysis_mut().request_full_sync();
            }
            run(&mut layer, &mut world, 10, "sensor");
            world.colliders[post].set_sensor(false);
            if sync {
                layer.analysis_mut().request_full_sync();
            }
            run(&mut layer, &mut world, 10, "solid again");
        });
    }
}

/// One layer stepping two worlds of equal body and collider counts in turn: the
/// layer notices the other world and resynchronises (documented), so it validates
/// against whichever world it stepped last.
#[test]
fn one_layer_stepping_two_worlds_resynchronises_to_each() {
    let make = |x: f32| {
        let (mut world, _) = world_with_ground();
        ball_at(&mut world, [x, 1.0, 0.0], 0.5);
        box_at(&mut world, [x + 2.0, 3.0, 0.0], 0.5);
        world
    };
    let (mut w1, mut w2) = (make(0.0), make(-2.0));
    let mut layer = ContactLayer::new();
    for i in 0..120 {
        let w = if i % 2 == 0 { &mut w1 } else { &mut w2 };
        layer.step(w);
        if let Err(e) = layer.validate(w) {
            panic!("step {i}: {e}");
        }
    }
}

/// A ball resting on the ground and another dropped on it from `height`, a rule
/// ignoring the pair added after one step: the world, the layer, the first ball
/// (body, collider) and the two nodes.
fn ball_ignoring_another(
    height: f32,
) -> (
    PhysicsWorld,
    ContactLayer,
    (RigidBodyHandle, ColliderHandle),
    (rapier_contact_graph::NodeId, rapier_contact_graph::NodeId),
) {
    let (mut world, _) = world_with_ground();
    let first = ball_at(&mut world, [0.0, 0.8, 0.0], 0.3);
    let (b, _) = ball_at(&mut world, [0.0, height, 0.0], 0.3);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let na = layer.graph().try_node_of_body(first.0).unwrap();
    let nb = layer.graph().try_node_of_body(b).unwrap();
    layer
        .logic_mut()
        .add_rule(Rule::ignore_pair(na, nb))
        .unwrap();
    (world, layer, first, (na, nb))
}

/// A rule's member gains one collider and loses another in the same step (the
/// collider count unchanged): the new collider gets the rule's hook flags and
/// Rapier filters its pairs. Failed before the rules watched their members'
/// collider lists (the flags were redone only when the collider count changed).
#[test]
fn a_rule_follows_its_members_collider_swap() {
    let (mut world, mut layer, (a, first), (na, nb)) = ball_ignoring_another(1.2);
    run(&mut layer, &mut world, 5, "rule");
    world.remove_collider(first);
    let second = world.insert_collider(ColliderBuilder::ball(0.35), Some(a));
    run(&mut layer, &mut world, 30, "swapped");
    assert!(
        world.colliders[second]
            .active_hooks()
            .contains(ActiveHooks::FILTER_CONTACT_PAIRS),
        "the new collider carries the rule's flag"
    );
    let touching = layer
        .graph()
        .edge_between(na, nb)
        .and_then(|e| layer.graph().edge(e))
        .is_some_and(|e| e.is_touching());
    assert!(!touching, "the rule still screens the pair");
}

/// A collider moved in place from static geometry to a body named by a rule: Rapier's
/// hooks name it by its new body at once. Failed before the hooks asked Rapier for the
/// collider's parent (they took the graph's last view, a static collider).
#[test]
fn a_rule_applies_to_a_collider_moved_onto_a_member() {
    let (mut world, _) = world_with_ground();
    let wall = world.insert_collider(
        ColliderBuilder::cuboid(0.2, 1.0, 1.0).translation(Vector::new(1.0, 1.5, 0.0)),
        None,
    );
    let (a, _) = ball_at(&mut world, [0.0, 0.8, 0.0], 0.3);
    let (b, _) = ball_at(&mut world, [1.0, 0.8, 0.0], 0.3);
    let mut layer = ContactLayer::new();
    run(&mut layer, &mut world, 2, "start");
    world.colliders.set_parent(wall, Some(a), &mut world.bodies);
    layer.analysis_mut().request_full_sync();
    layer.logic_mut().ignore_pair(&world, a, b).unwrap();
    run(&mut layer, &mut world, 20, "moved, then ruled");
}

/// A predicate rule, and a body created overlapping its member: for its first step the
/// hooks cannot name the new body (it has no node yet), so Rapier collides the pair and
/// the graph shows it; from the next step the rule applies. `validate()` passes at
/// every step, and checks that every pair the graph screens is one Rapier filtered.
#[test]
fn a_predicate_rule_meets_a_new_body_consistently() {
    let (mut world, _) = world_with_ground();
    let (a, _) = ball_at(&mut world, [0.0, 0.8, 0.0], 0.3);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let na = layer.graph().try_node_of_body(a).unwrap();
    layer
        .logic_mut()
        .add_rule(Rule::ignore_if(&[na], |_, _| true))
        .unwrap();
    run(&mut layer, &mut world, 3, "rule");
    ball_at(&mut world, [0.2, 0.8, 0.0], 0.3);
    run(&mut layer, &mut world, 20, "new body next to the member");
}

/// A user stepping Rapier with their own hooks instead of the layer's: the rules are
/// not applied, and `validate()` says so instead of passing.
#[test]
fn validate_sees_a_rule_rapier_did_not_apply() {
    let (mut world, mut layer, _, _) = ball_ignoring_another(1.6);
    let mut failed = None;
    for i in 0..60 {
        layer.pre_step(WorldMut::from(&mut world));
        world.step_with_events(&(), &());
        layer.analyze(WorldView::from(&world));
        if let Err(e) = layer.validate(&world) {
            failed = Some((i, e.to_string()));
            break;
        }
    }
    let (_, message) = failed.expect("validate() reports the rule Rapier did not apply");
    assert!(message.contains("Rapier collides it"), "{message}");
}
