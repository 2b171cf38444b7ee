//! The checks of a deserialised state that later steps rely on.

use super::LayerState;
use crate::graph::{NodeKind, NodeSource};
use crate::NodeId;

/// The checks of a deserialised state that later steps rely on (see the module docs).
/// The largest step count a restored layer may hold. The analysis tells steps apart by
/// their number, so the count must have room to grow: 2^62 steps at a million a
/// second take 146,000 years, so only corrupted bytes come near it.
const MAX_RESTORED_STEP: u64 = 1 << 62;

pub(super) fn check_state(s: &LayerState) -> std::result::Result<(), String> {
    if s.coherence.step() > MAX_RESTORED_STEP {
        return Err(format!(
            "a step count of {} (more than 2^62: corrupted)",
            s.coherence.step()
        ));
    }
    let g = &s.graph;
    // The analysis tells "this step" from "an earlier one" by step numbers: one from
    // the future would make it skip a node or an edge as already done.
    let step = s.coherence.step();
    for (n, node) in g.nodes() {
        if node.seen_step > step || node.born_step > step {
            return Err(format!("node {n:?} carries a step number from the future"));
        }
    }
    for (e, edge) in g.edges() {
        if edge.walk_stamp > step || edge.updated_step > step || edge.created_step > step {
            return Err(format!("edge {e:?} carries a step number from the future"));
        }
    }
    if g.clock > step {
        return Err("the graph's clock is ahead of the step count".into());
    }
    g.nodes.check().map_err(|e| format!("node arena: {e}"))?;
    g.edges.check().map_err(|e| format!("edge arena: {e}"))?;
    g.validate().map_err(|e| e.to_string())?;
    s.groups.check(g)?;
    let live_of = |n: NodeId, kind: NodeKind| g.node(n).is_some_and(|node| node.kind() == kind);
    if let Some(n) = s.logic.rules.keys().find(|&&n| !live_of(n, NodeKind::Rule)) {
        return Err(format!("rule {n:?} has no rule node"));
    }
    if s.logic.rules.len() != g.count_of_kind(NodeKind::Rule) {
        return Err("rule nodes without a rule".into());
    }
    s.logic.timers.check()?;
    if let Some(n) = s
        .logic
        .timers
        .nodes()
        .find(|&n| !live_of(n, NodeKind::Timer))
    {
        return Err(format!("timer {n:?} has no timer node"));
    }
    if s.logic.timers.nodes().count() != g.count_of_kind(NodeKind::Timer) {
        return Err("timer nodes without a timer".into());
    }
    for &c in s.logic.declared.keys() {
        let ok = g.node(c).is_some_and(|n| {
            n.kind() == NodeKind::Composite && matches!(n.source(), NodeSource::Layer(_))
        });
        if !ok {
            return Err(format!("declared composite {c:?} has no composite node"));
        }
    }
    if let Some(s) = &s.speedups {
        s.config().validate().map_err(|e| e.to_string())?;
    }
    for m in s.monitor.iter().chain(&s.monitor_restore) {
        m.monitor.config().validate().map_err(|e| e.to_string())?;
        m.repair_config().validate().map_err(|e| e.to_string())?;
    }
    Ok(())
}
