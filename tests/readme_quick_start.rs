//! The README's quick start, kept compiling and true.

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet, Touching};

#[test]
fn readme_quick_start_runs() -> Result<(), rapier_contact_graph::Error> {
    let mut world = PhysicsWorld::new();
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 2.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    let mut layer = ContactLayer::new();
    let touches = layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_bodies(&[ball]));
    for _ in 0..100 {
        layer.step(&mut world);
        // The quick start is the cheap path: Rapier's own events drive the layer.
        assert!(layer.analysis().touching_in_effect());
    }
    let ground = world.bodies.iter().next().map(|(h, _)| h).unwrap();
    assert_eq!(
        layer.touching_body(&world.bodies, ball)?,
        vec![Touching::Body(ground)]
    );
    assert_eq!(
        layer.supports_of_body(&world, ball, 0.5)?,
        vec![Touching::Body(ground)]
    );
    assert!(layer.is_grounded(&world, ball)?);
    let touching = layer.touching_body(&world.bodies, ball)?;
    let contact = layer
        .contact_details(&world, ball, touching[0])?
        .expect("the ball rests on the ground");
    // From the ball towards the ground: down.
    assert!(contact.normal.y < -0.99, "normal {:?}", contact.normal);
    assert!(contact.normal_impulse > 0.0);
    let events: Vec<_> = touches.try_iter().collect();
    // One landing: it begins and never ends (a bounce would add an end and a begin).
    assert_eq!(
        events.first().map(|e| e.kind),
        Some(EventKind::ContactStarted)
    );
    assert!(events.first().is_some_and(|e| e.normal.y.abs() > 0.99));
    assert_eq!(events.len() % 2, 1, "{events:?}");
    Ok(())
}
