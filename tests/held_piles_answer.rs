//! A held pile answers a disturbance and its owner as a sleeping pile does (paper §7,
//! fixation): a ball thrown into it moves it, a kinematic paddle pushes it, and a
//! body the user takes back is the user's.

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;
use rcg_scenes as scenes;

const SETTLE: u64 = 400;
const AFTER: u64 = 180;

/// The held preset, with or without the release spreading through the pile.
fn preset(group: bool) -> SpeedUps {
    SpeedUps {
        release_group: group,
        ..SpeedUps::reliable_sleep()
    }
}

/// A settled pile of 50 boxes (10 columns of 5).
fn pile() -> scenes::Scene {
    scenes::box_pile(50, 7)
}

fn positions(world: &PhysicsWorld, bodies: &[RigidBodyHandle]) -> Vec<Vector> {
    bodies
        .iter()
        .map(|&h| world.bodies[h].translation())
        .collect()
}

fn displaced(before: &[Vector], after: &[Vector]) -> usize {
    before
        .iter()
        .zip(after)
        .filter(|(a, b)| (**a - **b).length() > 0.01)
        .count()
}

/// Boxes the ball displaces by more than 1 cm: stock Rapier (its own sleep) or the
/// layer with `config`.
fn thrown_at(config: Option<SpeedUps>) -> (usize, usize) {
    let mut scene = pile();
    let boxes = scene.dynamic_bodies();
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(config.clone()).unwrap();
    let mut step = 0;
    let stepper = |scene: &mut scenes::Scene, layer: &mut ContactLayer, step: u64| {
        if config.is_some() {
            common::step_validated(scene, layer, step);
        } else {
            scene.world.step();
        }
    };
    while step < SETTLE {
        stepper(&mut scene, &mut layer, step);
        step += 1;
    }
    let held = layer.speedups().map_or(0, |s| s.stats().fixated);
    let before = positions(&scene.world, &boxes);
    common::build::throw_heavy_ball(&mut scene.world);
    for _ in 0..AFTER {
        stepper(&mut scene, &mut layer, step);
        step += 1;
    }
    (displaced(&before, &positions(&scene.world, &boxes)), held)
}

#[test]
fn a_thrown_ball_moves_a_held_pile_as_it_moves_a_sleeping_one() {
    let (stock, _) = thrown_at(None);
    let (layer, held) = thrown_at(Some(preset(true)));
    eprintln!("stock {stock}, layer {layer}, held {held}");
    assert!(
        held >= 45,
        "the pile was held before the throw ({held} boxes)"
    );
    assert!(
        stock >= 5,
        "the ball moves stock Rapier's sleeping pile ({stock})"
    );
    assert!(
        2 * layer >= stock,
        "the held pile answers: {layer} boxes displaced, stock Rapier {stock}"
    );
}

#[test]
fn the_release_reaches_the_bodies_the_hit_ones_touch() {
    let (alone, _) = thrown_at(Some(preset(false)));
    let (group, _) = thrown_at(Some(preset(true)));
    eprintln!("alone {alone}, group {group}");
    assert!(
        group > alone,
        "the whole held group answers ({group}) more than the bodies hit alone ({alone})"
    );
}

#[test]
fn a_kinematic_paddle_pushes_a_held_pile() {
    let mut scene = pile();
    let boxes = scene.dynamic_bodies();
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(preset(true))).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    assert!(layer.speedups().unwrap().stats().fixated >= 45);
    let before = positions(&scene.world, &boxes);
    let paddle = scene
        .world
        .insert(
            RigidBodyBuilder::kinematic_velocity_based()
                .translation(Vector::new(-3.0, 0.6, 0.0))
                .linvel(Vector::new(2.0, 0.0, 0.0)),
            ColliderBuilder::cuboid(0.1, 0.5, 1.5),
        )
        .0;
    common::run_validated(&mut scene, &mut layer, SETTLE, AFTER);
    let moved = displaced(&before, &positions(&scene.world, &boxes));
    eprintln!("paddle moved {moved}");
    // Nothing passes through the paddle: every box is ahead of it or pushed aside.
    let x = scene.world.bodies[paddle].translation().x;
    assert!(x > 0.0, "the paddle crossed the pile ({x})");
    assert!(
        moved >= 10,
        "the paddle pushed the pile ({moved} boxes moved)"
    );
    for (&h, b) in boxes.iter().zip(&before) {
        let p = scene.world.bodies[h].translation();
        let inside = (p.x - x).abs() < 0.1 && p.y < 1.1 && p.z.abs() < 1.5;
        assert!(
            !inside,
            "box {h:?} from {b:?} is inside the paddle at {p:?}"
        );
    }
}

#[test]
fn a_held_box_the_user_makes_dynamic_and_throws_up_is_the_users() {
    let mut scene = pile();
    // The top box of the first column.
    let top = scene.dynamic_bodies()[4];
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(preset(true))).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    assert!(layer.speedups().unwrap().is_fixated(top));
    let y0 = scene.world.bodies[top].translation().y;
    let rb = &mut scene.world.bodies[top];
    rb.set_body_type(RigidBodyType::Dynamic, true);
    rb.set_linvel(Vector::new(0.0, 5.0, 0.0), true);
    let mut peak = y0;
    for step in SETTLE..SETTLE + 120 {
        common::step_validated(&mut scene, &mut layer, step);
        peak = peak.max(scene.world.bodies[top].translation().y);
    }
    // Thrown up at 5 m/s it rises about 1.27 m, then falls back onto the pile.
    assert!(peak - y0 > 1.0, "the box rose {} m", peak - y0);
    let y = scene.world.bodies[top].translation().y;
    assert!(
        y < y0 + 0.3,
        "the box came down ({y} against {y0}): not held in mid-air"
    );
}

#[test]
fn a_held_box_falls_when_the_box_under_it_is_removed() {
    let mut scene = pile();
    // The first column, bottom to top.
    let column: Vec<RigidBodyHandle> = scene.dynamic_bodies()[..5].to_vec();
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(preset(true))).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    let s = layer.speedups().unwrap();
    assert!(
        column.iter().all(|&h| s.is_fixated(h)),
        "the column is held"
    );
    let y0 = scene.world.bodies[column[1]].translation().y;
    scene.world.remove_body_with_colliders(column[0], true);
    common::run_validated(&mut scene, &mut layer, SETTLE, 120);
    // Without the monitor: the box that rested on the removed one falls as in plain
    // Rapier (about one box height, 0.5 m), and so does the rest of the column.
    let y = scene.world.bodies[column[1]].translation().y;
    assert!(y0 - y > 0.3, "the box fell {} m", y0 - y);
}

#[test]
fn a_held_pile_falls_when_its_ground_is_moved_down() {
    let mut scene = scenes::box_pile(20, 3);
    let boxes = scene.dynamic_bodies();
    let ground = scene.body("ground").unwrap();
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(preset(true))).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    assert_eq!(
        layer.speedups().unwrap().stats().fixated,
        20,
        "the pile is held"
    );
    let before = positions(&scene.world, &boxes);
    let g = &mut scene.world.bodies[ground];
    let at = g.translation();
    g.set_translation(at - Vector::new(0.0, 1.0, 0.0), true);
    common::run_validated(&mut scene, &mut layer, SETTLE, 120);
    // Without the monitor, as in plain Rapier: every box falls with the ground.
    for (&h, b) in boxes.iter().zip(&before) {
        let y = scene.world.bodies[h].translation().y;
        assert!(b.y - y > 0.9, "box {h:?} fell {} m", b.y - y);
    }
}

#[test]
fn a_held_box_the_user_disables_stays_disabled() {
    let mut scene = pile();
    let boxes = scene.dynamic_bodies();
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(preset(true))).unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    // One box of every column's top, each in whatever state of parking it is.
    let tops: Vec<RigidBodyHandle> = boxes.iter().skip(4).step_by(5).copied().collect();
    for &h in &tops {
        assert!(layer.speedups().unwrap().is_fixated(h));
        scene.world.bodies[h].set_enabled(false);
    }
    common::run_validated(&mut scene, &mut layer, SETTLE, 200);
    for &h in &tops {
        assert!(
            !scene.world.bodies[h].is_enabled(),
            "box {h:?} was enabled again"
        );
    }
}

/// The documented way to push a held body: make it dynamic first (Rapier drops an
/// impulse on a fixed body), then push it; it moves as a sleeping box pushed the same
/// way moves in stock Rapier.
#[test]
fn a_held_box_made_dynamic_then_pushed_moves_as_a_sleeping_one() {
    let push = |world: &mut PhysicsWorld, h: RigidBodyHandle| {
        let rb = &mut world.bodies[h];
        rb.set_body_type(RigidBodyType::Dynamic, true);
        let m = rb.mass();
        rb.apply_impulse(Vector::new(0.0, 4.0 * m, 0.0), true);
    };
    let rise = |layered: bool| {
        let mut scene = pile();
        let top = scene.dynamic_bodies()[4];
        let mut layer = ContactLayer::new();
        layer.speedups_mut().set(Some(preset(true))).unwrap();
        for step in 0..SETTLE {
            if layered {
                common::step_validated(&mut scene, &mut layer, step);
            } else {
                scene.world.step();
            }
        }
        if layered {
            assert!(
                layer.speedups().unwrap().is_fixated(top),
                "held before the push"
            );
        } else {
            assert!(
                scene.world.bodies[top].is_sleeping(),
                "asleep before the push"
            );
        }
        let y0 = scene.world.bodies[top].translation().y;
        push(&mut scene.world, top);
        let mut peak = y0;
        for step in SETTLE..SETTLE + 60 {
            if layered {
                common::step_validated(&mut scene, &mut layer, step);
            } else {
                scene.world.step();
            }
            peak = peak.max(scene.world.bodies[top].translation().y);
        }
        peak - y0
    };
    let (stock, held) = (rise(false), rise(true));
    // 4 m/s up: about 0.8 m.
    assert!(stock > 0.6, "the sleeping box rose {stock} m");
    assert!(
        (held - stock).abs() < 0.05 * stock,
        "the held box rose {held} m, the sleeping one {stock} m"
    );
}

/// A settled pile of 120 boxes on a floor of strips whose middle strip is removed
/// at step `SETTLE`, run `after` steps more.
fn floor_strip_scene(after: u64) -> rcg_scenes::disturb::Disturbance {
    rcg_scenes::disturb::support_removed(&rcg_scenes::disturb::DisturbParams {
        boxes: 120,
        seed: 0,
        at: SETTLE,
        after,
    })
}

/// The boxes asleep in stock Rapier when the strip goes, and how many of them wake
/// within `after` steps.
fn floor_strip_woken(after: u64) -> (usize, usize) {
    let mut d = floor_strip_scene(after);
    d.run_plain(0, d.at);
    let bodies = &d.scene.world.bodies;
    let mut asleep: Vec<RigidBodyHandle> = d
        .pile
        .iter()
        .copied()
        .filter(|&h| bodies[h].is_sleeping())
        .collect();
    let count = asleep.len();
    for step in d.at..d.steps {
        d.run_plain(step, 1);
        asleep.retain(|&h| d.scene.world.bodies[h].is_sleeping());
    }
    (count, count - asleep.len())
}

/// The boxes held when the strip goes under `config`, and how many of them are
/// released within `after` steps.
fn floor_strip_released(config: SpeedUps, after: u64) -> (usize, usize) {
    let mut d = floor_strip_scene(after);
    let mut layer = ContactLayer::new();
    layer.speedups_mut().set(Some(config)).unwrap();
    let mut held = Vec::new();
    let mut count = 0;
    for step in 0..d.steps {
        if step == d.at {
            let s = layer.speedups().unwrap();
            held = d
                .pile
                .iter()
                .copied()
                .filter(|&h| s.is_fixated(h))
                .collect();
            count = held.len();
        }
        d.before_step(step);
        common::step_validated(&mut d.scene, &mut layer, step);
        let s = layer.speedups().unwrap();
        held.retain(|&h| s.is_fixated(h));
    }
    (count, count - held.len())
}

#[test]
fn a_held_pile_beside_a_removed_floor_strip_wakes_as_a_sleeping_one() {
    // Rapier wakes the island that touched a removed collider whole: the boxes beside
    // the trench slide after those that fall. The held pile's group is released with
    // the boxes that lost their support, within the release budget's steps.
    let (asleep, woken) = floor_strip_woken(20);
    let (held, released) = floor_strip_released(preset(true), 20);
    let (_, alone) = floor_strip_released(preset(false), 20);
    eprintln!("stock: {woken} of {asleep} woken; layer: {released} of {held} released, {alone} without the group release");
    assert!(
        asleep >= 100 && held >= 100,
        "the pile was asleep ({asleep}) and held ({held})"
    );
    assert!(
        released >= woken,
        "the held pile answers as the sleeping one: {released} released, {woken} woken"
    );
    // Without the group release only what rested on the strip, transitively.
    assert!(
        alone < woken,
        "without the group release part of the pile stays held ({alone} released)"
    );
}
