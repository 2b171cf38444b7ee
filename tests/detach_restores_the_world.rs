//! The layer restores exactly what it changed and nothing else: every
//! setting of every collider and body, the joints and the solver parameters are
//! recorded before the layer is attached; rules, triggers, passive bodies, every
//! speed-up, the monitor and touching tracking run, switched on and off; the user
//! changes some of their own settings meanwhile; after `ContactLayer::detach` the
//! world's settings are the user's as the user last set them.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::monitor::MonitorMode;
use rapier_contact_graph::{ContactLayer, WorldMut};

use common::build::*;

fn groups(g: InteractionGroups) -> String {
    format!(
        "{:x}/{:x}/{:?}",
        g.memberships.bits(),
        g.filter.bits(),
        g.test_mode
    )
}

/// Every setting of the world that is not simulation state (poses, velocities and
/// sleep are the simulation's; a layer may change them like any step does).
fn settings(world: &PhysicsWorld) -> Vec<String> {
    let mut out = Vec::new();
    for (h, c) in world.colliders.iter() {
        out.push(format!(
            "collider {:?}: parent {:?} sensor {} enabled {} hooks {:?} events {:?} types {:?} \
             groups {:?} solver {:?} friction {} restitution {} skin {} force threshold {} \
             shape {:?}",
            h.into_raw_parts(),
            c.parent(),
            c.is_sensor(),
            c.is_enabled(),
            c.active_hooks(),
            c.active_events(),
            c.active_collision_types(),
            groups(c.collision_groups()),
            groups(c.solver_groups()),
            c.friction(),
            c.restitution(),
            c.contact_skin(),
            c.contact_force_event_threshold(),
            c.shape().shape_type(),
        ));
    }
    for (h, b) in world.bodies.iter() {
        let a = b.activation();
        out.push(format!(
            "body {:?}: type {:?} enabled {} damping {} {} thresholds {} {} {} ccd {} \
             soft ccd {} gravity {} dominance {} extra iterations {} colliders {:?}",
            h.into_raw_parts(),
            b.body_type(),
            b.is_enabled(),
            b.linear_damping(),
            b.angular_damping(),
            a.normalized_linear_threshold,
            a.angular_threshold,
            a.time_until_sleep,
            b.is_ccd_enabled(),
            b.soft_ccd_prediction(),
            b.gravity_scale(),
            b.dominance_group(),
            b.additional_solver_iterations(),
            b.colliders(),
        ));
    }
    for (h, j) in world.impulse_joints.iter() {
        out.push(format!(
            "joint {:?}: {:?}",
            h.into_raw_parts(),
            j.data.enabled
        ));
    }
    let p = &world.integration_parameters;
    out.push(format!(
        "solver: iterations {} recycling {} warm start {} dt {}",
        p.num_solver_iterations, p.contact_recycling, p.warmstart_coefficient, p.dt
    ));
    out
}

/// A pile with the user's own non-default settings: hook and event flags, collision
/// types of a sensor, sleep thresholds, damping, solver parameters, a joint.
fn world() -> (
    PhysicsWorld,
    Vec<RigidBodyHandle>,
    ColliderHandle,
    ColliderHandle,
) {
    let (mut world, _) = world_with_ground();
    world.integration_parameters.num_solver_iterations = 6;
    world.integration_parameters.warmstart_coefficient = 0.9;
    let mut bodies = Vec::new();
    for i in 0..12 {
        let (x, y) = ((i % 4) as f32 * 0.9 - 1.4, 0.6 + (i / 4) as f32 * 1.0);
        let (h, c) = box_at(&mut world, [x, y, 0.0], 0.4);
        bodies.push(h);
        let col = &mut world.colliders[c];
        match i % 4 {
            0 => col.set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS),
            1 => col.set_active_events(ActiveEvents::COLLISION_EVENTS),
            2 => col.set_active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS),
            _ => {}
        }
        let rb = &mut world.bodies[h];
        rb.set_linear_damping(0.05 * i as f32);
        rb.activation_mut().normalized_linear_threshold = 0.3;
        rb.activation_mut().time_until_sleep = 1.5;
    }
    let joint = RevoluteJointBuilder::new(Vector::Z).local_anchor1(Vector::new(0.45, 0.0, 0.0));
    world
        .impulse_joints
        .insert(bodies[0], bodies[1], joint, true);
    // A sensor on a fixed post, with the user's own (default) collision types.
    let (_, sensor) = world.insert(
        fixed_at([0.0, 1.0, 1.2]),
        ColliderBuilder::cuboid(2.0, 1.0, 0.5).sensor(true),
    );
    // A ball whose collider the user turns into a sensor and back meanwhile.
    let (_, toggled) = ball_at(&mut world, [2.5, 1.0, 0.0], 0.3);
    (world, bodies, sensor, toggled)
}

#[test]
fn detach_gives_back_every_setting_as_the_user_last_set_it() {
    let (mut world, bodies, sensor, toggled) = world();
    let mut layer = ContactLayer::new();
    let mut expected = settings(&world);
    layer.step(&mut world);
    // Rules over bodies with and without the user's own hook flags.
    layer
        .logic_mut()
        .ignore_pair(&world, bodies[0], bodies[2])
        .unwrap();
    let between = layer
        .logic_mut()
        .ignore_pair(&world, bodies[4], bodies[5])
        .unwrap();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, bodies[1], true)
        .unwrap();
    layer
        .logic_mut()
        .set_body_disabled(&world.bodies, bodies[7], true)
        .unwrap();
    for i in 0..60 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        if i == 20 {
            layer
                .speedups_mut()
                .set(Some(rcg_lab::table5::combination(127)))
                .unwrap();
        }
        if i == 30 {
            common::monitor_in(&mut layer, MonitorMode::Repair);
        }
    }
    // The user changes their own settings while the layer's flags are on: these are
    // the settings `detach` must leave.
    let c5 = world.bodies[bodies[5]].colliders()[0];
    let hooks = world.colliders[c5].active_hooks() | ActiveHooks::FILTER_INTERSECTION_PAIR;
    world.colliders[c5].set_active_hooks(hooks);
    world.colliders[sensor].set_active_collision_types(ActiveCollisionTypes::DYNAMIC_FIXED);
    world.colliders[toggled].set_sensor(true);
    // As documented: a change in place to a body the layer may hold or that sleeps.
    layer.analysis_mut().request_full_sync();
    world.integration_parameters.dt = 1.0 / 50.0;
    for i in 0..120 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
        match i {
            10 => {
                world.colliders[toggled].set_sensor(false);
                layer.analysis_mut().request_full_sync();
            }
            20 => layer.speedups_mut().set(None).unwrap(),
            40 => layer
                .speedups_mut()
                .set(Some(rcg_lab::table5::combination(0b101_0101)))
                .unwrap(),
            60 => {
                layer.logic_mut().remove_rule(between).unwrap();
            }
            80 => {
                layer.speedups_mut().set(None).unwrap();
                common::monitor_in(&mut layer, MonitorMode::Off);
                layer.set_tracking(Tracking::Touching);
            }
            _ => {}
        }
    }
    layer.detach(WorldMut::from(&mut world));
    // Rapier gives a re-enabled body's colliders their enabled flag back in its next
    // step (they show `DisabledByParent` until then): one plain Rapier step.
    world.step();
    // What the user changed meanwhile, in the recorded settings.
    for line in expected.iter_mut() {
        let c5_key = format!("collider {:?}:", c5.into_raw_parts());
        let sensor_key = format!("collider {:?}:", sensor.into_raw_parts());
        if line.starts_with(&c5_key) {
            *line = line.replace(
                &format!("hooks {:?}", ActiveHooks::FILTER_CONTACT_PAIRS),
                &format!("hooks {hooks:?}"),
            );
        }
        if line.starts_with(&sensor_key) {
            *line = line.replace(
                &format!("types {:?}", ActiveCollisionTypes::default()),
                &format!("types {:?}", ActiveCollisionTypes::DYNAMIC_FIXED),
            );
        }
        if line.starts_with("solver:") {
            *line = line.replace(
                &format!("dt {}", 1.0f32 / 60.0),
                &format!("dt {}", 1.0f32 / 50.0),
            );
        }
    }
    let got = settings(&world);
    let diff: Vec<String> = expected
        .iter()
        .zip(&got)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("before: {a}\nafter:  {b}"))
        .collect();
    assert_eq!(expected.len(), got.len());
    assert!(
        diff.is_empty(),
        "settings changed by the layer:\n{}",
        diff.join("\n")
    );
}
