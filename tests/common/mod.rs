//! Helpers shared by the integration tests.
#![allow(dead_code)]

use rapier3d::prelude::*;
use rapier_contact_graph::scenes::Scene;
use rapier_contact_graph::{ContactLayer, StepStats};

/// Steps a scene with the layer `n` times (script first), validating after every step.
pub fn run_validated(scene: &mut Scene, layer: &mut ContactLayer, first: u64, n: u64) -> StepStats {
    let mut stats = StepStats::default();
    for step in first..first + n {
        scene.before_step(step);
        stats = layer.step(&mut scene.world);
        if let Err(e) = layer.validate(&scene.world) {
            panic!("{}: validate() failed after step {}: {e}", scene.name, step);
        }
    }
    stats
}

/// Every body's pose, bit for bit, in handle order.
pub fn pose_bits(world: &PhysicsWorld) -> Vec<[u32; 7]> {
    world
        .bodies
        .iter()
        .map(|(_, rb)| {
            let p = rb.position();
            [
                p.translation.x.to_bits(),
                p.translation.y.to_bits(),
                p.translation.z.to_bits(),
                p.rotation.x.to_bits(),
                p.rotation.y.to_bits(),
                p.rotation.z.to_bits(),
                p.rotation.w.to_bits(),
            ]
        })
        .collect()
}
