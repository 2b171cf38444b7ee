//! Pictures of the contact graph, like the paper's Figs. 2 and 9.
//!
//! Runs two shared scenes headless with the layer, writes their contact graphs as
//! Graphviz DOT files (contact groups as clusters, insulators outside them) and prints
//! the group statistics. If Graphviz's `dot` is on the PATH it also renders PNGs.
//!
//! ```text
//! cargo run --example graph_picture [OUTPUT_DIR]   # default: target/graph_picture
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;

use rapier_contact_graph::export::dot::{to_dot, DotOptions};
use rapier_contact_graph::{ContactLayer, NodeId};
use rcg_scenes::{self as scenes, Scene};

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/graph_picture".into()),
    );
    std::fs::create_dir_all(&dir)?;
    let have_dot = Command::new("dot")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success());

    // Two piles, settled: two sleeping groups sharing the fixed ground and wall (Fig. 9).
    // Ball on box, the step before the ball lands: all awake, and the ball's edge to the
    // box is proximity only (dashed grey), so the ball is a group of its own.
    for (file, scene, steps) in [
        ("two_piles", scenes::two_piles_with_wall(), 120),
        ("ball_on_box", scenes::ball_on_box(), 39),
    ] {
        let dot_path = dir.join(format!("{file}.dot"));
        picture(scene, steps, &dot_path)?;
        let png_path = dot_path.with_extension("png");
        if have_dot {
            let status = Command::new("dot")
                .arg("-Tpng")
                .arg(&dot_path)
                .arg("-o")
                .arg(&png_path)
                .status()?;
            if status.success() {
                println!("  rendered {}", png_path.display());
            } else {
                println!("  dot failed ({status}) on {}", dot_path.display());
            }
        } else {
            println!(
                "  render with: dot -Tpng {} -o {}   (Graphviz not found on PATH)",
                dot_path.display(),
                png_path.display()
            );
        }
    }
    Ok(())
}

/// Runs `scene` for `steps` steps with the layer, writes its DOT file and prints what
/// the groups are.
fn picture(mut scene: Scene, steps: u64, path: &Path) -> std::io::Result<()> {
    let mut layer = ContactLayer::new();
    for step in 0..steps {
        scene.before_step(step);
        layer.step(&mut scene.world);
    }

    // Name the nodes after the scene's bodies.
    let graph = layer.graph();
    let names: Vec<(NodeId, &str)> = scene
        .bodies
        .iter()
        .filter_map(|&(name, h)| Some((graph.node_of_body(h)?, name)))
        .collect();
    let name_of = |n: NodeId| {
        names
            .iter()
            .find(|(m, _)| *m == n)
            .map(|(_, s)| s.to_string())
    };
    let options = DotOptions {
        label: Some(&name_of),
        ..DotOptions::default()
    };
    std::fs::write(path, to_dot(&layer, &options))?;

    let s = layer.analysis().stats();
    let g = s.groups;
    println!(
        "{} after {} steps -> {}",
        scene.name,
        s.step,
        path.display()
    );
    println!(
        "  nodes {}, edges {}, awake bodies {}; groups {} (awake {}), largest group: bodies {}, variables {}; variables in all {}",
        s.nodes,
        s.edges,
        s.awake_bodies,
        g.count,
        g.awake_groups,
        g.largest_bodies,
        g.largest_variables,
        g.total_variables
    );
    // Groups by their smallest member, as numbered in the picture.
    let mut groups: Vec<_> = layer.groups().iter().map(|(_, grp)| grp).collect();
    groups.sort_by_key(|grp| grp.bodies.iter().map(|n| n.index()).min());
    let list = |nodes: &[NodeId]| {
        let mut v: Vec<_> = nodes.to_vec();
        v.sort();
        v.iter()
            .map(|&n| name_of(n).unwrap_or_else(|| format!("n{}", n.index())))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for (k, grp) in groups.iter().enumerate() {
        println!(
            "  group {k}: [{}] on insulators [{}]; {} contacts, {} variables{}",
            list(&grp.bodies),
            list(&grp.insulators),
            grp.contacts,
            grp.variables,
            if grp.asleep { ", asleep" } else { "" }
        );
    }
    Ok(())
}
