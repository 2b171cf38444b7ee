//! The stamp of the world a snapshot was taken with, and what a mismatch names.

use serde::{Deserialize, Serialize};

use super::LayerSnapshot;
use crate::graph::NodeSource;
use crate::WorldView;

/// A digest of the world a snapshot was taken with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(super) struct WorldStamp {
    pub(super) bodies: u64,
    pub(super) colliders: u64,
    pub(super) joints: u64,
    pub(super) digest: u64,
}

/// A 64-bit mix of words (FxHash's multiply-rotate, with a final avalanche).
struct Digest(u64);

impl Digest {
    fn word(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn floats(&mut self, xs: &[f32]) {
        for x in xs {
            self.word(x.to_bits() as u64);
        }
    }
    fn handle(&mut self, (i, g): (u32, u32)) {
        self.word(((g as u64) << 32) | i as u64);
    }
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^ (x >> 33)
    }
}

fn pose_words(p: &rapier3d::math::Pose) -> [f32; 7] {
    let (t, r) = (p.translation, p.rotation);
    [t.x, t.y, t.z, r.x, r.y, r.z, r.w]
}

impl WorldStamp {
    /// O(bodies + colliders + joints).
    pub(super) fn of(view: &WorldView) -> Self {
        let mut d = Digest(0);
        for (h, rb) in view.bodies.iter() {
            d.handle(h.into_raw_parts());
            d.word(rb.body_type() as u64);
            d.word(rb.is_enabled() as u64 | (rb.is_sleeping() as u64) << 1);
            d.floats(&pose_words(rb.position()));
            let (v, w) = (rb.linvel(), rb.angvel());
            d.floats(&[v.x, v.y, v.z, w.x, w.y, w.z]);
        }
        for (h, c) in view.colliders.iter() {
            d.handle(h.into_raw_parts());
            d.word(c.parent().map_or(u64::MAX, |p| {
                let (i, g) = p.into_raw_parts();
                ((g as u64) << 32) | i as u64
            }));
            d.word(c.is_sensor() as u64 | (c.is_enabled() as u64) << 1);
            d.floats(&pose_words(c.position()));
        }
        let mut joints = 0u64;
        for (h, j) in view.impulse_joints.iter() {
            joints += 1;
            d.handle(h.into_raw_parts());
            d.handle(j.body1().into_raw_parts());
            d.handle(j.body2().into_raw_parts());
        }
        for mb in view.multibody_joints.multibodies() {
            for l in mb.links() {
                joints += 1;
                d.handle(l.rigid_body_handle().into_raw_parts());
            }
            d.word(u64::MAX);
        }
        Self {
            bodies: view.bodies.len() as u64,
            colliders: view.colliders.len() as u64,
            joints,
            digest: d.finish(),
        }
    }
}

/// Says how `view` differs from the snapshot's world, as precisely as it can.
pub(super) fn mismatch(snapshot: &LayerSnapshot, view: &WorldView) -> String {
    for (id, node) in snapshot.state.graph.nodes() {
        match node.source() {
            NodeSource::Body(h) if !view.bodies.contains(h) => {
                return format!("node {id:?} stands for body {h:?}, which the world lacks");
            }
            NodeSource::StaticCollider(h) | NodeSource::Sensor(h)
                if !view.colliders.contains(h) =>
            {
                return format!("node {id:?} stands for collider {h:?}, which the world lacks");
            }
            _ => {}
        }
    }
    let (here, saved) = (WorldStamp::of(view), snapshot.world);
    if (here.bodies, here.colliders, here.joints) != (saved.bodies, saved.colliders, saved.joints) {
        return format!(
            "the world has {} bodies, {} colliders and {} joints; the snapshot's had {}, {} and {}",
            here.bodies, here.colliders, here.joints, saved.bodies, saved.colliders, saved.joints
        );
    }
    "the world has the same objects as the snapshot's but not the same state (poses, \
     velocities, types or sleep): restore against the world saved with the snapshot"
        .into()
}
