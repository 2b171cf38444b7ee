//! "Is this body on the ground?", asked by Rapier handle under the default tracking:
//! `ContactLayer::is_grounded` follows the chain of supports (contacts pushing a body
//! upwards) down to fixed or kinematic ground. Written as a Rapier user writes it,
//! with `validate()` after every step.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{coherence::Tracking, ContactLayer, Error, Touching};

use common::build::*;

/// A ground, a stack of three cubes on it at the origin, and a ball high above the
/// ground beside the stack; returns the world, the stack (bottom up) and the ball.
fn stack_and_ball() -> (PhysicsWorld, Vec<RigidBodyHandle>, RigidBodyHandle) {
    let (mut world, _) = world_with_ground();
    let stack = stack_of_boxes(&mut world, [0.0, 1.0, 0.0], 3, 0.5);
    let (ball, _) = ball_at(&mut world, [3.0, 10.0, 0.0], 0.5);
    (world, stack, ball)
}

fn step_validated(layer: &mut ContactLayer, world: &mut PhysicsWorld, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

#[test]
fn a_stack_is_grounded_through_its_supports_under_the_default_tracking() {
    let (mut world, stack, ball) = stack_and_ball();
    let mut layer = ContactLayer::new();
    step_validated(&mut layer, &mut world, 30);
    assert!(
        layer.analysis().touching_in_effect(),
        "the default tracking"
    );
    for &b in &stack {
        assert_eq!(layer.is_grounded(&world, b), Ok(true));
    }
    // The top cube rests on the middle one only: grounded through the chain.
    assert_eq!(
        layer.supports_of_body(&world, stack[2], 0.0).unwrap(),
        vec![Touching::Body(stack[1])]
    );
    // The ball is still falling.
    assert!(world.bodies[ball].translation().y > 5.0);
    assert_eq!(layer.is_grounded(&world, ball), Ok(false));
    // The node form reads normals the edges keep only under proximity tracking: under
    // the default it says so, and `is_grounded` is the answer.
    let top = layer.node_of_body(&world.bodies, stack[2]).unwrap();
    assert_eq!(
        layer.analysis().is_supported(top),
        Err(Error::DetailsNotKept)
    );
    // Once landed, the ball is grounded too.
    step_validated(&mut layer, &mut world, 200);
    assert_eq!(layer.is_grounded(&world, ball), Ok(true));
}

#[test]
fn a_body_on_a_kinematic_platform_is_grounded_and_the_ground_itself_is_not() {
    let mut world = PhysicsWorld::new();
    let (platform, _) = world.insert(
        RigidBodyBuilder::kinematic_velocity_based().linvel(Vector::new(0.2, 0.0, 0.0)),
        ColliderBuilder::cuboid(3.0, 0.25, 3.0),
    );
    let (cube, _) = box_at(&mut world, [0.0, 0.75, 0.0], 0.5);
    let mut layer = ContactLayer::new();
    step_validated(&mut layer, &mut world, 60);
    assert_eq!(layer.is_grounded(&world, cube), Ok(true));
    // What holds things up rests on nothing itself.
    assert_eq!(layer.is_grounded(&world, platform), Ok(false));
}

#[test]
fn a_stack_in_free_fall_is_not_grounded() {
    let mut world = PhysicsWorld::new();
    let stack = stack_of_boxes(&mut world, [0.0, 50.0, 0.0], 2, 0.5);
    let mut layer = ContactLayer::new();
    for _ in 0..30 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        for &b in &stack {
            assert_eq!(layer.is_grounded(&world, b), Ok(false));
        }
    }
}

#[test]
fn grounded_answers_alike_under_proximity_tracking_and_while_held() {
    let answers = |mut layer: ContactLayer, steps: usize| {
        let (mut world, stack, ball) = stack_and_ball();
        step_validated(&mut layer, &mut world, steps);
        let mut held = 0;
        for &b in &stack {
            held += usize::from(layer.analysis().holds(&world.bodies, b));
        }
        let grounded: Vec<bool> = stack
            .iter()
            .chain([&ball])
            .map(|&b| layer.is_grounded(&world, b).unwrap())
            .collect();
        (grounded, held)
    };
    let (touching, _) = answers(ContactLayer::new(), 300);
    assert_eq!(touching, vec![true; 4]);
    let (proximity, _) = answers(ContactLayer::with_tracking(Tracking::Proximity), 300);
    assert_eq!(proximity, touching);
    // Held still by the speed-ups (a fixed body to Rapier): still grounded.
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    let (held_answers, held) = answers(layer, 600);
    assert!(held > 0, "the settled stack is held");
    assert_eq!(held_answers, touching);
}

#[test]
fn without_gravity_nothing_is_grounded() {
    let (mut world, stack, _) = stack_and_ball();
    world.gravity = Vector::ZERO;
    let mut layer = ContactLayer::new();
    step_validated(&mut layer, &mut world, 10);
    assert_eq!(layer.is_grounded(&world, stack[0]), Ok(false));
}
