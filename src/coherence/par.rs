//! The analysis's passes that may run on rayon's threads (the `parallel` feature):
//! read-only passes over many nodes whose results are put back in one order, so that
//! the graph, the monitor's findings and the events are the same whichever threads
//! computed them. Without `parallel` (or below [`PAR_MIN_NODES`] nodes) they run in
//! order on the calling thread.

use std::sync::atomic::{AtomicBool, Ordering};

/// From this many nodes on a pass goes to rayon's threads (`parallel`).
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
pub(crate) const PAR_MIN_NODES: usize = 1024;

/// Nodes per rayon task: enough work per task to outweigh handing it over.
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
pub(crate) const PAR_CHUNK: usize = 256;

/// Whether the passes may use rayon's threads (`parallel` only; on by default).
static PARALLEL: AtomicBool = AtomicBool::new(true);

/// Lets the analysis's passes use rayon's threads or not (with the `parallel`
/// feature; without it they never do). For benchmarks comparing both in one process:
/// the results are the same either way. O(1).
#[doc(hidden)]
pub fn set_parallel_analysis(on: bool) {
    PARALLEL.store(on, Ordering::Relaxed);
}

/// Whether a pass over `len` nodes goes to rayon's threads. O(1).
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
pub(crate) fn parallel_for(len: usize) -> bool {
    cfg!(feature = "parallel") && len >= PAR_MIN_NODES && PARALLEL.load(Ordering::Relaxed)
}
