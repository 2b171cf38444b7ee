//! A body the speed-ups hold is fixed to Rapier, and Rapier cannot step a fixed body
//! everywhere a dynamic one goes: as a multibody's member, or jointed to a disabled
//! body, it panics. What the user joins a held body to, the layer releases it from
//! before Rapier's next step, and it never holds such a body (paper §7, fixation).

mod common;

use common::build::{ball_at, world_with_ground};
use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;

/// Steps through the layer, `validate()` after each step.
fn run(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

/// Two balls resting side by side on the ground, jointed, stepped until the pile
/// preset holds the second. The layer, the world and the two balls.
fn held_jointed_pair() -> (ContactLayer, PhysicsWorld, RigidBodyHandle, RigidBodyHandle) {
    let (mut world, _) = world_with_ground();
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5).0;
    let b = ball_at(&mut world, [1.0, 1.0, 0.0], 0.5).0;
    let joint = SphericalJointBuilder::new().local_anchor1(Vector::new(1.0, 0.0, 0.0));
    world.impulse_joints.insert(a, b, joint, true);
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    let held = |layer: &ContactLayer| layer.speedups().is_some_and(|s| s.is_fixated(b));
    for _ in 0..600 {
        if held(&layer) {
            break;
        }
        run(&mut layer, &mut world, 1);
    }
    assert!(held(&layer), "the pile preset holds a resting ball");
    (layer, world, a, b)
}

#[test]
fn a_held_body_whose_joint_partner_the_user_disables_is_released() {
    let (mut layer, mut world, a, b) = held_jointed_pair();
    world.bodies[a].set_enabled(false);
    run(&mut layer, &mut world, 60);
    assert!(!layer.speedups().unwrap().is_fixated(b));
    assert!(world.bodies[b].is_dynamic());
    assert!(
        !world.bodies[a].is_enabled(),
        "the user's call keeps its effect"
    );
}

#[test]
fn a_body_jointed_to_a_disabled_one_is_never_held() {
    let (mut world, _) = world_with_ground();
    let a = ball_at(&mut world, [0.0, 1.0, 0.0], 0.5).0;
    let b = ball_at(&mut world, [1.0, 1.0, 0.0], 0.5).0;
    let joint = SphericalJointBuilder::new().local_anchor1(Vector::new(1.0, 0.0, 0.0));
    world.impulse_joints.insert(a, b, joint, true);
    world.bodies[a].set_enabled(false);
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    for _ in 0..400 {
        run(&mut layer, &mut world, 1);
        assert!(!layer.speedups().unwrap().is_fixated(b));
    }
}

#[test]
fn a_held_body_the_user_makes_a_multibody_root_is_released() {
    let (mut layer, mut world, a, b) = held_jointed_pair();
    let c = ball_at(&mut world, [1.0, 2.0, 0.0], 0.5).0;
    let link = SphericalJointBuilder::new().local_anchor1(Vector::new(0.0, 1.0, 0.0));
    world.multibody_joints.insert(b, c, link, true).unwrap();
    run(&mut layer, &mut world, 60);
    assert!(!layer.speedups().unwrap().is_fixated(b));
    assert!(world.bodies[b].is_dynamic() && world.bodies[c].is_dynamic());
    assert!(world.bodies[a].is_enabled());
}

#[test]
fn a_held_body_the_user_makes_a_multibody_link_is_released() {
    let (mut layer, mut world, _, b) = held_jointed_pair();
    let c = ball_at(&mut world, [1.0, 2.0, 0.0], 0.5).0;
    let link = SphericalJointBuilder::new().local_anchor1(Vector::new(0.0, -1.0, 0.0));
    world.multibody_joints.insert(c, b, link, true).unwrap();
    run(&mut layer, &mut world, 60);
    assert!(!layer.speedups().unwrap().is_fixated(b));
    assert!(world.bodies[b].is_dynamic());
}

#[test]
fn a_held_passive_body_the_user_makes_a_multibody_root_is_made_active_again() {
    let (mut layer, mut world, _, b) = held_jointed_pair();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, b, true)
        .unwrap();
    run(&mut layer, &mut world, 1);
    let c = ball_at(&mut world, [1.0, 2.0, 0.0], 0.5).0;
    let link = SphericalJointBuilder::new().local_anchor1(Vector::new(0.0, 1.0, 0.0));
    world.multibody_joints.insert(b, c, link, true).unwrap();
    run(&mut layer, &mut world, 1);
    assert!(
        world.bodies[b].is_enabled(),
        "a multibody member cannot be passive"
    );
    assert!(
        !layer.logic().refusals().is_empty(),
        "and the layer says so"
    );
    run(&mut layer, &mut world, 60);
}
