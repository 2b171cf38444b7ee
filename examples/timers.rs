//! Timers: a `Timer` node ticking every 0.5 simulated seconds, over 3 simulated
//! seconds (300 steps of 0.01 s) of the ball-on-box scene. Tick *k* is due at
//! k·0.5 s, so it arrives at step 50·k, without drift.
//!
//! ```text
//! cargo run --example timers
//! ```

use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet};
use rcg_scenes as scenes;

fn main() {
    let mut scene = scenes::ball_on_box();
    let mut layer = ContactLayer::new();
    let timer = layer.logic_mut().add_timer(0.5).expect("a positive period");
    let ticks = layer.subscribe(Filter::kinds(KindSet::of(&[EventKind::TimerTick])));
    println!(
        "timer node {timer}: kind {:?}, period {} s",
        layer.graph().node(timer).unwrap().kind(),
        layer.logic().timer_period(timer).unwrap()
    );

    let steps = (3.0 / scenes::DT as f64).round() as u64;
    for step in 0..steps {
        scene.before_step(step);
        layer.step(&mut scene.world);
        for ev in ticks.try_iter() {
            assert_eq!((ev.kind, ev.node1), (EventKind::TimerTick, timer));
            let ball = scene.world.bodies[scene.body("ball").unwrap()].translation();
            println!(
                "step {:>3}  t = {:.2} s  tick {}  (ball y = {:.3})",
                ev.step,
                layer.logic().simulated_time(),
                ev.tick,
                ball.y
            );
        }
    }
    println!(
        "{} steps, {:.2} simulated seconds: {} ticks",
        layer.analysis().current_step(),
        layer.logic().simulated_time(),
        layer.logic().timer_ticks(timer).unwrap()
    );
    layer.logic_mut().remove_timer(timer).unwrap();
    println!(
        "timer removed; its id is now stale: {:?}",
        layer.logic().timer_ticks(timer).err()
    );
}
