//! Bad-input audit (see `tests/common/audit.rs`): `set_body_disabled` with stale, foreign
//! and removed bodies, and the audit's last table — the states on which Rapier 0.36
//! itself panics (a disabled multibody member, an enabled joint to a disabled body, a
//! multibody link that is not dynamic) and how the layer keeps its calls from
//! reaching them.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Error, WorldMut};

use common::audit::*;
use common::build::*;

#[test]
fn set_passive_with_stale_foreign_and_removed_bodies() {
    let (mut world, _, ball, mut layer) = stepped(2);
    let (_, removed) = stale_node(&mut layer, &mut world);
    assert_eq!(
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, removed, true),
        Err(Error::UnknownBody(removed))
    );
    for f in foreign_bodies(ball) {
        assert_eq!(
            layer.logic_mut().set_body_disabled(&world.bodies, f, true),
            Err(Error::UnknownBody(f))
        );
    }
    // Another world's set, even where the handle is valid in it.
    let other = foreign_world(3);
    assert_eq!(
        layer
            .logic_mut()
            .set_body_disabled(&other.bodies, ball, true),
        Err(Error::ForeignWorld)
    );
    // Queued, then removed from the world before the pre-step (wrong time): the
    // pre-step skips it.
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, true)
        .unwrap();
    world.remove_body(ball);
    no_panic("passive on a removed body", || layer.step(&mut world));
    // Removed and not analysed yet: refused at once, as every call taking the world
    // answers, and the same after the step.
    let (spare, _) = ball_at(&mut world, [3.0, 1.0, 0.0], 0.5);
    layer.step(&mut world);
    world.remove_body(spare);
    for _ in 0..2 {
        for h in [ball, spare] {
            assert_eq!(
                layer.logic_mut().set_body_disabled(&world.bodies, h, false),
                Err(Error::UnknownBody(h))
            );
        }
        layer.step(&mut world);
    }
    layer.validate(&world).unwrap();
}

/// A floor, a chain root – link (a multibody) and a free ball overlapping the link,
/// stepped once; a ball `spare` that is no multibody member.
fn multibody_scene() -> (PhysicsWorld, ContactLayer, [RigidBodyHandle; 3]) {
    let mut world = PhysicsWorld::new();
    let (root, link) = multibody_chain(&mut world);
    let (spare, _) = ball_at(&mut world, [2.0, 0.5, 0.0], 0.25);
    let mut layer = ContactLayer::new();
    layer.step(&mut world);
    (world, layer, [root, link, spare])
}

#[test]
fn rapier_panics_set_passive_on_a_multibody_member_is_refused() {
    let (mut world, mut layer, [root, link, spare]) = multibody_scene();
    // At the call: a `Link` node (the root and the link) is refused, nothing changes.
    for h in [root, link] {
        assert!(matches!(
            layer.logic_mut().set_body_disabled(&world.bodies, h, true),
            Err(Error::Unsupported { .. })
        ));
    }
    no_panic("steps after refused set_body_disabled", || {
        for _ in 0..3 {
            layer.step(&mut world);
        }
    });
    assert!(world.bodies[root].is_enabled() && world.bodies[link].is_enabled());
    assert!(layer.logic().refusals().is_empty());
    // Wrong time: joined to the multibody between `set_body_disabled` and the pre-step.
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, spare, true)
        .unwrap();
    world
        .insert_multibody_joint(link, spare, chain_joint())
        .unwrap();
    no_panic("step after a refused queued change", || {
        layer.step(&mut world)
    });
    assert!(world.bodies[spare].is_enabled());
    assert_eq!(layer.logic().refusals().len(), 1);
    assert_eq!(layer.logic().refusals()[0].0, spare);
    assert!(matches!(
        layer.logic().refusals()[0].1,
        Error::Unsupported { .. }
    ));
    layer.validate(&world).unwrap();
    no_panic("the next step", || layer.step(&mut world));
    assert!(
        layer.logic().refusals().is_empty(),
        "cleared by every pre-step"
    );
    // Making a member active is always accepted.
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, root, false)
        .unwrap();
    no_panic("set_body_disabled(false) on a member", || {
        layer.step(&mut world)
    });
    layer.validate(&world).unwrap();
}

#[test]
fn rapier_panics_a_passive_body_joined_to_a_multibody_is_made_active_again() {
    let (mut world, mut layer, [_, _, spare]) = multibody_scene();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, spare, true)
        .unwrap();
    layer.step(&mut world);
    assert!(!world.bodies[spare].is_enabled());
    // The user makes the passive body the root of a new multibody whose link rests on
    // the floor (a contact of the link: Rapier's solver panics on it).
    let (other, _) = ball_at(&mut world, [2.0, 0.2, 0.0], 0.25);
    world
        .insert_multibody_joint(spare, other, RevoluteJointBuilder::new(Vector::Z))
        .unwrap();
    no_panic("step with a passive multibody root", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(world.bodies[spare].is_enabled(), "made active again");
}

#[test]
fn rapier_panics_joints_of_passive_bodies_are_held_disabled() {
    let (mut world, ground, ball, mut layer) = stepped(3);
    for x in [-2.0, 2.0] {
        ball_at(&mut world, [x, 1.0, 0.0], 0.5);
    }
    layer.step(&mut world);
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, true)
        .unwrap();
    layer.step(&mut world);
    // Joints added by the user to the passive body: to the fixed ground, and to a new
    // fixed body (Rapier enables the `DisabledByAttachedBody` joints of a body it
    // inserts, whatever the other end).
    let j1 = world.insert_impulse_joint(ground, ball, FixedJointBuilder::new());
    let (post, _) = fixed_box_at(&mut world, [4.0, 1.0, 0.0], 0.4);
    let j2 = world.insert_impulse_joint(post, ball, FixedJointBuilder::new());
    // A joint the user disabled himself.
    let mut off: GenericJoint = FixedJointBuilder::new().into();
    off.set_enabled(false);
    let j3 = world.insert_impulse_joint(ground, ball, off);
    no_panic("steps with joints to a passive body", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    let enabled = |w: &PhysicsWorld, j| w.impulse_joints.get(j).unwrap().data.is_enabled();
    assert!(!enabled(&world, j1) && !enabled(&world, j2) && !enabled(&world, j3));
    // Active again: the layer's joints come back, the user's stays disabled.
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, false)
        .unwrap();
    no_panic("steps after set_body_disabled(false)", || {
        for _ in 0..3 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(enabled(&world, j1) && enabled(&world, j2) && !enabled(&world, j3));
    // Another world handed to the pre-step loses nothing.
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, true)
        .unwrap();
    layer.step(&mut world);
    assert!(!enabled(&world, j1));
    let mut other = PhysicsWorld::new();
    no_panic("pre_step on another world", || {
        layer.pre_step(WorldMut::from(&mut other))
    });
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, ball, false)
        .unwrap();
    layer.step(&mut world);
    assert!(enabled(&world, j1), "still held, enabled again");
}

#[test]
fn rapier_panics_a_deferred_fixation_is_checked_again_when_applied() {
    let (mut world, _) = world_with_ground();
    let (root, _) = ball_at(&mut world, [-2.0, 1.0, 0.0], 0.5);
    let (link, _) = ball_at(&mut world, [2.0, 1.0, 0.0], 0.5);
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
    assert!(layer.speedups().unwrap().stats().fixations > 0);
    // Wrong time: between the decision and its application, the body becomes a link.
    world
        .insert_multibody_joint(root, link, RevoluteJointBuilder::new(Vector::Z))
        .unwrap();
    no_panic("steps after a deferred fixation of a new link", || {
        for _ in 0..5 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
    });
    assert!(world.bodies[link].is_dynamic());
}
