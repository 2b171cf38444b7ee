//! Minimised regression tests of the bugs `tests/fuzz_operations.rs` found: `bug_*`
//! are ignored until fixed (each fails when run with `--ignored`), `fixed_*` were
//! fixed meanwhile (each failed when found).
//!
//! Joints, containers, multibodies and passive bodies: containers that follow joints
//! and type changes, groups of removed containers, `set_body_disabled` on multibody members,
//! joints to passive bodies, and fixations deferred to a pre-step.

mod common;

#[allow(dead_code)]
#[path = "common/fuzz/mod.rs"]
mod harness;

use rapier3d::prelude::*;
use rapier_contact_graph::{Category, ContactLayer, EdgeKind, Error, NodeKind, WorldView};

use common::build::*;

fn containers(layer: &ContactLayer) -> Vec<(NodeKind, usize)> {
    let g = layer.graph();
    let mut v: Vec<_> = g
        .nodes()
        .filter(|(_, n)| n.kind().category() == Category::Container)
        .map(|(id, n)| (n.kind(), g.neighbors(id).count()))
        .collect();
    v.sort();
    v
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_containers_follow_a_jointed_body_changing_type() {
    let mut world = PhysicsWorld::new();
    let a = world
        .insert(RigidBodyBuilder::fixed(), ColliderBuilder::ball(0.5))
        .0;
    let b = ball_at(&mut world, [1.0, 0.0, 0.0], 0.5).0;
    world.insert_impulse_joint(a, b, FixedJointBuilder::new());
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    assert!(
        containers(&layer).is_empty(),
        "a fixed body joins no container"
    );
    // Both bodies dynamic now: Rapier's joint makes them one composite.
    world.bodies[a].set_body_type(RigidBodyType::Dynamic, true);
    layer.analysis_mut().request_full_sync(); // as the docs ask for a fixed body changed in place
    layer.step(&mut world);
    let mut fresh = ContactLayer::new();
    fresh.analyze(WorldView::from(&world));
    assert_eq!(containers(&fresh), vec![(NodeKind::Composite, 2)]);
    // Failed before the fix: the layer has no container (the joint signature, counts only, did not
    // change, and `request_full_sync` does not force the container sync).
    assert_eq!(containers(&layer), containers(&fresh));
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_containers_follow_a_joint_swapped_for_another_between_steps() {
    let mut world = PhysicsWorld::new();
    let mut body = |x: f32| ball_at(&mut world, [x, 0.0, 0.0], 0.4).0;
    let (a, b, c) = (body(0.0), body(1.0), body(5.0));
    let j = world.insert_impulse_joint(a, b, FixedJointBuilder::new());
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    let ca = layer.graph().try_node_of_body(c).unwrap();
    // The composite moves from (a, b) to (a, c): same number of joints.
    world.remove_impulse_joint(j);
    world.insert_impulse_joint(a, c, FixedJointBuilder::new());
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    let in_container = |n| {
        layer
            .graph()
            .neighbors(n)
            .any(|(_, _, e)| e.kind() == EdgeKind::Structural)
    };
    // Failed before the fix: c is in no container (the layer still has the (a, b) composite).
    assert!(in_container(ca), "c is jointed to a now");
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_a_fixated_jointed_body_leaves_its_container() {
    use rapier_contact_graph::speedups::SpeedUps;
    let (mut world, _) = world_with_ground();
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5).0;
    let b = ball_at(&mut world, [1.0, 1.0, 0.0], 0.5).0;
    world.insert_impulse_joint(
        a,
        b,
        FixedJointBuilder::new().local_anchor2(Vector::new(-1.0, 0.0, 0.0)),
    );
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps {
            hold: true,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    for _ in 0..100 {
        layer.step(&mut world);
    }
    let held = layer.speedups().unwrap().fixated().count();
    assert!(held > 0, "the resting pair is fixated");
    layer.validate(&world).unwrap();
    let mut fresh = ContactLayer::new();
    fresh.analyze(WorldView::from(&world));
    // Failed before the fix: the layer keeps the composite of the two bodies although (at least) one
    // of them is now a fixed body, which "never joins a container"; a fresh layer
    // has no container.
    assert_eq!(containers(&layer), containers(&fresh));
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_a_removed_container_of_passive_bodies_leaves_its_group() {
    let (mut world, _) = world_with_ground();
    let a = ball_at(&mut world, [0.0, 3.0, 0.0], 0.4).0;
    let b = ball_at(&mut world, [1.0, 3.0, 0.0], 0.4).0;
    let j = world.insert_impulse_joint(a, b, FixedJointBuilder::new());
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, a, true)
        .unwrap();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, b, true)
        .unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    // The container is now a group of its own (its members, passive, are in none).
    world.remove_impulse_joint(j);
    layer.step(&mut world);
    // Failed before the fix: "group .. holds dead node ..": `Containers::sync` removes the
    // container's node without dissolving its group; only the members' groups are
    // disturbed, and passive members have none.
    layer.validate(&world).unwrap();
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_switching_subgroup_off_regroups_a_container() {
    use rapier_contact_graph::speedups::SpeedUps;
    let (mut world, _) = world_with_ground();
    let joint = || FixedJointBuilder::new().local_anchor2(Vector::new(-1.0, 0.0, 0.0));
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5).0;
    let b = ball_at(&mut world, [1.0, 1.0, 0.0], 0.5).0;
    world.insert_impulse_joint(a, b, joint());
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    // A third member whose node comes after the composite's (validate() checks an
    // edge's groups from its A side only).
    let c = ball_at(&mut world, [2.0, 1.0, 0.0], 0.5).0;
    world.insert_impulse_joint(b, c, joint());
    layer
        .speedups_mut()
        .set(Some(SpeedUps {
            insulate_sleepy: true,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    for _ in 0..100 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    assert!(
        world.bodies[c].is_sleeping(),
        "the composite rests and sleeps"
    );
    layer.speedups_mut().set(None).unwrap();
    layer.step(&mut world);
    // Failed before the fix: "edge .. joins groups Some(..) and None": under subgrouping the sleepy
    // members insulated, so the composite's node was grouped alone; once the switch
    // is off they no longer insulate, and nothing regroups them (sleeping groups
    // persist).
    layer.validate(&world).unwrap();
}

/// Panicked when this fuzzing found it ("Matrix slicing out of bounds" in Rapier's
/// `GenericRhs::apply_impulse`: Rapier 0.36 does not carry a disabled multibody
/// root with enabled links); `set_body_disabled` refuses multibody members since.
#[test]
fn fixed_set_passive_on_a_multibody_member_is_refused() {
    let mut world = PhysicsWorld::new();
    let (root, link) = multibody_chain(&mut world);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    for body in [root, link] {
        match layer
            .logic_mut()
            .set_body_disabled(&world.bodies, body, true)
        {
            Err(Error::Unsupported { .. }) => {}
            other => panic!("set_body_disabled(true) on a multibody member: {other:?}"),
        }
        // Making it active is always accepted (a no-op here).
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, body, false)
            .unwrap();
    }
    for _ in 0..5 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    assert!(world.bodies[root].is_enabled() && world.bodies[link].is_enabled());
    assert!(layer.logic().refusals().is_empty());
}

/// The same, reached around `set_body_disabled`'s own check: the body becomes a multibody
/// member between `set_body_disabled` and the pre-step, or after it was made passive.
#[test]
fn fixed_a_passive_body_joined_to_a_multibody_is_made_active_again() {
    // Joined between `set_body_disabled` and the pre-step: refused there.
    let mut world = PhysicsWorld::new();
    arena_floor(&mut world);
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.25).0;
    let b = ball_at(&mut world, [0.0, 0.5, 0.0], 0.25).0;
    ball_at(&mut world, [0.0, 0.5, 0.0], 0.25); // overlaps b
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, a, true)
        .unwrap();
    let joint = chain_joint();
    world.insert_multibody_joint(a, b, joint).unwrap();
    layer.step(&mut world);
    assert!(
        world.bodies[a].is_enabled(),
        "the queued change was refused"
    );
    assert_eq!(layer.logic().refusals().len(), 1);
    assert_eq!(layer.logic().refusals()[0].0, a);
    assert!(matches!(
        layer.logic().refusals()[0].1,
        Error::Unsupported { .. }
    ));
    layer.validate(&world).unwrap();
    layer.step(&mut world);
    assert!(layer.logic().refusals().is_empty(), "reported once");

    // Joined after the body was made passive: made active again.
    let mut world = PhysicsWorld::new();
    arena_floor(&mut world);
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.25).0;
    let b = ball_at(&mut world, [0.0, 0.5, 0.0], 0.25).0;
    ball_at(&mut world, [0.0, 0.5, 0.0], 0.25);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, a, true)
        .unwrap();
    layer.step(&mut world);
    assert!(!world.bodies[a].is_enabled());
    let na = layer.graph().try_node_of_body(a).unwrap();
    assert!(layer.graph().node(na).unwrap().is_body_disabled());
    world.insert_multibody_joint(a, b, joint).unwrap();
    for _ in 0..5 {
        layer.step(&mut world); // panicked in Rapier's step before the guard
        layer.validate(&world).unwrap();
    }
    assert!(world.bodies[a].is_enabled(), "made active again");
    assert!(!layer.graph().node(na).unwrap().is_body_disabled());
}

/// Panicked when this fuzzing found it ("entered unreachable code" in Rapier's
/// `interaction_groups.rs`: an enabled joint between two bodies the solver sees as
/// fixed; plain Rapier does the same with `set_enabled(false)`, since it disables a
/// disabled body's joints only when the body is disabled). The layer disables the
/// joints of its passive bodies in every pre-step since.
#[test]
fn fixed_a_joint_to_a_passive_body_is_disabled_while_it_is_passive() {
    for other_passive in [false, true] {
        let mut world = PhysicsWorld::new();
        arena_floor(&mut world);
        let passive = ball_at(&mut world, [0.0, 0.5, 0.0], 0.25).0;
        let other = ball_at(&mut world, [0.0, 0.5, 0.0], 0.25).0;
        for _ in 0..3 {
            ball_at(&mut world, [0.0, 0.5, 0.0], 0.25); // all overlapping
        }
        if !other_passive {
            world.bodies[other].set_body_type(RigidBodyType::Fixed, true);
        }
        let mut layer = ContactLayer::new();
        layer.step(&mut world);
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, passive, true)
            .unwrap();
        if other_passive {
            layer
                .logic_mut()
                .set_body_disabled(&world.bodies, other, true)
                .unwrap();
        }
        layer.step(&mut world);
        // A joint between a passive body and a fixed (or passive) one, added by the
        // user: Rapier's step panicked on it.
        let j = world.insert_impulse_joint(other, passive, FixedJointBuilder::new());
        for _ in 0..5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
        assert!(!world.impulse_joints.get(j).unwrap().data.is_enabled());
        // Active again: Rapier enables the joint with the body (and a passive other
        // end has it disabled again at the next pre-step).
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, passive, false)
            .unwrap();
        for _ in 0..5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
        assert!(world.bodies[passive].is_enabled());
        assert_eq!(
            world.impulse_joints.get(j).unwrap().data.is_enabled(),
            !other_passive
        );
        if other_passive {
            layer
                .logic_mut()
                .set_body_disabled(&world.bodies, other, false)
                .unwrap();
            for _ in 0..5 {
                layer.step(&mut world);
                layer.validate(&world).unwrap();
            }
            assert!(world.impulse_joints.get(j).unwrap().data.is_enabled());
        }
        // A joint the user disabled stays disabled through a passive spell.
        let k = world.insert_impulse_joint(other, passive, FixedJointBuilder::new());
        world
            .impulse_joints
            .get_mut(k, false)
            .unwrap()
            .data
            .set_enabled(false);
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, passive, true)
            .unwrap();
        layer.step(&mut world);
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, passive, false)
            .unwrap();
        layer.step(&mut world);
        assert!(!world.impulse_joints.get(k).unwrap().data.is_enabled());
        assert!(world.impulse_joints.get(j).unwrap().data.is_enabled());
    }
}

/// Failed when this fuzzing found it; passes now.
#[test]
fn fixed_a_collider_added_to_a_passive_body_gets_no_edges() {
    let mut world = PhysicsWorld::new();
    let (cube, _) = box_at(&mut world, [0.0, 1.0, -0.5], 0.25);
    world.insert_collider(
        ColliderBuilder::cuboid(0.4, 0.25, 0.4).translation(Vector::new(0.0, 0.5, 0.0)),
        None,
    );
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, cube, true)
        .unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    // A second collider on the passive body (Rapier enables it and pairs it with
    // the static box), and an awake ball, so that the pair array is scanned.
    world.insert_collider(ColliderBuilder::ball(0.3), Some(cube));
    ball_at(&mut world, [0.0, 0.5, 0.0], 0.25);
    layer.step(&mut world);
    // Failed before the fix: "passive node .. has physical or geometric edges": the scan makes the
    // edge of every Rapier pair (`edge_of_pair`) before its passive screen refuses
    // to feed it.
    layer.validate(&world).unwrap();
}

/// Panicked when this fuzzing found it ("A rigid-body that is not at the root of a
/// multibody must be dynamic", Rapier's multibody.rs: the pre-step applied the
/// fixation decided at the last analysis to what had become a multibody link). The
/// pre-step checks the body again since, and releases a held body joined as a link.
#[test]
fn fixed_a_deferred_fixation_of_a_new_multibody_link_is_skipped() {
    use rapier_contact_graph::speedups::SpeedUps;
    for already_held in [false, true] {
        let (mut world, _) = world_with_ground();
        let root = ball_at(&mut world, [-2.0, 1.0, 0.0], 0.5).0;
        let link = ball_at(&mut world, [2.0, 1.0, 0.0], 0.5).0;
        let mut layer = ContactLayer::new();
        layer
            .speedups_mut()
            .set(Some(SpeedUps {
                hold: true,
                ..SpeedUps::contact_graph()
            }))
            .unwrap();
        for _ in 0..200 {
            layer.step(&mut world);
            if layer.speedups().unwrap().stats().fixations > 0 {
                break;
            }
        }
        assert!(
            layer.speedups().unwrap().stats().fixations > 0,
            "fixations decided"
        );
        assert!(
            world.bodies[link].is_dynamic(),
            "applied at the next pre-step only"
        );
        if already_held {
            layer.step(&mut world);
            assert!(layer.speedups().unwrap().is_fixated(link), "held");
            assert!(world.bodies[link].is_fixed());
            // Rapier accepts the held (fixed) body as a link, then asserts in its
            // step that a link is dynamic.
            world
                .insert_multibody_joint(root, link, RevoluteJointBuilder::new(Vector::Z))
                .unwrap();
        } else {
            // The user joins the still dynamic body to a multibody, as a link.
            world
                .insert_multibody_joint(root, link, RevoluteJointBuilder::new(Vector::Z))
                .unwrap();
        }
        for _ in 0..5 {
            layer.step(&mut world); // panicked in Rapier's step before the guard
            layer.validate(&world).unwrap();
        }
        assert!(world.bodies[link].is_dynamic(), "a link stays dynamic");
        assert!(!layer.speedups().unwrap().is_fixated(link));
    }
}

/// Found by the 10,000-sequence run after the first joint guard, which marked a
/// passive body's joints `DisabledByAttachedBody` as Rapier does: a new fixed body
/// jointed to a passive (kinematic) one panicked in Rapier's step all the same
/// ("entered unreachable code", `interaction_groups.rs`), because Rapier enables
/// every `DisabledByAttachedBody` joint of a body it inserts or enables, whatever
/// the other end. Passes since the layer disables such joints as `Disabled` and
/// enables them itself once both ends are active.
#[test]
fn fixed_a_new_fixed_body_jointed_to_a_passive_body_does_not_panic() {
    let (mut world, floor) = world_with_ground();
    // Awake bodies in the majority: Rapier then looks at every joint, not only at
    // those of awake bodies.
    for x in [-2.0, 0.0, 2.0] {
        ball_at(&mut world, [x, 1.0, 0.0], 0.5);
    }
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, floor, true)
        .unwrap();
    layer.step(&mut world);
    let (post, _) = fixed_box_at(&mut world, [3.0, 1.0, 0.0], 0.4);
    world.bodies[floor].set_body_type(RigidBodyType::KinematicVelocityBased, true);
    layer.analysis_mut().request_full_sync(); // a passive body changed in place
    let j = world.insert_impulse_joint(post, floor, FixedJointBuilder::new());
    for _ in 0..3 {
        layer.step(&mut world); // panicked here
        layer.validate(&world).unwrap();
    }
    assert!(!world.impulse_joints.get(j).unwrap().data.is_enabled());
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, floor, false)
        .unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    assert!(world.impulse_joints.get(j).unwrap().data.is_enabled());
}

/// The fixed floor made passive through the layer (disabled), a wall's collider moved
/// onto it, a ball joined to it as a multibody link, then the floor given another
/// type: Rapier's solver graph check (debug builds only) fails in the next step
/// ("solver contact graph diverged from the from-scratch selection"), in plain Rapier
/// as well (`upstream_a_disabled_multibody_root_with_a_collider_moved_onto_it_given_a_type`
/// below). The fuzzer changes no disabled multibody member's type. Found by a long run
/// with `PROPTEST_RNG_SEED=45`, shrunk.
#[test]
#[ignore = "limit (upstream): a type given to a disabled multibody root with a collider moved onto it trips Rapier's solver graph check"]
fn limit_a_disabled_multibody_root_with_a_collider_moved_onto_it_given_a_type() {
    use harness::{run_unsteered, Config, Op, Ty};
    let ops = [
        Op::Passive(0, true),
        Op::Step(1),
        Op::SetParent(1, Some(0)),
        Op::Ball {
            x: 0,
            y: 0,
            z: 0,
            r: 0,
        },
        Op::Multibody { a: 30, b: 61 },
        Op::Step(1),
        Op::SetType(62, Ty::KinematicVelocity),
        Op::Step(1),
    ];
    run_unsteered(Config::Touching, &ops, true).unwrap();
}

/// The limit above in plain Rapier, no layer: a disabled fixed body with a collider
/// moved onto it, a multibody link joined to it, a step, then its type changed (to any
/// type). Rapier 0.36.1's solver graph check fails in the next step; should an update
/// stop it, this test fails and the limit and the fuzzer's steering can go.
#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "solver contact graph diverged")]
fn upstream_a_disabled_multibody_root_with_a_collider_moved_onto_it_given_a_type() {
    let mut w = harness::arena();
    let floor = w.bodies.iter().next().map(|(h, _)| h).unwrap();
    w.bodies[floor].set_enabled(false);
    w.step();
    let wall = w.colliders.iter().nth(1).map(|(h, _)| h).unwrap();
    let PhysicsWorld {
        colliders, bodies, ..
    } = &mut w;
    colliders.set_parent(wall, Some(floor), bodies);
    let (ball, _) = ball_at(&mut w, [0.0, 0.5, 0.0], 0.25);
    let _ = w.insert_multibody_joint(
        floor,
        ball,
        RevoluteJointBuilder::new(Vector::Z).local_anchor2(Vector::new(0.0, 0.6, 0.0)),
    );
    w.step();
    w.bodies[floor].set_body_type(RigidBodyType::Dynamic, true);
    for _ in 0..3 {
        w.step();
    }
}
