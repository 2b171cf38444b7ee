//! The speed-ups keep the user's solver settings unless changing one is the speed-up
//! asked for: iterations (unless `iterations` or `fewer_iterations` says otherwise), warm start
//! and contact recycling (unless `cache` is off); and `detach` gives back what the
//! user last set, per-body sleep thresholds and damping included.

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
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
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
        .speedups_mut()
        .set(Some(SpeedUps {
            iterations: Some(3),
            ..SpeedUps::reliable_sleep()
        }))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 3);
    layer
        .speedups_mut()
        .set(Some(SpeedUps {
            fewer_iterations: true,
            ..SpeedUps::reliable_sleep()
        }))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 1, "fewer_iterations_count");
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    layer.step(&mut world);
    assert_eq!(iterations(&world), 8, "the user's again");
    layer.detach(WorldMut::from(&mut world));
    assert_eq!(iterations(&world), 8);
}

/// Runs `preset` for `steps` steps with `validate()` after each.
fn run(world: &mut PhysicsWorld, layer: &mut ContactLayer, steps: usize) {
    for _ in 0..steps {
        layer.step(world);
        layer.validate(&*world).unwrap();
    }
}

#[test]
fn presets_with_cache_keep_the_users_warm_start_and_recycling() {
    for preset in [
        SpeedUps::default(),
        SpeedUps::reliable_sleep(),
        SpeedUps::papers_fastest(),
    ] {
        let mut world = world_with_iterations(4);
        world.integration_parameters.warmstart_coefficient = 0.5;
        world.integration_parameters.contact_recycling = false;
        let mut layer = ContactLayer::new();
        layer.speedups_mut().set(Some(preset.clone())).unwrap();
        run(&mut world, &mut layer, 30);
        let p = &world.integration_parameters;
        assert_eq!(
            (p.warmstart_coefficient, p.contact_recycling),
            (0.5, false),
            "{}",
            rcg_lab::table5::label(&preset)
        );
        // Changed by the user while the preset runs: the user's again.
        world.integration_parameters.warmstart_coefficient = 0.8;
        world.integration_parameters.contact_recycling = true;
        run(&mut world, &mut layer, 5);
        layer.detach(WorldMut::from(&mut world));
        let p = &world.integration_parameters;
        assert_eq!(
            (p.warmstart_coefficient, p.contact_recycling),
            (0.8, true),
            "{} after detach",
            rcg_lab::table5::label(&preset)
        );
    }
}

#[test]
fn detach_gives_back_the_users_sleep_thresholds_and_damping() {
    let mut world = world_with_iterations(4);
    let h = world.bodies.iter().find(|(_, b)| b.is_dynamic()).unwrap().0;
    {
        let rb = &mut world.bodies[h];
        let a = rb.activation_mut();
        a.normalized_linear_threshold = 0.3;
        a.angular_threshold = 0.7;
        a.time_until_sleep = 5.0;
        rb.set_linear_damping(0.25);
    }
    let mut layer = ContactLayer::new();
    // The paper's fastest preset owns sleeping (thresholds) and damps every body.
    layer
        .speedups_mut()
        .set(Some(SpeedUps::papers_fastest()))
        .unwrap();
    run(&mut world, &mut layer, 40);
    assert_ne!(world.bodies[h].activation().time_until_sleep, 5.0);
    layer.detach(WorldMut::from(&mut world));
    let rb = &world.bodies[h];
    let a = rb.activation();
    assert_eq!(
        (
            a.normalized_linear_threshold,
            a.angular_threshold,
            a.time_until_sleep,
            rb.linear_damping()
        ),
        (0.3, 0.7, 5.0, 0.25)
    );
}
