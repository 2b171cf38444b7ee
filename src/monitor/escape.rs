//! Escapes: bodies whose pose or velocity is not finite.
//!
//! Looked at: the refreshed and the created bodies (a body can only go non-finite by
//! moving, or by a user edit, which wakes it), the bodies in an open episode (to close
//! it when the pose is finite again), and the bodies Rapier's NaN quarantine reports.
//! The quarantine resets a body to its last finite pose and disables it within the
//! step, so after a step only its report tells.

use std::collections::HashSet;

use rapier3d::math::Real;
use rapier3d::prelude::{RigidBody, RigidBodyHandle};

use super::{Ctx, Violation, ViolationKind};

#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Escape {
    /// Bodies in a reported episode.
    #[cfg_attr(feature = "serde", serde(with = "crate::util::serde_maps::sorted_set"))]
    escaped: HashSet<RigidBodyHandle>,
    /// Scratch.
    look: Vec<RigidBodyHandle>,
}

/// The number of non-finite scalars of a body's pose (7) and velocities (6).
fn non_finite(rb: &RigidBody) -> u32 {
    let p = rb.position();
    let (t, r) = (p.translation, p.rotation);
    let (v, w) = (rb.linvel(), rb.angvel());
    let scalars = [
        t.x, t.y, t.z, r.x, r.y, r.z, r.w, v.x, v.y, v.z, w.x, w.y, w.z,
    ];
    scalars.iter().filter(|x| !x.is_finite()).count() as u32
}

impl Escape {
    pub(crate) fn forget(&mut self, h: RigidBodyHandle) {
        self.escaped.remove(&h);
    }

    pub(crate) fn check(
        &mut self,
        ctx: &Ctx,
        quarantined: &[RigidBodyHandle],
        out: &mut Vec<Violation>,
    ) {
        let layer = ctx.layer;
        let graph = layer.graph();
        for &h in quarantined {
            if self.escaped.insert(h) {
                out.push(Violation {
                    step: ctx.step,
                    kind: ViolationKind::Escape,
                    body: h,
                    node: graph.node_of_body(h),
                    value: 0.0,
                });
            }
        }
        let coherence = layer.coherence();
        self.look.clear();
        self.look.extend(
            coherence
                .refreshed_nodes()
                .iter()
                .chain(coherence.created_nodes())
                .filter_map(|&n| graph.body_of(n)),
        );
        self.look.extend(self.escaped.iter().copied());
        for i in 0..self.look.len() {
            let h = self.look[i];
            let Some(rb) = ctx.view.bodies.get(h) else {
                self.escaped.remove(&h);
                continue;
            };
            let bad = non_finite(rb);
            if bad == 0 {
                if !quarantined.contains(&h) {
                    self.escaped.remove(&h);
                }
            } else if self.escaped.insert(h) {
                out.push(Violation {
                    step: ctx.step,
                    kind: ViolationKind::Escape,
                    body: h,
                    node: graph.node_of_body(h),
                    value: bad as Real,
                });
            }
        }
    }
}
