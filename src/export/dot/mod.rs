//! Graphviz DOT export of the contact graph, drawn like the paper's Figs. 2 and 9.
//!
//! [`to_dot`] writes the graph of a [`ContactLayer`] (and, on request, its contact
//! groups) as an undirected DOT graph; render it with `dot -Tpng graph.dot -o graph.png`
//! or `dot -Tsvg`. The text is deterministic: nodes and groups are sorted by slot
//! index, edges by the indices of their end nodes, and nothing depends on hash order,
//! so two runs of the same scene give byte-identical files that diff and snapshot well.
//!
//! # Example
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::export::dot::{to_dot, DotOptions};
//! use rapier_contact_graph::ContactLayer;
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.99, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! for _ in 0..10 {
//!     layer.step(&mut world);
//! }
//! let dot = to_dot(&layer, &DotOptions::default());
//! assert!(dot.contains("graph contact_graph {"));
//! assert!(dot.contains("subgraph cluster_g0"), "the ball is a group");
//! // std::fs::write("graph.dot", &dot)?;  then: dot -Tpng graph.dot -o graph.png
//! ```

use std::fmt::{self, Write as _};

use crate::graph::{Category, ContactGraph, Edge, EdgeKind, Node, NodeId};
use crate::groups::{Group, Groups};
use crate::ContactLayer;

/// What [`to_dot`] and [`graph_to_dot`] draw.
///
/// Build it with struct-update syntax from [`DotOptions::default`], which draws
/// everything: groups as clusters, proximity edges, contact counts, no names.
///
/// ```
/// use rapier_contact_graph::export::dot::DotOptions;
///
/// let names = |n: rapier_contact_graph::NodeId| (n.index() == 0).then(|| "ground".to_string());
/// let options = DotOptions {
///     proximity_edges: false,
///     label: Some(&names),
///     ..DotOptions::default()
/// };
/// assert!(options.groups);
/// ```
#[derive(Clone, Copy)]
pub struct DotOptions<'a> {
    /// Draw every contact group as a cluster (`subgraph cluster_gK`) around its member
    /// nodes, with insulators outside, like the paper's Fig. 9. Default `true`.
    pub groups: bool,
    /// Include the physical edges whose bodies do not touch (proximity only, or kept
    /// until the obsolete test removes them), drawn dashed grey. Default `true`.
    pub proximity_edges: bool,
    /// Label every touching physical edge with its number of active contacts.
    /// Default `true`.
    pub contact_counts: bool,
    /// Extra name for a node, shown on a second line under `R3`-style symbols
    /// (for instance the scene's body names). `None` (the default), or a closure
    /// returning `None`, shows the symbol alone.
    pub label: Option<&'a dyn Fn(NodeId) -> Option<String>>,
}

impl Default for DotOptions<'_> {
    fn default() -> Self {
        Self {
            groups: true,
            proximity_edges: true,
            contact_counts: true,
            label: None,
        }
    }
}

impl fmt::Debug for DotOptions<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DotOptions")
            .field("groups", &self.groups)
            .field("proximity_edges", &self.proximity_edges)
            .field("contact_counts", &self.contact_counts)
            .field("label", &self.label.map(|_| "<fn>"))
            .finish()
    }
}

/// The contact graph of `layer` (and its contact groups, if [`DotOptions::groups`])
/// as a Graphviz DOT document, in the visual encoding below.
///
/// The output is deterministic: it depends only on the graph and groups, never on
/// hash order. Cost: O(nodes + edges + group members), plus sorting the edges.
///
/// # Visual encoding
///
/// The encoding follows the paper's symbolic notation (Table 1) and adds what a
/// picture of a running simulation needs to be read at a glance.
///
/// **Nodes.** The label is the kind's symbol letter plus the node's slot index (`R3`,
/// `F0`, …) — the paper labels nodes by their letter, and the index tells two rigid
/// bodies apart and matches [`NodeId::index`]. An optional name
/// ([`DotOptions::label`]) goes on a second line. The shape gives the category of
/// Table 1:
///
/// | category  | kinds      | shape   | style |
/// |-----------|------------|---------|-------|
/// | physical  | R, L       | circle  | solid when awake, **dashed** when asleep |
/// | physical  | F, S       | circle  | **filled grey**: insulators (Fig. 8) |
/// | container | C, M       | box     | solid |
/// | logical   | A, V, T    | diamond | solid |
///
/// Fixed and scripted bodies are filled because they are what separates contact
/// groups: "they behave as if they had infinite mass" and the traversal does not pass
/// through them, so one floor can carry many groups. Filling them makes the shared
/// insulators of Fig. 9 stand out. Sleeping simulated bodies are dashed because their
/// state is frozen (the layer does not walk their pairs), which is exactly what one
/// wants to see when checking sleep. A body whose pose was not finite at the last
/// update is outlined in red.
///
/// **Edges.** The line style gives the edge category of Table 2:
///
/// | edge                               | style |
/// |------------------------------------|-------|
/// | physical, touching                 | solid, labelled with the contact count |
/// | physical, proximity only          | dashed grey |
/// | physical, neither (stale)          | dashed light grey |
/// | structural (body – container)      | bold |
/// | geometric (body – trigger)         | dotted |
/// | logical (rule – body)              | dashed blue |
///
/// Touching edges are the ones that carry contact variables and join groups, so they
/// get the strongest plain line; proximity-only edges are in the graph (the paper's
/// "close proximity") but constrain nothing, so they are faint, and can be left out
/// ([`DotOptions::proximity_edges`]) to declutter a dense pile. An edge whose pair has
/// left Rapier's narrow phase but which the obsolete test (§3.1) has not removed yet
/// is lighter still.
///
/// **Groups.** With [`DotOptions::groups`], every contact group is a Graphviz cluster
/// (`subgraph cluster_gK`) holding its member nodes, as the regions A–D of Fig. 9. A
/// cluster's label gives its number, size, contact count and whether it sleeps (a
/// sleeping group has a dashed frame). Insulators stay outside every cluster: they
/// belong to no group and are shared by several, which is the point of Fig. 9. Groups
/// are numbered by their smallest member slot index, not by their internal ids, so the
/// numbering is stable across runs. All edges are written at the top level after the
/// clusters: an edge written inside a cluster would pull its insulator end into it.
///
/// **Layout.** The graph is meant for `dot` (the only Graphviz layout that draws
/// clusters well). Each edge is written *B* first (`n5 -- n2`): `dot` ranks the first
/// end of an edge above the second, so nodes with lower slot indices end up lower in
/// the picture. Scenes usually create the ground first and stack bodies upwards, so
/// the picture then reads like the scene: floor at the bottom, piles standing on it.
///
///
/// # Example
/// ```
/// use rapier_contact_graph::export::dot::{to_dot, DotOptions};
/// use rcg_scenes as scenes;
/// use rapier_contact_graph::ContactLayer;
///
/// let mut scene = scenes::ball_on_box();
/// let mut layer = ContactLayer::new();
/// for _ in 0..150 {
///     layer.step(&mut scene.world);
/// }
/// // Name the nodes after the scene's bodies.
/// let graph = layer.graph();
/// let names: Vec<_> = scene
///     .bodies
///     .iter()
///     .filter_map(|&(name, h)| Some((graph.node_of_body(h)?, name)))
///     .collect();
/// let label = |n| names.iter().find(|(m, _)| *m == n).map(|(_, s)| s.to_string());
/// let dot = to_dot(&layer, &DotOptions { label: Some(&label), ..Default::default() });
///
/// // The fixed ground is a filled insulator outside the one group (box + ball).
/// assert!(dot.contains(r#"n0 [label="F0\nground", shape=circle, style=filled"#));
/// assert_eq!(dot.matches("subgraph cluster_").count(), 1);
/// assert!(dot.contains("n1 -- n0 [style=solid"), "the box touches the ground");
/// ```
pub fn to_dot(layer: &ContactLayer, options: &DotOptions) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// Contact graph at step {}: {} nodes, {} edges, {} groups.",
        layer.analysis().current_step(),
        layer.graph().node_count(),
        layer.graph().edge_count(),
        layer.groups().len()
    );
    write_dot(&mut out, layer.graph(), Some(layer.groups()), options);
    out
}

/// [`to_dot`] for a graph and groups held apart from a layer (for instance a cloned
/// snapshot). Without `groups`, or with [`DotOptions::groups`] off, no cluster is
/// drawn.
pub fn graph_to_dot(graph: &ContactGraph, groups: Option<&Groups>, options: &DotOptions) -> String {
    let mut out = String::new();
    write_dot(&mut out, graph, groups, options);
    out
}

/// Escapes `s` for use inside a double-quoted DOT label: backslashes and quotes are
/// escaped, and line breaks become Graphviz's centred line break `\n`.
///
/// ```
/// use rapier_contact_graph::export::dot::escape;
/// assert_eq!(escape("a \"b\"\\c\nd"), r#"a \"b\"\\c\nd"#);
/// ```
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => {}
            c => out.push(c),
        }
    }
    out
}

/// `n` and the noun in singular or plural.
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The DOT node name of a node: `n` plus its slot index (unique among live nodes).
fn name(id: NodeId) -> String {
    format!("n{}", id.index())
}

fn write_dot(
    out: &mut String,
    graph: &ContactGraph,
    groups: Option<&Groups>,
    options: &DotOptions,
) {
    // `fmt::Write` for a `String` never fails.
    let _ = try_write_dot(out, graph, groups, options);
}

// Long: writes the document's parts (nodes, clusters, edges) in order into one writer.
fn try_write_dot(
    out: &mut String,
    graph: &ContactGraph,
    groups: Option<&Groups>,
    options: &DotOptions,
) -> fmt::Result {
    writeln!(out, "graph contact_graph {{")?;
    writeln!(
        out,
        "  graph [fontname=\"Helvetica\", fontsize=11, nodesep=0.3, ranksep=0.5];"
    )?;
    writeln!(
        out,
        "  node [fontname=\"Helvetica\", fontsize=11, margin=0.04];"
    )?;
    writeln!(out, "  edge [fontname=\"Helvetica\", fontsize=9];")?;

    // Clusters: each group's live members, sorted; groups by their smallest member.
    let mut clustered = vec![
        false;
        graph
            .nodes()
            .map(|(id, _)| id.index() as usize + 1)
            .max()
            .unwrap_or(0)
    ];
    if let (true, Some(groups)) = (options.groups, groups) {
        let mut sorted: Vec<(Vec<NodeId>, &Group)> = groups
            .iter()
            .map(|(_, g)| {
                let mut members: Vec<NodeId> = g
                    .bodies
                    .iter()
                    .copied()
                    .filter(|&n| graph.contains_node(n))
                    .collect();
                members.sort_by_key(|n| n.index());
                members.dedup();
                (members, g)
            })
            .filter(|(members, _)| !members.is_empty())
            .collect();
        sorted.sort_by_key(|(members, _)| members[0].index());
        for (k, (members, group)) in sorted.iter().enumerate() {
            writeln!(out, "  subgraph cluster_g{k} {{")?;
            let asleep = if group.asleep { ", asleep" } else { "" };
            writeln!(
                out,
                "    graph [label=\"group {k}: {}, {}{asleep}\", style=\"{}\", color=grey40];",
                count(members.len(), "body", "bodies"),
                count(group.contacts as usize, "contact", "contacts"),
                if group.asleep {
                    "rounded,dashed"
                } else {
                    "rounded"
                },
            )?;
            for &n in members {
                let slot = &mut clustered[n.index() as usize];
                if *slot {
                    continue; // Never twice: a node is in one group at most.
                }
                *slot = true;
                if let Some(node) = graph.node(n) {
                    write_node(out, "    ", n, node, options)?;
                }
            }
            writeln!(out, "  }}")?;
        }
    }

    // Every other node (insulators, logical nodes, ungrouped bodies), in slot order.
    for (id, node) in graph.nodes() {
        if !clustered[id.index() as usize] {
            write_node(out, "  ", id, node, options)?;
        }
    }

    // Edges at the top level (inside a cluster they would pull an insulator into it),
    // sorted by their end nodes' indices: slot order depends on insertion history.
    // Written B first: dot ranks the first end above the second, so the lower index
    // (usually the ground, and the bottom of a pile) is drawn below.
    let mut edges: Vec<&Edge> = graph
        .edges()
        .map(|(_, e)| e)
        .filter(|e| options.proximity_edges || e.kind() != EdgeKind::Physical || e.is_touching())
        .collect();
    edges.sort_by_key(|e| (e.a().index(), e.b().index()));
    for e in edges {
        write!(out, "  {} -- {} [", name(e.b()), name(e.a()))?;
        match e.kind() {
            EdgeKind::Physical if e.is_touching() => {
                write!(out, "style=solid")?;
                if options.contact_counts {
                    write!(out, ", label=\"{}\"", e.cache().contact_count)?;
                }
            }
            EdgeKind::Physical if e.is_proximate() => write!(out, "style=dashed, color=grey50")?,
            EdgeKind::Physical => write!(out, "style=dashed, color=grey80")?,
            EdgeKind::Structural => write!(out, "style=bold")?,
            EdgeKind::Geometric => write!(out, "style=dotted")?,
            EdgeKind::Logical => write!(out, "style=dashed, color=blue")?,
        }
        writeln!(out, "];")?;
    }
    writeln!(out, "}}")
}

fn write_node(
    out: &mut String,
    indent: &str,
    id: NodeId,
    node: &Node,
    options: &DotOptions,
) -> fmt::Result {
    let kind = node.kind();
    write!(
        out,
        "{indent}{} [label=\"{}{}",
        name(id),
        kind.letter(),
        id.index()
    )?;
    if let Some(extra) = options.label.and_then(|f| f(id)) {
        write!(out, "\\n{}", escape(&extra))?;
    }
    let shape = match kind.category() {
        Category::Physical => "circle",
        Category::Container => "box",
        Category::Logical => "diamond",
    };
    write!(out, "\", shape={shape}")?;
    if kind.is_insulator() {
        write!(out, ", style=filled, fillcolor=grey80")?;
    } else if kind.is_simulated() && !node.is_awake() {
        write!(out, ", style=dashed")?;
    }
    if node.is_non_finite() {
        write!(out, ", color=red")?;
    }
    writeln!(out, "];")
}

#[cfg(test)]
mod tests;
