//! A stable text form of the layer's state, for snapshot tests and debugging.
//!
//! Nodes and edges are listed in slot order, groups by their smallest member; floats
//! are rounded (to 3 decimals) so that a snapshot pins behaviour, not the last bit of
//! a solver sum. Marks are printed for the current step only: `prox=new`,
//! `touch=vanished`, and so on; a frozen (sleeping) edge prints `frozen`.

use std::fmt::Write;

use crate::graph::{EdgeKind, NodeId, Transition};
use crate::ContactLayer;

fn mark(t: Option<Transition>) -> &'static str {
    match t {
        Some(Transition::New) => "new",
        Some(Transition::Persistent) => "persistent",
        Some(Transition::Vanished) => "vanished",
        None => "-",
    }
}

fn round(x: f32) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let r = (x as f64 * 1000.0).round() / 1000.0;
    // Avoid "-0.000".
    if r == 0.0 {
        "0.000".to_string()
    } else {
        format!("{r:.3}")
    }
}

/// The state of the layer as text. `name` labels nodes (e.g. with a scene's body
/// names); unnamed nodes print their id.
///
/// # Example
/// ```
/// use rapier_contact_graph::{export::text::describe, ContactLayer};
/// let layer = ContactLayer::new();
/// assert!(describe(&layer, &|_| None).starts_with("step 0"));
/// ```
// Long: writes the dump's sections in order.
pub fn describe(layer: &ContactLayer, name: &dyn Fn(NodeId) -> Option<String>) -> String {
    let graph = layer.graph();
    let step = layer.analysis().current_step();
    let label = |n: NodeId| name(n).unwrap_or_else(|| format!("{n:?}"));
    let stats = layer.analysis().stats();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "step {step}: {} nodes, {} edges, {} groups ({} awake), largest {} bodies / {} variables",
        graph.node_count(),
        graph.edge_count(),
        stats.groups.count,
        stats.groups.awake_groups,
        stats.groups.largest_bodies,
        stats.groups.largest_variables,
    );
    let _ = writeln!(s, "nodes:");
    for (id, n) in graph.nodes() {
        let _ = writeln!(
            s,
            "  {} {} {}{}",
            n.kind().letter(),
            label(id),
            if n.is_awake() { "awake" } else { "still" },
            if n.is_non_finite() { " NON-FINITE" } else { "" },
        );
    }
    let _ = writeln!(s, "edges:");
    for (_, e) in graph.edges() {
        let c = e.cache();
        let kind = match e.kind() {
            EdgeKind::Physical => "physical",
            EdgeKind::Structural => "structural",
            EdgeKind::Geometric => "geometric",
            EdgeKind::Logical => "logical",
        };
        let _ = write!(s, "  {} - {} {kind}", label(e.a()), label(e.b()));
        if e.kind() == EdgeKind::Physical {
            if e.updated_step() == step {
                let _ = write!(
                    s,
                    " prox={} touch={}",
                    mark(e.proximity_mark(step)),
                    mark(e.touching_mark(step))
                );
            } else {
                let _ = write!(s, " frozen prox={} touch={}", c.proximity, c.touching);
            }
            let _ = write!(
                s,
                " contacts={} pen={} impulse={} xform_changed={}",
                c.contact_count,
                round(c.max_penetration),
                round(c.normal_impulse),
                c.relative_pose_changed
            );
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "groups:");
    let mut groups: Vec<_> = layer
        .groups()
        .iter()
        .map(|(_, g)| {
            let mut members: Vec<NodeId> = g.bodies.clone();
            members.sort();
            (members, g)
        })
        .collect();
    groups.sort_by_key(|(m, _)| m.first().map(|n| n.index()));
    for (members, g) in groups {
        let names: Vec<String> = members.iter().map(|&n| label(n)).collect();
        let ins: Vec<String> = g.insulators.iter().map(|&n| label(n)).collect();
        let _ = writeln!(
            s,
            "  [{}] {} edges, {} contacts, {} variables, on [{}]{}",
            names.join(", "),
            g.edges.len(),
            g.contacts,
            g.variables,
            ins.join(", "),
            if g.asleep { ", asleep" } else { "" }
        );
    }
    for e in layer.analysis().removed_edges() {
        let _ = writeln!(
            s,
            "removed edge {} - {} prox={} touch={}",
            label(e.a()),
            label(e.b()),
            mark(e.proximity_mark(step)),
            mark(e.touching_mark(step))
        );
    }
    s
}
