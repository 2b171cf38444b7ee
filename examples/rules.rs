//! Rules: "ignore this pair". Box `top` rests on box `bottom`; at step 100 a rule
//! `layer.logic_mut().ignore_pair(&world, bottom, top)` makes Rapier ignore the pair, so `top` falls
//! through `bottom` onto the ground; at step 200 the rule is removed and the two,
//! now overlapping, interact again (Rapier pushes them apart).
//!
//! ```text
//! cargo run --example rules
//! ```

use rapier_contact_graph::rapier3d::math::Vector;
use rapier_contact_graph::rapier3d::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};
use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet};

fn main() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (bottom, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    // Shifted along x so that, once fallen through, the two overlap along x only.
    let (top, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.3, 1.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let names = [(ground, "ground"), (bottom, "bottom"), (top, "top")];
    let name = |h| {
        names
            .iter()
            .find(|(b, _)| Some(*b) == h)
            .map_or("?", |n| n.1)
    };

    let mut layer = ContactLayer::new();
    let touches = layer.subscribe(Filter::kinds(KindSet::of(&[
        EventKind::ContactStarted,
        EventKind::ContactStopped,
    ])));
    let top_y = |w: &PhysicsWorld| w.bodies[top].translation().y;
    let mut rule = None;
    for step in 0..300u64 {
        if step == 100 {
            let r = layer.logic_mut().ignore_pair(&world, bottom, top).unwrap();
            println!(
                "-- before step {}: add rule {r} = {:?}; top y = {:.2}",
                step + 1,
                layer.logic().rule(r).unwrap(),
                top_y(&world),
            );
            rule = Some(r);
        }
        if step == 200 {
            let r = layer.logic_mut().remove_rule(rule.take().unwrap()).unwrap();
            println!(
                "-- before step {}: remove rule {r:?}; top y = {:.2}",
                step + 1,
                top_y(&world)
            );
        }
        layer.step(&mut world);
        if step == 100 {
            let n = layer.analysis().flagged_colliders();
            println!("   (hook flags set in step 101's pre-step on {n} colliders)");
        }
        for ev in touches.try_iter() {
            println!(
                "step {:>3}  {:<10} {:<6} {:<6} (top at y = {:.2})",
                ev.step,
                format!("{:?}", ev.kind),
                name(ev.body1),
                name(ev.body2),
                top_y(&world)
            );
        }
        layer.validate(&world).expect("the graph matches the world");
    }
    let (b, t) = (
        world.bodies[bottom].translation(),
        world.bodies[top].translation(),
    );
    println!(
        "end: bottom at ({:.2}, {:.2}), top at ({:.2}, {:.2}); flagged colliders: {}",
        b.x,
        b.y,
        t.x,
        t.y,
        layer.analysis().flagged_colliders()
    );
}
