//! A held body the analysis releases is given back to Rapier at the end of
//! `ContactLayer::step`, not at the next pre-step (paper §7, fixation): the step that
//! first solves a released pile then pays Rapier's part of the release alone. A
//! hand-written loop gives the same bodies back at its next pre-step, with the same
//! trajectories bit for bit.

mod common;

use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};
use rcg_scenes as scenes;

const SETTLE: u64 = 400;
const AFTER: u64 = 120;

/// A settled, held pile of 50 boxes.
fn held_pile() -> (scenes::Scene, ContactLayer) {
    let mut scene = scenes::box_pile(50, 7);
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    common::run_validated(&mut scene, &mut layer, 0, SETTLE);
    assert!(
        layer.speedups().unwrap().fixated().count() > 40,
        "the pile is held"
    );
    (scene, layer)
}

#[test]
fn a_release_is_given_back_at_the_end_of_the_step_that_decides_it() {
    let (mut scene, mut layer) = held_pile();
    common::build::throw_heavy_ball(&mut scene.world);
    let mut released = 0;
    for step in SETTLE..SETTLE + AFTER {
        common::step_validated(&mut scene, &mut layer, step);
        let given_back = layer.analysis().given_back();
        let s = layer.speedups().unwrap();
        for &h in &given_back {
            let rb = &scene.world.bodies[h];
            assert!(!s.is_fixated(h), "{h:?} given back but still held");
            assert!(rb.is_dynamic(), "{h:?} given back but not dynamic");
            // The graph shows it as the step saw it until the next analysis.
            let node = layer.graph().node_of_body(h).unwrap();
            assert!(layer.graph().node(node).unwrap().is_held());
        }
        assert!(
            s.pending_releases().is_empty(),
            "nothing left for the pre-step"
        );
        released += given_back.len();
    }
    assert!(released > 10, "the ball released the pile ({released})");
}

#[test]
fn a_hand_written_loop_gives_back_the_same_bodies_at_its_pre_step() {
    let (mut a, mut layer_a) = held_pile();
    let (mut b, mut layer_b) = held_pile();
    assert_eq!(common::pose_bits(&a.world), common::pose_bits(&b.world));
    common::build::throw_heavy_ball(&mut a.world);
    common::build::throw_heavy_ball(&mut b.world);
    let mut released = 0;
    for _ in 0..AFTER {
        layer_a.step(&mut a.world);
        layer_b.pre_step(WorldMut::from(&mut b.world));
        b.world
            .step_with_events(&layer_b.hooks(), layer_b.event_handler());
        layer_b.analyze(WorldView::from(&b.world));
        layer_a.validate(&a.world).unwrap();
        layer_b.validate(&b.world).unwrap();
        // The same releases, given back one at the end of the step, the other at
        // the next pre-step.
        let given_back = layer_a.analysis().given_back();
        assert!(layer_b.analysis().given_back().is_empty());
        let pending: Vec<_> = layer_b.speedups().unwrap().pending_releases().to_vec();
        let mut sorted = pending.clone();
        sorted.sort_by_key(|h| h.into_raw_parts());
        assert_eq!(given_back, sorted);
        released += given_back.len();
        assert_eq!(common::pose_bits(&a.world), common::pose_bits(&b.world));
    }
    assert!(released > 10, "the ball released the pile ({released})");
}
