//! The plausibility monitor's test scenes and stepping helpers
//! (`tests/monitor_detect_*.rs`).
#![allow(dead_code)]

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::{
    Monitor, MonitorConfig, Peaks, Violation, ViolationCounts, ViolationKind,
};
use rapier_contact_graph::{ContactLayer, WorldView};
use rcg_scenes::{self as scenes, Scene};

pub const DT: Real = 0.01;

pub fn no_one(_: RigidBodyHandle) -> bool {
    false
}

/// A world with the scenes' settings and a fixed ground slab whose top is `y = 0`.
pub fn world_with_ground() -> PhysicsWorld {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, -9.81, 0.0);
    world.integration_parameters.dt = DT;
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0),
    );
    world
}

pub fn cube(world: &mut PhysicsWorld, at: Vector, half: Real) -> RigidBodyHandle {
    world
        .insert(
            RigidBodyBuilder::dynamic().translation(at),
            ColliderBuilder::cuboid(half, half, half),
        )
        .0
}

pub fn ball(
    world: &mut PhysicsWorld,
    body: RigidBodyBuilder,
    radius: Real,
    e: Real,
) -> RigidBodyHandle {
    world
        .insert(
            body,
            ColliderBuilder::ball(radius)
                .restitution(e)
                .restitution_combine_rule(CoefficientCombineRule::Max),
        )
        .0
}

/// One layer step and one check; returns the step's violations.
pub fn step(
    world: &mut PhysicsWorld,
    layer: &mut ContactLayer,
    monitor: &mut Monitor,
    held: &dyn Fn(RigidBodyHandle) -> bool,
    excepted: &dyn Fn(RigidBodyHandle) -> bool,
) -> Vec<Violation> {
    layer.step(world);
    monitor
        .check(layer, &WorldView::from(&*world), held, excepted)
        .to_vec()
}

/// Runs a scene (script included) for `steps` steps with a primed monitor, nobody held
/// or excepted; returns every violation, the totals and the peaks.
pub fn run_scene(scene: &mut Scene, steps: u64) -> (Vec<Violation>, ViolationCounts, Peaks) {
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    let mut monitor = Monitor::new(MonitorConfig::default()).unwrap();
    monitor.prime(&WorldView::from(&scene.world));
    let mut all = Vec::new();
    for s in 0..steps {
        scene.before_step(s);
        layer.step(&mut scene.world);
        monitor.check(&layer, &WorldView::from(&scene.world), &no_one, &no_one);
        assert_eq!(monitor.last().len(), monitor.last_count());
        all.extend_from_slice(monitor.last());
    }
    let sum: u64 = ViolationKind::ALL
        .iter()
        .map(|&k| all.iter().filter(|v| v.kind == k).count() as u64)
        .sum();
    assert_eq!(
        monitor.totals().total(),
        sum,
        "totals count every violation"
    );
    println!(
        "{:<22} peaks: hang {:.3}, launch {:.3} (excess {:.4} J), penetration {:.3}",
        scene.name,
        monitor.peaks().hang,
        monitor.peaks().launch,
        monitor.peaks().launch_excess,
        monitor.peaks().penetration
    );
    (all, monitor.totals(), monitor.peaks())
}

pub fn bouncing_ball() -> Scene {
    let mut scene = scenes::ball_on_box();
    for (_, c) in scene.world.colliders.iter_mut() {
        c.set_restitution(0.8);
    }
    scene.name = "bounce_e0.8";
    scene
}

/// Two balls rolling into each other on the ground, and two meeting head-on in the air,
/// all with restitution 1 (the most energy a collision can hand over).
pub fn colliding_balls() -> Scene {
    let mut world = world_with_ground();
    let r = 0.5;
    let mut bodies = Vec::new();
    for (name, at, v) in [
        ("rest", [0.0, r, 0.0], [0.0, 0.0, 0.0]),
        ("roller", [-3.0, r, 0.0], [5.0, 0.0, 0.0]),
        ("left", [-3.0, 3.0, 3.0], [4.0, 0.0, 0.0]),
        ("right", [3.0, 3.0, 3.0], [-4.0, 0.0, 0.0]),
    ] {
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::from(at))
            .linvel(Vector::from(v));
        bodies.push((name, ball(&mut world, body, r, 1.0)));
    }
    Scene {
        name: "colliding_balls",
        world,
        bodies,
        script: None,
    }
}

/// The scenes that must stay quiet for the launch check, with their lengths.
pub fn quiet_scenes() -> Vec<(Scene, u64)> {
    vec![
        (scenes::sphere_pile(300, 1), 600),
        (bouncing_ball(), 400),
        (colliding_balls(), 300),
        (scenes::toppling_stack(), 400),
        (scenes::pendulum_wall(), 400),
        (scenes::kinematic_platform(), 300),
        (scenes::diku(&Default::default()), 1000),
    ]
}
