//! The README's quick start, kept compiling and true.

use rapier3d::prelude::*;
use rapier_contact_graph::{
    events::{EventKind, Filter, KindSet},
    ContactLayer,
};

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
    let touches = layer.subscribe(Filter::kinds(KindSet::TOUCH));
    for _ in 0..100 {
        layer.step(&mut world);
    }
    let ground = world.bodies.iter().next().map(|(h, _)| h).unwrap();
    assert_eq!(
        layer.touching_body(&world.bodies, ball)?,
        vec![rapier_contact_graph::Touching::Body(ground)]
    );
    assert_eq!(
        layer.supports_of_body(&world, ball, 0.5)?,
        vec![rapier_contact_graph::Touching::Body(ground)]
    );
    let events: Vec<_> = touches.try_iter().collect();
    assert_eq!(events.first().map(|e| e.kind), Some(EventKind::TouchBegin));
    Ok(())
}
