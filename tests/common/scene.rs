//! Running a scene with the layer, validated after every step, and naming its nodes
//! for the text snapshots.

use std::collections::HashMap;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, NodeId, StepStats};
use rcg_scenes::Scene;

/// A scene named `name` around `world`, with no named bodies and no script.
pub fn plain_scene(name: &'static str, world: PhysicsWorld) -> Scene {
    Scene {
        name,
        world,
        bodies: Vec::new(),
        script: None,
    }
}

/// Steps a scene with the layer `n` times (script first), validating after every step.
pub fn run_validated(scene: &mut Scene, layer: &mut ContactLayer, first: u64, n: u64) -> StepStats {
    let mut stats = StepStats::default();
    for step in first..first + n {
        stats = step_validated(scene, layer, step);
    }
    stats
}

/// One step of a scene with the layer (script first, `step` is the step index), then
/// `validate()`; panics naming the scene and step if it fails.
pub fn step_validated(scene: &mut Scene, layer: &mut ContactLayer, step: u64) -> StepStats {
    scene.before_step(step);
    let stats = layer.step(&mut scene.world);
    if let Err(e) = layer.validate(&scene.world) {
        panic!("{}: validate() failed after step {}: {e}", scene.name, step);
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

/// Names nodes after the scene's named bodies; remembers names of nodes removed later.
#[derive(Default)]
pub struct Names(HashMap<NodeId, String>);

impl Names {
    /// Learns the names of the scene's bodies that have nodes now.
    pub fn learn(&mut self, scene: &Scene, layer: &ContactLayer) {
        for (name, h) in &scene.bodies {
            if let Some(n) = layer.graph().node_of_body(*h) {
                self.0.entry(n).or_insert_with(|| name.to_string());
            }
        }
        // Triggers are named after the body carrying them.
        for (id, node) in layer.graph().nodes() {
            if let Some(carrier) = node.carrier() {
                if let Some((name, _)) = scene.bodies.iter().find(|(_, h)| *h == carrier) {
                    self.0.entry(id).or_insert_with(|| format!("{name}-sensor"));
                }
            }
        }
        // Unnamed bodies get their kind letter and handle index.
        for (id, node) in layer.graph().nodes() {
            self.0.entry(id).or_insert_with(|| match node.body() {
                Some(h) => format!("{}#{}", node.kind().letter(), h.into_raw_parts().0),
                None => format!("{id:?}"),
            });
        }
    }

    /// Names a node explicitly.
    pub fn set(&mut self, n: NodeId, name: &str) {
        self.0.insert(n, name.to_string());
    }

    /// The text form of the layer's state with these names.
    pub fn describe(&self, layer: &ContactLayer) -> String {
        rapier_contact_graph::export::text::describe(layer, &|n| self.0.get(&n).cloned())
    }
}

/// Runs a scene and snapshots its state at the given (1-based, ascending) frames.
/// The snapshots show the paper's whole graph, proximity edges and per-edge contact
/// details included: the layer tracks proximity.
pub fn snapshot_frames(mut scene: Scene, frames: &[u64]) -> Vec<(u64, String)> {
    let mut layer =
        ContactLayer::with_tracking(rapier_contact_graph::coherence::Tracking::Proximity);
    let mut names = Names::default();
    let mut out = Vec::new();
    let mut done = 0;
    for &f in frames {
        run_validated(&mut scene, &mut layer, done, f - done);
        done = f;
        names.learn(&scene, &layer);
        out.push((f, names.describe(&layer)));
    }
    out
}

/// Formats an event stream with names, one event a line, for snapshots.
pub fn format_events(events: &[rapier_contact_graph::Event], names: &Names) -> String {
    let mut s = String::new();
    for ev in events {
        let name = |n: NodeId| names.0.get(&n).cloned().unwrap_or_else(|| format!("{n:?}"));
        let b = ev
            .node2
            .map(|b| format!(" {}", name(b)))
            .unwrap_or_default();
        let tick = if ev.tick > 0 {
            format!(" #{}", ev.tick)
        } else {
            String::new()
        };
        s += &format!(
            "{:>4} {:?} {}{}{}\n",
            ev.step,
            ev.kind,
            name(ev.node1),
            b,
            tick
        );
    }
    s
}

/// Switches the layer's monitor to `mode` with the default detector and repair
/// settings (valid, so it cannot fail).
pub fn monitor_in(layer: &mut ContactLayer, mode: rapier_contact_graph::monitor::MonitorMode) {
    use rapier_contact_graph::monitor::{MonitorConfig, RepairConfig};
    layer
        .monitor_mut()
        .set(mode, MonitorConfig::default(), RepairConfig::default())
        .expect("the default monitor settings are valid");
}

/// The monitor's violations counted so far, by kind (the monitor must be on).
pub fn violation_totals(layer: &ContactLayer) -> rapier_contact_graph::monitor::ViolationCounts {
    layer
        .monitor()
        .map(|m| m.monitor().totals())
        .expect("the monitor is on")
}
