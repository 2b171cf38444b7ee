//! Headless pictures of a scene, coloured as the paper's Fig. 17: PNG frames of what
//! Rapier's own [`DebugRenderPipeline`] draws, every collider's lines in the colour of
//! its body's state.
//!
//! The paper's caption: "Purple means sleepy, red moving, blue absolute rest, green
//! fixed." A fifth colour, amber over a thick dark-orange casing, marks bodies in a
//! plausibility violation, so a hanging sleeper stands out in a sequence of frames.
//!
//! ```
//! use rapier3d::prelude::*;
//! use rcg_lab::report::frames::{Camera, Classifier, Renderer, Shade};
//! use rcg_scenes as scenes;
//! use rapier_contact_graph::ContactLayer;
//!
//! let mut scene = scenes::sphere_stack(3);
//! let mut layer = ContactLayer::new();
//! layer.step(&mut scene.world);
//! let camera = Camera::new(320, 240)
//!     .with_bounds(Vector::new(-2.0, -1.0, -1.0), Vector::new(2.0, 3.5, 1.0))?;
//! let renderer = Renderer::new(camera);
//! let classes = Classifier::new(&scene.world.bodies, &layer);
//! let frame = renderer.render(&scene.world, &|h| classes.shade(h), "sphere_stack  t = 0.01 s");
//! assert_eq!(frame.count(Shade::Fixed), 1); // the ground
//! // A ball's debug outline is three great circles: in the side view, its silhouette
//! // and a cross through its centre.
//! let top = scene.body("s2").unwrap();
//! let (x, y) = frame.projection().to_pixel(scene.world.bodies[top].translation());
//! assert_eq!(frame.pixel(x as u32, y as u32), Some(Shade::Moving.rgb()));
//! // frame.write_png("target/frames/stack.png")?;
//! # Ok::<(), rapier_contact_graph::Error>(())
//! ```
//!
//! Rapier draws, the lab colours: [`Renderer::render`] runs Rapier's
//! [`DebugRenderPipeline`] into a backend of this module that projects each line
//! through the orthographic [`Camera`], colours a collider's lines by its body's
//! [`Shade`], and paints them with tiny-skia, farthest object first; plotters sets the
//! caption and legend. Deterministic: the same world gives the same bytes. Design and
//! rejected alternatives: `docs/ARCHITECTURE.md` ("Frames"). Files: `lines.rs` (the
//! debug-render backend that keeps the projected lines), `paint.rs` (stroking, legend,
//! text), `camera.rs`, `shade.rs`.
//!
//! # Cost
//! [`Renderer::render`]: Rapier's pass (a few dozen lines per collider), one
//! classifier call per body, a sort of the objects by depth, then O(pixels covered)
//! stroking and O(pixels) for the copy to RGB and the text.

mod camera;
mod lines;
mod paint;
mod shade;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use parry3d::shape::ShapeType;
use plotters::prelude::{BitMapBackend, IntoDrawingArea, RGBColor, Text};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rapier3d::math::Vector;
use rapier3d::prelude::{
    DebugColor, DebugRenderBackend, DebugRenderMode, DebugRenderObject, DebugRenderPipeline,
    DebugRenderStyle, PhysicsWorld, RigidBodyHandle,
};
use tiny_skia::{LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, StrokeDash, Transform};

pub use camera::{Camera, Projection, View};
pub use shade::{violating_bodies, Classifier, Shade, DEFAULT_REST_SPEED};

use super::text;
use lines::{Key, Lines, Pen};
use paint::{legend_swatches, paint, set_text, stroke};

/// Grey of scenery and of colliders without a body.
const SCENERY: [u8; 3] = [0x99, 0x99, 0x99];
const BORDER: [u8; 3] = [0xBB, 0xBB, 0xBB];
const INK: RGBColor = RGBColor(0x22, 0x22, 0x22);
/// Width of a body's lines, in pixels (2: the pixel under a line's middle is fully
/// covered, so it has exactly the shade's colour).
pub const LINE_WIDTH: f32 = 2.0;
/// Width of a violating body's lines, drawn over a casing [`Shade::outline_width`]
/// wider in [`Shade::outline_rgb`].
const VIOLATING_WIDTH: f32 = 3.0;
/// Dashes of a sensor's lines: on, off, in pixels.
const SENSOR_DASH: [f32; 2] = [6.0, 4.0];
/// Subdivisions of Rapier's round outlines (its default, 20, shows as a polygon at
/// the sizes of these frames).
const SUBDIVISIONS: u32 = 48;

/// Layout, in pixels.
const PAD: f64 = 10.0;
const BAND: f64 = 34.0;
const SWATCH_R: f32 = 7.0;
/// Font sizes of the caption and the legend, and the smallest either shrinks to.
const CAPTION_SIZE: f64 = 21.0;
const LEGEND_SIZE: f64 = 19.0;
const MIN_SIZE: f64 = 13.0;

/// Draws frames of a world through a [`Camera`]; holds what stays the same from frame
/// to frame (camera, scenery, legend on or off, what Rapier draws).
#[derive(Clone, Debug, PartialEq)]
pub struct Renderer {
    camera: Camera,
    /// Sorted by raw handle parts.
    scenery: Vec<RigidBodyHandle>,
    legend: bool,
    mode: DebugRenderMode,
    style: DebugRenderStyle,
}

impl Renderer {
    /// A renderer through `camera`, with a legend and no scenery, drawing Rapier's
    /// collider shapes and joints. O(1).
    pub fn new(camera: Camera) -> Self {
        Renderer {
            camera,
            scenery: Vec::new(),
            legend: true,
            mode: DebugRenderMode::COLLIDER_SHAPES | DebugRenderMode::JOINTS,
            style: DebugRenderStyle {
                subdivisions: SUBDIVISIONS,
                ..DebugRenderStyle::default()
            },
        }
    }

    /// The same renderer drawing `bodies` in neutral grey, whatever their shade (e.g.
    /// the ground and walls). Handles the world does not hold are harmless. O(b log b).
    pub fn with_scenery(mut self, bodies: impl IntoIterator<Item = RigidBodyHandle>) -> Self {
        self.scenery.extend(bodies);
        self.scenery.sort_by_key(|h| h.into_raw_parts());
        self.scenery.dedup();
        self
    }

    /// The same renderer with every body that is fixed in Rapier *now* as scenery. Call
    /// it before stepping with the `fixate` speed-up, which makes held bodies fixed
    /// too. O(bodies).
    pub fn with_fixed_as_scenery(self, world: &PhysicsWorld) -> Self {
        let fixed: Vec<RigidBodyHandle> = world
            .bodies
            .iter()
            .filter(|(_, rb)| rb.is_fixed())
            .map(|(h, _)| h)
            .collect();
        self.with_scenery(fixed)
    }

    /// The same renderer with the legend on or off (on by default). O(1).
    pub fn with_legend(mut self, on: bool) -> Self {
        self.legend = on;
        self
    }

    /// The same renderer drawing what `mode` asks of Rapier's debug pipeline (default:
    /// collider shapes and joints; add e.g. [`DebugRenderMode::CONTACTS`]). Collider
    /// shapes take their body's shade, the rest Rapier's colours. O(1).
    pub fn with_mode(mut self, mode: DebugRenderMode) -> Self {
        self.mode = mode;
        self
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    fn is_scenery(&self, h: RigidBodyHandle) -> bool {
        self.scenery
            .binary_search_by_key(&h.into_raw_parts(), |s| s.into_raw_parts())
            .is_ok()
    }

    /// Draws `world`, each body's colliders in the shade `classify` gives it (called
    /// once per body with a collider to draw), with `caption` at the top (e.g.
    /// `"hanging sleeper  t = 1.20 s"`; empty: no caption band) and the legend at the
    /// bottom. Cost in the module docs.
    pub fn render(
        &self,
        world: &PhysicsWorld,
        classify: &dyn Fn(RigidBodyHandle) -> Shade,
        caption: &str,
    ) -> Frame {
        self.render_with(world, classify, caption, |_| {})
    }

    /// [`Self::render`] with a second drawing pass: after Rapier's pipeline has drawn
    /// into the frame's [`DebugRenderBackend`], `overlay` gets the same backend and
    /// may draw more lines (3-D, world coordinates) into it, e.g. the contact graph.
    /// They are painted over the bodies, in the order drawn, in the colours they are
    /// drawn with (Rapier's HSLA [`DebugColor`], alpha honoured); the backend's
    /// [`DebugRenderBackend::filter_object`] accepts everything in this pass.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use rcg_lab::report::frames::{Camera, Renderer, Shade};
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (ground, collider) = world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(2.0, 0.1, 1.0));
    /// let camera = Camera::new(200, 200).with_bounds(Vector::splat(-2.0), Vector::splat(2.0))?;
    /// let frame = Renderer::new(camera).with_legend(false).render_with(&world, &|_| Shade::Fixed, "", |backend| {
    ///     let object = DebugRenderObject::Collider(collider, &world.colliders[collider]);
    ///     // A pure red line (hue 0, saturation 1, lightness 0.5, opaque) up the middle.
    ///     backend.draw_line(object, Vector::new(0.0, 0.5, 0.0), Vector::new(0.0, 1.5, 0.0), [0.0, 1.0, 0.5, 1.0]);
    /// });
    /// let (x, y) = frame.projection().to_pixel(Vector::new(0.0, 1.0, 0.0));
    /// assert_eq!(frame.pixel(x as u32, y as u32), Some([255, 0, 0]));
    /// # let _ = ground;
    /// # Ok::<(), rapier_contact_graph::Error>(())
    /// ```
    // Long: Rapier's pass, the caller's pass, painting and text share the frame's buffers.
    pub fn render_with(
        &self,
        world: &PhysicsWorld,
        classify: &dyn Fn(RigidBodyHandle) -> Shade,
        caption: &str,
        overlay: impl FnOnce(&mut dyn DebugRenderBackend),
    ) -> Frame {
        let (width, height) = self.camera.size();
        let (w, h) = (f64::from(width), f64::from(height));
        let top = if caption.is_empty() { 0.0 } else { BAND };
        let bottom = if self.legend { BAND } else { 0.0 };
        let viewport = [PAD, top + PAD, w - PAD, h - bottom - PAD];
        let fallback = if self.camera.bounds().is_none() {
            world_bounds(world)
        } else {
            None
        };
        let projection = self.camera.projection(fallback, viewport);

        let mut lines = Lines {
            renderer: self,
            classify,
            projection,
            clip: [
                viewport[0] - 2.0,
                viewport[1] - 2.0,
                viewport[2] + 2.0,
                viewport[3] + 2.0,
            ],
            overlay: false,
            shades: BTreeMap::new(),
            batches: Vec::new(),
            broken: BTreeSet::new(),
        };
        let mut pipeline = DebugRenderPipeline::new(self.style, self.mode);
        pipeline.render(
            &mut lines,
            &world.bodies,
            &world.colliders,
            &world.impulse_joints,
            &world.multibody_joints,
            &world.narrow_phase,
            &world.soft_bodies,
        );
        // ---- The second pass (e.g. the contact graph), over the bodies. ----
        lines.overlay = true;
        overlay(&mut lines);

        let mut counts = [0usize; 5];
        for s in lines.shades.values() {
            counts[*s as usize] += 1;
        }
        let skipped = lines
            .broken
            .iter()
            .filter(|(overlay, k)| !overlay && matches!(k, Key::Collider(..)))
            .count();

        // Camera sizes are clamped to 160..=8192, which tiny-skia accepts; were it to
        // refuse, the frame would stay blank rather than panic.
        let Some(mut pixmap) = Pixmap::new(width, height) else {
            return Frame {
                width,
                height,
                rgb: vec![255; width as usize * height as usize * 3],
                projection,
                counts,
                skipped,
            };
        };
        pixmap.fill(tiny_skia::Color::WHITE);
        let [x0, y0, x1, y1] = viewport;
        let border = [
            (x0.round() - 0.5, y0.round() - 0.5),
            (x1.round() + 0.5, y0.round() - 0.5),
            (x1.round() + 0.5, y1.round() + 0.5),
            (x0.round() - 0.5, y1.round() + 0.5),
            (x0.round() - 0.5, y0.round() - 0.5),
        ];
        let segments: Vec<[(f64, f64); 2]> = border.windows(2).map(|s| [s[0], s[1]]).collect();
        stroke(
            &mut pixmap,
            &segments,
            Pen::Colour([BORDER[0], BORDER[1], BORDER[2], 255]),
            1.0,
        );
        paint(&mut pixmap, lines.batches, &lines.broken);
        let legend_items = if self.legend {
            legend_swatches(&mut pixmap, &counts, w, h - BAND)
        } else {
            Vec::new()
        };

        // tiny-skia's pixels are premultiplied RGBA; over the opaque white background
        // every pixel is opaque, so the colour channels are the RGB values.
        let mut rgb: Vec<u8> = pixmap
            .data()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        set_text(&mut rgb, (width, height), caption, &legend_items);
        Frame {
            width,
            height,
            rgb,
            projection,
            counts,
            skipped,
        }
    }
}

/// The union of the enabled colliders' bounding boxes, leaving out half-spaces and
/// non-finite boxes; `None` when nothing is left. O(colliders).
fn world_bounds(world: &PhysicsWorld) -> Option<(Vector, Vector)> {
    let mut out: Option<(Vector, Vector)> = None;
    for (_, co) in world.colliders.iter() {
        if !co.is_enabled() || co.shape().shape_type() == ShapeType::HalfSpace {
            continue;
        }
        let aabb = co.compute_aabb();
        if !(aabb.mins.is_finite() && aabb.maxs.is_finite()) {
            continue;
        }
        out = Some(match out {
            None => (aabb.mins, aabb.maxs),
            Some((lo, hi)) => (lo.min(aabb.mins), hi.max(aabb.maxs)),
        });
    }
    out
}

/// A rendered frame: RGB pixels, the projection used and what was drawn.
#[derive(Clone, Debug)]
pub struct Frame {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
    projection: Projection,
    counts: [usize; 5],
    skipped: usize,
}

impl Frame {
    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, row-major from the top-left corner, 3 bytes (R, G, B) per pixel.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// The colour of pixel `(x, y)`, `None` outside the frame. O(1).
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 3;
        Some([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]])
    }

    /// The projection the frame was drawn with: where a world point landed.
    pub fn projection(&self) -> &Projection {
        &self.projection
    }

    /// How many bodies were drawn in `shade` (scenery not counted).
    pub fn count(&self, shade: Shade) -> usize {
        self.counts[shade as usize]
    }

    /// Colliders left out because a line Rapier drew for them was not finite (e.g. a
    /// NaN pose). (A non-finite line of the overlay pass leaves out that object's
    /// overlay lines, uncounted.)
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// The frame as the bytes of a PNG file (8-bit RGB, zlib-compressed by the `png`
    /// crate). O(pixels).
    pub fn png(&self) -> Vec<u8> {
        super::encode_png(self.width, self.height, &self.rgb)
    }

    /// Writes [`Self::png`] to `path`; the directory must exist. O(pixels).
    pub fn write_png(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        std::fs::write(path, self.png())
    }
}

#[cfg(test)]
mod tests;
