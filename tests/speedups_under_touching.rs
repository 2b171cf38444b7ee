//! The speed-ups decide the same under touching tracking (the default, driven by
//! Rapier's collision events) as under proximity tracking (every awake pair read each
//! step): what they read besides the touching edges, what holds a body up, they read
//! from Rapier's narrow phase for the bodies concerned, and the world writes they
//! make are applied in handle order. For every one of the 128 combinations on a
//! settling pile: the same poses, velocities and sleep timers bit for bit, the same
//! sleepy, held and parked bodies and the same groups at every step, with
//! `validate()` after each.

mod common;

use common::{pose_bits, run_validated};
use rapier3d::prelude::*;
use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::ContactLayer;
use rcg_scenes::sphere_pile;

/// Everything one step leaves behind that the two trackings must agree on.
#[derive(PartialEq, Debug)]
struct After {
    poses: Vec<[u32; 7]>,
    motion: Vec<[u32; 8]>,
    speedups: Vec<[bool; 3]>,
    groups: Vec<Vec<u32>>,
}

fn after(layer: &ContactLayer, world: &PhysicsWorld) -> After {
    let s = layer.speedups().expect("speed-ups on");
    let motion = world
        .bodies
        .iter()
        .map(|(_, rb)| {
            let (v, w, a) = (rb.linvel(), rb.angvel(), rb.activation());
            [
                v.x,
                v.y,
                v.z,
                w.x,
                w.y,
                w.z,
                a.time_since_can_sleep,
                a.angular_threshold,
            ]
            .map(f32::to_bits)
        })
        .collect();
    let speedups = world
        .bodies
        .iter()
        .map(|(h, _)| [s.is_sleepy(h), s.is_fixated(h), s.is_parked(h)])
        .collect();
    let mut groups: Vec<Vec<u32>> = layer
        .groups()
        .iter()
        .map(|(_, g)| {
            let mut members: Vec<u32> = g.bodies.iter().map(|n| n.index()).collect();
            members.sort_unstable();
            members
        })
        .collect();
    groups.sort_unstable();
    After {
        poses: pose_bits(world),
        motion,
        speedups,
        groups,
    }
}

fn run(bits: u8, tracking: Tracking) -> Vec<After> {
    let mut scene = sphere_pile(60, 7);
    let mut layer = ContactLayer::with_tracking(tracking);
    layer
        .speedups_mut()
        .set(Some(rcg_lab::table5::combination(bits)))
        .unwrap();
    (0..400)
        .map(|step| {
            run_validated(&mut scene, &mut layer, step, 1);
            assert_eq!(
                layer.analysis().coherence().tracking(),
                tracking,
                "combination {bits:07b}: the tracking in effect at step {step}"
            );
            after(&layer, &scene.world)
        })
        .collect()
}

fn same_under_both(bits: std::ops::Range<u8>) {
    for b in bits {
        let touching = run(b, Tracking::Touching);
        let proximity = run(b, Tracking::Proximity);
        for (step, (t, p)) in touching.iter().zip(&proximity).enumerate() {
            assert_eq!(t, p, "combination {b:07b} differs at step {step}");
        }
    }
}

#[test]
fn combinations_without_fixation_decide_the_same() {
    same_under_both(0..64);
}

#[test]
fn combinations_with_fixation_decide_the_same_cache_to_zero() {
    same_under_both(64..96);
}

#[test]
fn combinations_with_fixation_decide_the_same_damp_and_subgroup() {
    same_under_both(96..128);
}
