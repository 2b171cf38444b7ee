//! Snapshot and restore: a world and its layer saved to bytes (Rapier's serde and
//! `ContactLayer::snapshot`, bincode), loaded, and stepped beside the original. The pair
//! must continue bit for bit: poses, events, the graph's text form and the full layer
//! state (its snapshot bytes) are compared after every step, and both layers are
//! validated after every step.
#![cfg(feature = "serde")]

mod common;
#[path = "common/twins.rs"]
mod twins;

use std::sync::Arc;

use common::build::ball_at;
use common::pose_bits;
use rapier3d::prelude::*;
use rapier_contact_graph::logic::IgnorePredicate;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::{ContactLayer, NodeId};
use rcg_scenes::{self as scenes, Scene};

use twins::*;

// ── Rapier alone ────────────────────────────────────────────────────────────

/// A scene with impulse joints (a fixed pair and a hinged pair) on a floor.
fn jointed_boxes() -> Scene {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = scenes::DT;
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let mut bodies = Vec::new();
    let names = ["a", "b", "c", "d"];
    for (i, x) in [-3.0f32, -2.4, 2.0, 2.6].into_iter().enumerate() {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, 1.5 + 0.3 * i as f32, 0.0))
                .angvel(Vector::new(0.0, 0.0, 1.0)),
            ColliderBuilder::cuboid(0.25, 0.25, 0.25),
        );
        bodies.push((names[i], h));
    }
    let anchors = |b: FixedJointBuilder| {
        b.local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0))
    };
    world.insert_impulse_joint(bodies[0].1, bodies[1].1, anchors(FixedJointBuilder::new()));
    world.insert_impulse_joint(
        bodies[2].1,
        bodies[3].1,
        RevoluteJointBuilder::new(Vector::Z)
            .local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0)),
    );
    Scene {
        name: "jointed_boxes",
        world,
        bodies,
        script: None,
    }
}

#[test]
fn rapier_alone_continues_bit_for_bit_after_a_round_trip() {
    // The layer's guarantee rests on Rapier's: check it first, on its own, at several
    // moments of each scene (falling, colliding, settling, asleep).
    type Builder = (fn() -> Scene, &'static [u64]);
    let builders: [Builder; 6] = [
        (|| scenes::sphere_pile(40, 7), &[1, 60, 250]),
        (scenes::toppling_stack, &[1, 40, 120]),
        (scenes::trigger_ledge, &[1, 50, 150]),
        (scenes::pendulum_wall, &[1, 45, 90]),
        (scenes::kinematic_platform, &[1, 30, 100]),
        (jointed_boxes, &[1, 30, 200]),
    ];
    for (build, points) in builders {
        for &k in points {
            let mut scene = build();
            scene.run_plain(0, k);
            let mut copy: PhysicsWorld =
                bincode::deserialize(&bincode::serialize(&scene.world).unwrap()).unwrap();
            for step in k..k + 300 {
                scene.before_step(step);
                if let Some(s) = scene.script {
                    s(&mut copy, step);
                }
                scene.world.step();
                copy.step();
                assert!(
                    pose_bits(&scene.world) == pose_bits(&copy),
                    "{}: Rapier's restored world diverges at step {step} (saved after {k})",
                    scene.name
                );
            }
        }
    }
}

// ── The layer ───────────────────────────────────────────────────────────────

#[test]
fn a_restored_sphere_pile_continues_bit_for_bit() {
    for k in [1, 45, 200] {
        let mut t = Twins::split(
            scenes::sphere_pile(40, 7),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        t.run(300);
        assert!(t.events > 0 || k == 200, "the pile produced no event");
    }
}

#[test]
fn a_restored_trigger_ledge_continues_bit_for_bit_with_its_trigger_events() {
    // Saved before the ball reaches the trigger, while it is inside, and after.
    let mut inside_seen = false;
    for k in [5, 40, 70, 120] {
        let mut t = Twins::split(
            scenes::trigger_ledge(),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        let start = t
            .orig
            .layer
            .graph()
            .count_of_kind(rapier_contact_graph::NodeKind::Sensor);
        assert_eq!(start, 1);
        inside_seen |= t
            .orig
            .layer
            .graph()
            .edges()
            .any(|(_, e)| e.kind() == rapier_contact_graph::EdgeKind::Geometric);
        t.run(250);
    }
    assert!(
        inside_seen,
        "no snapshot was taken with the ball inside the trigger"
    );
}

#[test]
fn a_restored_toppling_stack_continues_bit_for_bit() {
    for k in [20, 90] {
        let mut t = Twins::split(
            scenes::toppling_stack(),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        t.run(300);
    }
}

#[test]
fn a_restored_kinematic_platform_continues_bit_for_bit() {
    let mut t = Twins::split(
        scenes::kinematic_platform(),
        ContactLayer::new(),
        40,
        &mut no_predicates(),
    );
    t.run(250);
}

#[test]
fn a_restored_layer_with_rules_timers_passive_bodies_and_containers_continues_bit_for_bit() {
    for k in [3, 60] {
        let (scene, layer, predicate, sleeper) = logic_scene();
        let ground = layer
            .graph()
            .try_node_of_body(scene.body("ground").unwrap())
            .unwrap();
        let mut asked = Vec::new();
        let mut bind = |n: NodeId, members: &[NodeId]| -> Option<IgnorePredicate> {
            asked.push((n, members.to_vec()));
            (n == predicate).then(|| Arc::new(picky_predicate(ground)) as IgnorePredicate)
        };
        let mut t = Twins::split(scene, layer, k, &mut bind);
        assert_eq!(asked.len(), 1, "one predicate rule to give back");
        assert_eq!(asked[0].0, predicate);
        t.run(80);
        // A logical change after the restore, on both sides: the passive body comes
        // back, a timer goes, a rule goes.
        t.both(|world, layer| {
            layer
                .logic_mut()
                .set_body_disabled(&world.bodies, sleeper, false)
                .unwrap();
        });
        t.run(40);
        t.both(|_, layer| {
            let timer = layer
                .graph()
                .nodes_of_kind(rapier_contact_graph::NodeKind::Timer)
                .map(|(id, _)| id)
                .next()
                .unwrap();
            layer.logic_mut().remove_timer(timer).unwrap();
            layer.logic_mut().remove_rule(predicate).unwrap();
        });
        t.run(120);
        assert!(t.events > 0);
    }
}

#[test]
fn a_restored_layer_with_every_speed_up_and_repair_continues_bit_for_bit() {
    let mut scene = scenes::sphere_pile(40, 11);
    let layer_with_everything = || {
        let mut layer = ContactLayer::new();
        layer
            .speedups_mut()
            .set(Some(rcg_lab::table5::combination(127)))
            .unwrap();
        let (c, r) = (MonitorConfig::default(), RepairConfig::default());
        layer.monitor_mut().set(MonitorMode::Repair, c, r).unwrap();
        layer
    };
    let mut layer = layer_with_everything();
    // Run until a few bodies are fixated while the others are still counting their
    // steps at rest, then save.
    let mut k = 0;
    while layer.speedups().is_none_or(|s| s.stats().fixated < 4) {
        assert!(k < 1_000, "too little was ever fixated");
        common::run_validated(&mut scene, &mut layer, k, 1);
        k += 1;
    }
    let fixated = layer.speedups().unwrap().stats().fixated;
    assert!(fixated < 40, "everything fixated already");
    // `split` runs from step 0: give it a fresh pile and the same number of steps.
    let fresh = layer_with_everything();
    let mut t = Twins::split(scenes::sphere_pile(40, 11), fresh, k, &mut no_predicates());
    assert_eq!(t.copy.layer.speedups().unwrap().stats().fixated, fixated);
    t.run(100);
    // A hammer dropped into the box releases fixated bodies, on both sides alike.
    let above = scenes::pile::wall_height(40) + 1.0;
    t.both(|world, _| {
        world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.3, above, 0.2))
                .linvel(Vector::new(0.0, -10.0, 0.0)),
            ColliderBuilder::ball(0.4).density(20.0),
        );
    });
    let before = t.orig.layer.speedups().unwrap().stats().fixated;
    let mut released = 0;
    for _ in 0..300 {
        t.run(1);
        released += t.orig.layer.speedups().unwrap().stats().releases;
    }
    assert!(
        released > 0 || t.orig.layer.speedups().unwrap().stats().fixated < before,
        "the hammer released nothing"
    );
    // Switching the speed-ups and the monitor off restores the world on both sides
    // alike.
    t.both(|_, layer| {
        layer.speedups_mut().set(None).unwrap();
        let (c, r) = (MonitorConfig::default(), RepairConfig::default());
        layer.monitor_mut().set(MonitorMode::Off, c, r).unwrap();
    });
    t.run(100);
}

#[test]
fn a_snapshot_taken_between_world_edits_and_the_next_step_continues_bit_for_bit() {
    // Bodies removed and inserted, a rule, a timer and a passive body queued: the
    // layer has not seen any of it yet when the pair is saved.
    let mut edit = |world: &mut PhysicsWorld, layer: &mut ContactLayer| {
        let spheres: Vec<RigidBodyHandle> = world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        let [gone, passive, a, b] = spheres[..4] else {
            unreachable!()
        };
        world.remove_body(gone);
        ball_at(world, [0.2, 8.0, -0.3], 0.3);
        layer.logic_mut().ignore_pair(&*world, a, b).unwrap();
        layer.logic_mut().add_timer(0.1).unwrap();
        layer
            .logic_mut()
            .set_body_disabled(&world.bodies, passive, true)
            .unwrap();
    };
    let mut t = Twins::split_after(
        scenes::sphere_pile(30, 5),
        ContactLayer::new(),
        80,
        &mut edit,
        &mut no_predicates(),
    );
    t.run(250);
}

/// A layer with `SpeedUps::reliable_sleep()`.
fn held_layer() -> ContactLayer {
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(
            rapier_contact_graph::speedups::SpeedUps::reliable_sleep(),
        ))
        .unwrap();
    layer
}

/// Throws the heavy ball into the box pile at step 400.
fn throw_at_400(world: &mut PhysicsWorld, step: u64) {
    if step == 400 {
        common::build::throw_heavy_ball(world);
    }
}

#[test]
fn a_snapshot_taken_with_released_bodies_given_back_continues_bit_for_bit() {
    // `ContactLayer::step` gives the bodies its analysis released back to Rapier at
    // its end: saved then, the world holds them dynamic and the layer's graph held,
    // until the next analysis reads them.
    let thrown_pile = || Scene {
        script: Some(throw_at_400),
        ..scenes::box_pile(50, 7)
    };
    // The first step after the throw whose analysis gives bodies back.
    let (mut scene, mut layer) = (thrown_pile(), held_layer());
    let mut k = 0;
    loop {
        common::run_validated(&mut scene, &mut layer, k, 1);
        k += 1;
        if k > 400 && !layer.analysis().given_back().is_empty() {
            break;
        }
        assert!(k < 600, "the ball released nothing");
    }
    let mut t = Twins::split(thrown_pile(), held_layer(), k, &mut no_predicates());
    assert!(
        !t.copy.layer.analysis().given_back().is_empty(),
        "saved with bodies given back"
    );
    t.run(100);
}

#[test]
fn a_restored_held_floor_hit_by_a_slab_continues_bit_for_bit() {
    // The slab reaches about 16 held boxes at once and its release spreads from all
    // of them within its momentum's budget: which boxes the budget reaches must not
    // depend on the layer's tree of held boxes, which a restore builds anew.
    let floor = || {
        let (world, _) = common::build::floor_of_boxes(12, 0.2);
        common::plain_scene("floor_of_boxes", world)
    };
    let mut t = Twins::split(floor(), held_layer(), 60, &mut no_predicates());
    assert_eq!(
        t.copy.layer.speedups().unwrap().stats().fixated,
        144,
        "the floor is held when saved"
    );
    t.both(|world, _| {
        common::build::slab_over_floor(world, 0.2, 1.0, 2.0);
    });
    t.run(40);
}
