//! A release that spreads through a held pile is given back over a few steps, nearest
//! first (paper §7, fixation): no step gives back much more than the release budget
//! (a quarter of the world's dynamic bodies), and the whole wave is released.

mod common;

use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;
use rcg_scenes::disturb::{bin_hit, DisturbParams};

/// Steps watched after the ball is thrown.
const AFTER: u64 = 80;

#[test]
fn a_wave_larger_than_the_budget_is_released_over_several_steps() {
    // The lab's bin hit at 200 bodies: the ball's momentum reaches the whole pile.
    let mut d = bin_hit(&DisturbParams {
        boxes: 200,
        seed: 3,
        at: 1000,
        after: AFTER,
    });
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps::reliable_sleep()))
        .unwrap();
    let mut per_step = Vec::new();
    let mut held = 0;
    for step in 0..d.steps {
        if step == d.at {
            held = layer.speedups().map_or(0, |s| s.stats().fixated);
        }
        d.before_step(step);
        common::step_validated(&mut d.scene, &mut layer, step);
        if step >= d.at {
            per_step.push(layer.speedups().map_or(0, |s| s.stats().releases));
        }
    }
    assert!(held >= 180, "the pile was held ({held} of 200)");
    let released: usize = per_step.iter().sum();
    let most = per_step.iter().copied().max().unwrap_or(0);
    let steps = per_step.iter().filter(|&&r| r > 0).count();
    eprintln!("released {released} in {steps} steps, at most {most} in one: {per_step:?}");
    assert!(
        released >= held * 3 / 4,
        "the wave reached the pile ({released} of {held} released)"
    );
    // A quarter of the 201 dynamic bodies (the pile and the ball) a step, beyond the
    // few bodies the ball's reach meets directly.
    let budget = 201 / 4;
    assert!(
        most <= budget + 16,
        "one step released {most}, more than the budget {budget} and the bodies reached"
    );
    assert!(steps >= 3, "the wave took {steps} steps");
}
