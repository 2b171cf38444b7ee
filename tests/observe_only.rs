//! Attaching the layer changes nothing in Rapier's results (`docs/ARCHITECTURE.md` §6).

mod common;

use rapier3d::prelude::ActiveEvents;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::ContactLayer;
use rcg_scenes as scenes;

#[test]
fn settling_pile_is_bit_identical_with_and_without_the_layer() {
    let mut plain = scenes::sphere_pile(300, 7);
    let mut observed = scenes::sphere_pile(300, 7);
    let mut layer = ContactLayer::new();
    for step in 0..1000u64 {
        plain.before_step(step);
        plain.world.step();
        observed.before_step(step);
        layer.step(&mut observed.world);
        {
            assert_eq!(
                common::pose_bits(&plain.world),
                common::pose_bits(&observed.world),
                "trajectories differ at step {step}"
            );
            layer.validate(&observed.world).unwrap();
        }
    }
    assert!(layer.graph().edge_count() > 300, "the pile has contacts");
}

/// Observe-only sets no hook flag. Touching tracking (the default) adds
/// `COLLISION_EVENTS` (Rapier's events drive the graph; the trajectories stay
/// bit-identical, above) and nothing else, and `detach` takes it off again; under
/// proximity tracking no event flag is set at all.
#[test]
fn only_the_collision_event_flag_is_set_and_detach_takes_it_off() {
    let mut scene = scenes::two_piles_with_wall();
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 50);
    assert!(layer.analysis().touching_in_effect());
    for (_, c) in scene.world.colliders.iter() {
        assert!(c.active_hooks().is_empty());
        assert_eq!(c.active_events(), ActiveEvents::COLLISION_EVENTS);
    }
    layer.detach((&mut scene.world).into());
    for (_, c) in scene.world.colliders.iter() {
        assert!(c.active_hooks().is_empty());
        assert!(c.active_events().is_empty());
    }

    let mut scene = scenes::two_piles_with_wall();
    let mut layer = ContactLayer::with_tracking(Tracking::Proximity);
    common::run_validated(&mut scene, &mut layer, 0, 50);
    for (_, c) in scene.world.colliders.iter() {
        assert!(c.active_hooks().is_empty());
        assert!(c.active_events().is_empty());
    }
}
