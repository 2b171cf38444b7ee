//! Each speed-up switch acts through its mechanism, and the ones that should not
//! change motion do not (paper §7; the realisations are listed in `docs/ARCHITECTURE.md`).

mod common;

use common::build::box_at;
use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, Error};
use rcg_scenes as scenes;

fn layer_with(s: SpeedUps) -> ContactLayer {
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(s)).unwrap();
    layer
}

fn all_asleep(world: &PhysicsWorld) -> bool {
    world
        .bodies
        .iter()
        .filter(|(_, b)| b.is_dynamic())
        .all(|(_, b)| b.is_sleeping())
}

#[test]
fn invalid_parameters_are_refused_and_change_nothing() {
    let mut layer = ContactLayer::new();
    let bad = SpeedUps {
        sleepy_energy: f32::NAN,
        ..SpeedUps::contact_graph()
    };
    assert!(matches!(
        layer.speedups_mut().set(Some(bad)),
        Err(Error::InvalidParameter { .. })
    ));
    assert!(layer.speedups().is_none());
    let bad = SpeedUps {
        fewer_iterations_count: 0,
        ..SpeedUps::contact_graph()
    };
    assert!(layer.speedups_mut().set(Some(bad)).is_err());
}

#[test]
fn a_sleeping_group_never_moves_and_never_sinks() {
    let mut scene = scenes::sphere_stack(4);
    let mut layer = layer_with(SpeedUps::contact_graph());
    let mut slept_at = None;
    for step in 0..400 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        if slept_at.is_none() && all_asleep(&scene.world) {
            slept_at = Some(step);
        }
    }
    let slept_at = slept_at.expect("the layer put the stack to sleep");
    assert!(slept_at < 200, "slept at step {slept_at}");
    let before = common::pose_bits(&scene.world);
    common::run_validated(&mut scene, &mut layer, 400, 300);
    assert_eq!(
        common::pose_bits(&scene.world),
        before,
        "bit-identical while asleep"
    );
    assert!(all_asleep(&scene.world));
}

#[test]
fn the_layer_owns_sleep_rapier_alone_would_not_sleep_earlier() {
    // Without the sleepy switch nothing sleeps at all.
    let mut scene = scenes::sphere_stack(4);
    let mut layer = layer_with(SpeedUps::none());
    common::run_validated(&mut scene, &mut layer, 0, 400);
    assert!(scene.world.bodies.iter().all(|(_, b)| !b.is_sleeping()));
}

#[test]
fn a_ball_dropped_on_a_sleeping_pile_wakes_exactly_the_group_it_hits() {
    let mut scene = scenes::two_piles_with_wall();
    let mut layer = layer_with(SpeedUps::contact_graph());
    common::run_validated(&mut scene, &mut layer, 0, 300);
    assert!(all_asleep(&scene.world), "both piles sleep");
    assert_eq!(layer.groups().len(), 2);
    let ball = scene.world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-0.9, 3.0, 0.0))
            .linvel(Vector::new(0.0, -3.0, 0.0)),
    );
    scene
        .world
        .insert_collider(ColliderBuilder::ball(0.2), Some(ball));
    let left: Vec<_> = ["l0", "l1", "l2", "l3"]
        .iter()
        .map(|n| scene.body(n).unwrap())
        .collect();
    let right: Vec<_> = ["r0", "r1", "r2", "r3"]
        .iter()
        .map(|n| scene.body(n).unwrap())
        .collect();
    let mut left_woke = false;
    for step in 300..400 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        left_woke |= left.iter().all(|&h| !scene.world.bodies[h].is_sleeping());
        assert!(
            right.iter().all(|&h| scene.world.bodies[h].is_sleeping()),
            "the other pile stays asleep (step {step})"
        );
    }
    assert!(left_woke, "the pile that was hit woke as a whole");
}

#[test]
fn tweak_sets_the_iteration_count_and_cache_the_caching() {
    let mut scene = scenes::ball_on_box();
    let mut layer = layer_with(SpeedUps {
        fewer_iterations: true,
        fewer_iterations_count: 2,
        ..SpeedUps::contact_graph()
    });
    common::run_validated(&mut scene, &mut layer, 0, 2);
    let p = &scene.world.integration_parameters;
    assert_eq!(p.num_solver_iterations, 2);
    assert!(
        !p.contact_recycling && p.warmstart_coefficient == 0.0,
        "cache off"
    );
    layer
        .speedups_mut()
        .set(Some(SpeedUps {
            cache: true,
            ..SpeedUps::contact_graph()
        }))
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 2, 1);
    let p = &scene.world.integration_parameters;
    assert_eq!(p.num_solver_iterations, 4);
    assert!(
        p.contact_recycling && p.warmstart_coefficient == 1.0,
        "cache on"
    );
}

/// A box sunk deep into the ground: four contacts, all penetrating.
fn sunk_box() -> (
    PhysicsWorld,
    RigidBodyHandle,
    ColliderHandle,
    ColliderHandle,
) {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    let (_, g) = world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let (b, c) = box_at(&mut world, [0.0, 0.45, 0.0], 0.5);
    (world, b, g, c)
}

fn solver_contacts(world: &PhysicsWorld, c1: ColliderHandle, c2: ColliderHandle) -> usize {
    world
        .narrow_phase
        .contact_pair(c1, c2)
        .map(|p| {
            p.solver_manifolds()
                .iter()
                .map(|m| m.data.solver_contacts.len())
                .sum()
        })
        .unwrap_or(0)
}

#[test]
fn reduce_leaves_one_solver_contact_on_a_deep_pair() {
    let (mut plain, _, g, c) = sunk_box();
    plain.step();
    assert_eq!(
        solver_contacts(&plain, g, c),
        4,
        "without deepest_contact_only: four contacts"
    );
    let (mut world, _, g, c) = sunk_box();
    let mut layer = layer_with(SpeedUps {
        deepest_contact_only: true,
        deepest_contact_depth: 0.01,
        ..SpeedUps::contact_graph()
    });
    layer.step(&mut world);
    assert_eq!(
        solver_contacts(&world, g, c),
        1,
        "with deepest_contact_only: the deepest only"
    );
    assert!(world.colliders[c]
        .active_hooks()
        .contains(ActiveHooks::MODIFY_SOLVER_CONTACTS));
    layer.speedups_mut().set(None).unwrap();
    layer.step(&mut world);
    assert!(
        world
            .colliders
            .iter()
            .all(|(_, c)| c.active_hooks().is_empty()),
        "flags restored"
    );
}

/// A bouncy ball dropped on a resting box; returns the highest point after the bounce.
fn bounce_height(zero: bool) -> f32 {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5).restitution(1.0),
    );
    let mut layer = layer_with(SpeedUps {
        no_restitution_at_rest: zero,
        ..SpeedUps::contact_graph()
    });
    for _ in 0..100 {
        layer.step(&mut world); // the box becomes sleepy
    }
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 2.5, 0.0)),
        ColliderBuilder::ball(0.25).restitution(1.0),
    );
    let mut top_after_bounce = f32::MIN;
    let mut bounced = false;
    for _ in 0..150 {
        layer.step(&mut world);
        let rb = &world.bodies[ball];
        if rb.linvel().y > 0.0 {
            bounced = true;
        }
        if bounced {
            top_after_bounce = top_after_bounce.max(rb.translation().y);
        }
    }
    top_after_bounce
}

#[test]
fn zero_removes_the_bounce_of_a_sleepy_pair() {
    let bouncy = bounce_height(false);
    let zeroed = bounce_height(true);
    assert!(bouncy > 2.0, "restitution 1 bounces back up: {bouncy}");
    assert!(zeroed < 1.4, "zeroed restitution: no bounce ({zeroed})");
}

#[test]
fn damp_sets_and_restores_linear_damping() {
    let mut scene = scenes::ball_on_box();
    let ball = scene.body("ball").unwrap();
    let mut layer = layer_with(SpeedUps {
        viscous_damping: true,
        damping: 0.7,
        ..SpeedUps::contact_graph()
    });
    common::run_validated(&mut scene, &mut layer, 0, 1);
    assert_eq!(scene.world.bodies[ball].linear_damping(), 0.7);
    layer
        .speedups_mut()
        .set(Some(SpeedUps::contact_graph()))
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 1, 1);
    assert_eq!(scene.world.bodies[ball].linear_damping(), 0.0);
}

#[test]
fn fixate_holds_a_body_bit_identical_and_restores_it_exactly() {
    let mut scene = scenes::ball_on_box();
    let bx = scene.body("box").unwrap();
    let mass = scene.world.bodies[bx].mass();
    let mut layer = layer_with(SpeedUps {
        hold: true,
        insulate_sleepy: true,
        ..SpeedUps::contact_graph()
    });
    let mut fixed_at = None;
    for step in 0..300 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        if fixed_at.is_none() && layer.speedups().unwrap().is_fixated(bx) {
            fixed_at = Some(step);
        }
    }
    assert!(fixed_at.is_some(), "the resting box was fixated");
    let pose = *scene.world.bodies[bx].position();
    common::run_validated(&mut scene, &mut layer, 300, 100);
    assert_eq!(
        *scene.world.bodies[bx].position(),
        pose,
        "held bit-identical"
    );
    // A fast body hits it: released, dynamic again, mass restored exactly.
    common::build::hammer(&mut scene.world);
    let mut released = false;
    for step in 400..480 {
        common::run_validated(&mut scene, &mut layer, step, 1);
        if !layer.speedups().unwrap().is_fixated(bx) && scene.world.bodies[bx].is_dynamic() {
            released = true;
            break;
        }
    }
    assert!(released, "released when hit");
    assert_eq!(
        scene.world.bodies[bx].mass().to_bits(),
        mass.to_bits(),
        "mass restored exactly"
    );
}

#[test]
fn subgroup_splits_a_group_at_a_sleepy_body() {
    // A box at rest (sleepy) carrying a frictionless ball that spins in place (never
    // sleepy): the island stays awake, so the box is sleepy but awake. Without
    // subgrouping both form one group; with it the sleepy box insulates.
    let together = |subgroup: bool| {
        let mut world = PhysicsWorld::new();
        world.integration_parameters.dt = 0.01;
        world.insert(
            RigidBodyBuilder::fixed(),
            ColliderBuilder::cuboid(20.0, 0.5, 20.0).translation(Vector::new(0.0, -0.5, 0.0)),
        );
        let (a, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
            ColliderBuilder::cuboid(0.5, 0.5, 0.5).friction(0.0),
        );
        let (b, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 1.3, 0.0))
                .angvel(Vector::new(0.0, 10.0, 0.0)),
            ColliderBuilder::ball(0.3).friction(0.0),
        );
        let mut layer = layer_with(SpeedUps {
            insulate_sleepy: subgroup,
            sleepy_steps: 5,
            ..SpeedUps::contact_graph()
        });
        for _ in 0..60 {
            layer.step(&mut world);
            layer.validate(&world).unwrap();
        }
        let s = layer.speedups().unwrap();
        assert!(
            s.is_sleepy(a) && !s.is_sleepy(b),
            "the box rests, the ball spins"
        );
        assert!(!world.bodies[a].is_sleeping(), "the island is awake");
        let (na, nb) = (
            layer.graph().try_node_of_body(a).unwrap(),
            layer.graph().try_node_of_body(b).unwrap(),
        );
        assert!(layer.graph().touching(na).any(|n| n == nb));
        let g = |n| layer.graph().node(n).unwrap().group();
        g(nb).is_some() && g(na) == g(nb)
    };
    assert!(together(false), "one group without subgrouping");
    assert!(!together(true), "subgrouping: the sleepy box insulates");
}

#[test]
fn groups_do_not_change_motion() {
    let run = |groups: bool| {
        let mut scene = scenes::sphere_pile(150, 4);
        let mut layer = layer_with(SpeedUps {
            groups,
            ..SpeedUps::none()
        });
        for step in 0..300 {
            scene.before_step(step);
            layer.step(&mut scene.world);
        }
        common::pose_bits(&scene.world)
    };
    assert_eq!(run(true), run(false));
}

/// The default speed-ups never turn off a Rapier feature the user had on: warm start
/// and contact recycling stay as the user set them (a user's 0.8 warm start stays
/// 0.8), and come back as the user set them when the speed-ups are switched off.
/// Before, `SpeedUps { hold: true, ..Default::default() }` turned warm start off.
#[test]
fn default_speedups_keep_the_users_warm_start_and_recycling() {
    let mut scene = scenes::ball_on_box();
    scene.world.integration_parameters.warmstart_coefficient = 0.8;
    let mut layer = layer_with(SpeedUps {
        hold: true,
        ..SpeedUps::default()
    });
    common::run_validated(&mut scene, &mut layer, 0, 5);
    let p = &scene.world.integration_parameters;
    assert!(p.contact_recycling, "recycling kept");
    assert_eq!(p.warmstart_coefficient, 0.8, "the user's warm start kept");
    // The paper's configuration turns both off; switching off gives the user's back.
    layer
        .speedups_mut()
        .set(Some(SpeedUps::contact_graph()))
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 5, 2);
    let p = &scene.world.integration_parameters;
    assert!(!p.contact_recycling && p.warmstart_coefficient == 0.0);
    layer.speedups_mut().set(None).unwrap();
    common::run_validated(&mut scene, &mut layer, 7, 2);
    let p = &scene.world.integration_parameters;
    assert!(
        p.contact_recycling && p.warmstart_coefficient == 0.8,
        "the user's own again"
    );
}
