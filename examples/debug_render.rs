//! The contact graph drawn into a user's own Rapier debug-render backend, after
//! Rapier's own debug render, on the same backend.
//!
//! The backend here is a tiny text backend: it counts the lines it gets per kind of
//! object and prints the overlay's lines in a readable form. A real one would hand the
//! lines to a renderer (bevy gizmos, the testbed, a rasteriser); the calls are the same.
//!
//! Run: `cargo run --example debug_render`.

use rapier3d::prelude::*;
use rapier_contact_graph::debug_render::{BodyState, GraphOverlay, MarkerShape, OverlayStyle};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::ContactLayer;

/// Counts lines per object kind; records up to `keep` lines as text.
#[derive(Default)]
struct TextBackend {
    bodies: usize,
    colliders: usize,
    joints: usize,
    contacts: usize,
    other: usize,
    keep: usize,
    kept: Vec<String>,
}

impl DebugRenderBackend for TextBackend {
    fn draw_line(&mut self, object: DebugRenderObject, a: Vector, b: Vector, color: DebugColor) {
        let what = match object {
            DebugRenderObject::RigidBody(h, _) => {
                self.bodies += 1;
                format!("body {}", h.into_raw_parts().0)
            }
            DebugRenderObject::Collider(h, _) => {
                self.colliders += 1;
                format!("collider {}", h.into_raw_parts().0)
            }
            DebugRenderObject::ImpulseJoint(..) | DebugRenderObject::MultibodyJoint(..) => {
                self.joints += 1;
                "joint".into()
            }
            DebugRenderObject::ContactPair(..) => {
                self.contacts += 1;
                "contact".into()
            }
            _ => {
                self.other += 1;
                "other".into()
            }
        };
        if self.kept.len() < self.keep {
            self.kept.push(format!(
                "{what:>11}: ({:6.2} {:6.2} {:6.2}) -> ({:6.2} {:6.2} {:6.2})  hsla [{:5.1} {:.2} {:.2} {:.2}]",
                a.x, a.y, a.z, b.x, b.y, b.z, color[0], color[1], color[2], color[3]
            ));
        }
    }
}

impl TextBackend {
    fn total(&self) -> usize {
        self.bodies + self.colliders + self.joints + self.contacts + self.other
    }
}

fn main() {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = 0.01;
    // Ground, two piles of two balls (two contact groups), a sensor box around one pile,
    // and two boxes welded by a fixed joint (a composite) with a ball dropped on them.
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0),
    );
    for x in [-2.0, 2.0] {
        for k in 0..2 {
            world.insert(
                RigidBodyBuilder::dynamic().translation(Vector::new(x, 0.5 + k as f32, 0.0)),
                ColliderBuilder::ball(0.5),
            );
        }
    }
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.9, 1.0)
            .sensor(true)
            .translation(Vector::new(2.0, 1.0, 0.0)),
        None,
    );
    let (b1, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    let (b2, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(6.0, 0.5, 0.0)),
        ColliderBuilder::cuboid(0.5, 0.5, 0.5),
    );
    world.insert_impulse_joint(
        b1,
        b2,
        FixedJointBuilder::new().local_anchor2(Vector::new(-1.0, 0.0, 0.0)),
    );
    world.insert(
        RigidBodyBuilder::dynamic().translation(Vector::new(5.5, 3.0, 0.0)),
        ColliderBuilder::ball(0.3),
    );

    // The paper's speed-ups with fixation: bodies at rest end up held.
    let mut layer = ContactLayer::new();
    layer
        .speedups_mut()
        .set(Some(SpeedUps {
            hold: true,
            ..SpeedUps::contact_graph()
        }))
        .expect("valid speed-ups");
    let mut pipeline = DebugRenderPipeline::default();
    let mut overlay = GraphOverlay::new(OverlayStyle {
        marker: MarkerShape::Cross,
        ..OverlayStyle::default()
    });
    // Two frames: early, with piles, the welded pair and the dropped ball in contact
    // groups; late, when fixation holds every body. Held bodies are fixed in Rapier, and
    // Rapier keeps no contact between two fixed bodies, so the late frame has no
    // touching edge, no group, and the welded pair's container is gone with its
    // dynamic members: only the markers (green: held) and the trigger edges remain.
    let mut step = 0;
    for until in [5, 300] {
        while step < until {
            layer.step(&mut world);
            step += 1;
        }
        // One frame: Rapier's picture, then the graph on top, into the same backend.
        let mut backend = TextBackend::default();
        world.debug_render(&mut pipeline, &mut backend);
        let rapier_lines = backend.total();
        backend.keep = 8;
        let stats = overlay.render(&mut backend, &layer, &world.bodies, &world.colliders);

        println!("── after step {step} ──");
        println!("Rapier's debug render: {rapier_lines} lines");
        println!(
            "contact-graph overlay: {} lines: {} touching, {} trigger, {} structural edges, {} markers",
            stats.lines, stats.touching, stats.trigger, stats.structural, stats.markers
        );
        println!(
            "all lines by object: {} rigid body, {} collider, {} joint, {} contact pair",
            backend.bodies, backend.colliders, backend.joints, backend.contacts
        );
        println!("contact groups: {}", layer.groups().len());
        let mut counts = [0usize; BodyState::ALL.len()];
        for (id, _) in layer.graph().nodes() {
            if let Some(s) = BodyState::of(&layer, &world.bodies, id, overlay.style.rest_speed) {
                counts[s as usize] += 1;
            }
        }
        let states: Vec<String> = BodyState::ALL
            .iter()
            .zip(counts)
            .filter(|(_, n)| *n > 0)
            .map(|(s, n)| format!("{n} {}", s.name()))
            .collect();
        println!("body states: {}", states.join(", "));
        println!("first overlay lines:");
        for line in &backend.kept {
            println!("  {line}");
        }
    }
}
