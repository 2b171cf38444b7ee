//! The speed-ups keep the user's solver iterations unless asked to set their own, and
//! `detach` gives back what the user last set.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldMut};

fn world_with_iterations(n: usize) -> PhysicsWorld {
    let (mut world, _) = common::build::world_with_ground();
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::cuboid(0.25, 0.25, 0.25),
    );
    world.integration_parameters.num_solver_iterations = n;
    world
}

fn iterations(world: &PhysicsWorld) -> usize {
    world.integration_parameters.num_solver_iterations
}

#[test]
fn a_preset_keeps_the_users_solver_iterations() {
    let mut world = world_with_iterations(8);
    let mut layer = ContactLayer::new();
    layer
        .set_speedups(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    for _ in 0..5 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    assert_eq!(iterations(&world), 8);
    // Set by the user while the speed-ups run: kept too.
    world.integration_parameters.num_solver_iterations = 6;
    for _ in 0..5 {
        layer.step(&mut world);
    }
    assert_eq!(iterations(&world), 6);
}

#[test]
fn explicit_and_tweaked_iterations_apply_and_detach_gives_the_users_back() {
    let mut world = world_with_iterations(8);
    let mut layer = ContactLayer::new();
    layer
        .set_speedups(Some(SpeedUps {
            iterations: Some(3),
            ..SpeedUps::reliable_sleep()
        }))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 3);
    layer
        .set_speedups(Some(SpeedUps {
            tweak: true,
            ..SpeedUps::reliable_sleep()
        }))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 1, "tweak_iterations");
    layer
        .set_speedups(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 8, "the user's again");
    layer.detach(WorldMut::from(&mut world));
    assert_eq!(iterations(&world), 8);
}
