//! What the step's walk reads of each of Rapier's active bodies, read ahead of the
//! walk in one pass over the active set: on rayon's threads with the `parallel`
//! feature (from [`PAR_MIN_BODIES`] active bodies on), in order otherwise. The walk
//! then applies the reads in Rapier's active-set order, so nodes, lists and events
//! are the same whichever way they were read.

use std::sync::atomic::{AtomicBool, Ordering};

use rapier3d::prelude::{RigidBody, RigidBodyHandle};

use crate::graph::mirror as nodes;
use crate::WorldView;

#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
/// From this many active bodies on the reads go to rayon's threads (`parallel`).
pub(crate) const PAR_MIN_BODIES: usize = 1024;

/// Whether the reads may use rayon's threads (`parallel` only; on by default).
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
static PARALLEL_READS: AtomicBool = AtomicBool::new(true);

/// Lets the walk's reads use rayon's threads or not (with the `parallel` feature;
/// without it they never do). For benchmarks comparing both in one process: the
/// results are the same either way. O(1).
#[doc(hidden)]
pub fn set_parallel_reads(on: bool) {
    PARALLEL_READS.store(on, Ordering::Relaxed);
}

/// One active body's state as the walk needs it.
#[derive(Clone, Copy, Debug)]
pub(super) struct BodyRead {
    pub(super) fixed: bool,
    pub(super) enabled: bool,
    pub(super) finite: bool,
    /// [`nodes::colliders_sig`] of its collider list.
    pub(super) sig: u64,
    /// One of its colliders is a sensor.
    pub(super) sensor: bool,
}

impl BodyRead {
    /// O(the body's colliders).
    pub(super) fn of(view: &WorldView, rb: &RigidBody) -> Self {
        let p = rb.position();
        Self {
            fixed: rb.is_fixed(),
            enabled: rb.is_enabled(),
            finite: p.translation.is_finite() && p.rotation.is_finite(),
            sig: nodes::colliders_sig(rb.colliders()),
            sensor: rb
                .colliders()
                .iter()
                .any(|&c| view.colliders.get(c).is_some_and(|c| c.is_sensor())),
        }
    }
}

/// Rapier's active bodies in its order, each with its read (`None`: not in the body
/// set). O(active bodies + their colliders), spread over rayon's threads with
/// `parallel`.
pub(super) fn read_active(view: &WorldView, out: &mut Vec<(RigidBodyHandle, Option<BodyRead>)>) {
    out.clear();
    out.extend(view.islands.active_bodies().map(|h| (h, None)));
    let read = |(h, r): &mut (RigidBodyHandle, Option<BodyRead>)| {
        *r = view.bodies.get(*h).map(|rb| BodyRead::of(view, rb));
    };
    #[cfg(feature = "parallel")]
    if out.len() >= PAR_MIN_BODIES && PARALLEL_READS.load(Ordering::Relaxed) {
        use rayon::prelude::*;
        out.par_iter_mut().with_min_len(256).for_each(read);
        return;
    }
    out.iter_mut().for_each(read);
}
