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
//! # Design
//! - **Rapier draws, the lab colours.** [`Renderer::render`] runs Rapier's
//!   [`DebugRenderPipeline`] into a small [`DebugRenderBackend`] of this module, which
//!   projects each 3-D line through the [`Camera`] and keeps it, grouped by the
//!   [`DebugRenderObject`] it belongs to. A frame therefore shows exactly the geometry
//!   Rapier's debug render shows (a ball is three great circles, a cuboid its twelve
//!   edges, a mesh its triangles, a half-space two long lines), and only the colour is
//!   the lab's: the backend's choice per object, as the trait intends. A collider's
//!   lines take its body's [`Shade`]; scenery ([`Renderer::with_scenery`]) and
//!   colliders without a body are grey; sensors are dashed; anything else Rapier draws
//!   (joints by default; rigid-body axes, contacts, AABBs with
//!   [`Renderer::with_mode`]) keeps Rapier's colour. Rejected: keeping the
//!   hand-written silhouettes and filled shapes of the first version. They were a
//!   second description of every shape to keep in step with parry, and a filled disc
//!   hides what the debug lines show (rotation, the cross of a ball, mesh edges).
//! - **A second pass into the same backend.** [`Renderer::render_with`] hands the
//!   backend, after Rapier's pass, to a caller's closure as `&mut dyn
//!   DebugRenderBackend`: whatever it draws (e.g. the plugin's drawing of the contact
//!   graph: edges, groups, states) lands on top of the bodies in the colours it chose.
//! - **tiny-skia paints.** The kept lines are stroked with anti-aliasing by
//!   [`tiny_skia`], one path per object so that a body's own lines do not darken where
//!   they cross; objects are painted farthest first (by their farthest point along the
//!   viewing direction), so a nearer body's lines lie on top. Lines are clipped to the
//!   picture in `f64` first: a half-space's 10 km lines stay small numbers.
//! - **Orthographic camera** ([`Camera`], [`View`]): a ball of radius r is a circle of
//!   radius r wherever it is, so frames compare. The side view (x right, y up, looking
//!   along −z) is the default, as in the paper's figures; a tilted view turns and
//!   pitches it. The camera fits given world bounds (use them for a sequence: the scale
//!   stays put) or, without them, the world's colliders at each render.
//! - **Colours from the caller.** The renderer asks a `&dyn Fn(RigidBodyHandle) ->
//!   Shade` once per body; [`Classifier`] is the paper's classification (fixated →
//!   fixed, sleepy, absolute rest, moving, violations from the monitor).
//! - **Caption and legend with real text.** tiny-skia has no text: after the lines,
//!   the pixels go to plotters' bitmap back end, which sets the caption (the caller's
//!   text: scene name and time) in the top band and, in the bottom band, the legend
//!   labels beside swatches stroked like the bodies (name and body count per shade), in
//!   the charts' DejaVu Sans; what does not fit shrinks, then is cut with "...".
//! - **Deterministic and forgiving.** No clocks, threads or hash order in what is
//!   drawn: the same world gives the same bytes. A collider with a non-finite line is
//!   left out whole and counted ([`Frame::skipped`]); sizes are clamped; nothing here
//!   panics on data.
//!
//! # Cost
//! [`Renderer::render`]: Rapier's pass (a few dozen lines per collider: 3 × 48 for a
//! ball), one classifier call per body, a sort of the objects by depth, then
//! O(pixels covered) stroking and O(pixels) for the copy to RGB and the text. Measured
//! with the `frames` subcommand (4 bodies, 800 × 480, release build, 2 shared cores):
//! 1–2 ms to render a frame and 3 ms to encode and write its PNG, of about 21 KB (the
//! hand-written renderer before: 6 ms, and 1.15 MB stored uncompressed).

mod camera;
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

/// What a run of lines belongs to: Rapier's object, by kind and handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Key {
    RigidBody(u32, u32),
    Collider(u32, u32),
    ColliderAabb(u32, u32),
    ImpulseJoint(u32, u32),
    MultibodyJoint(u32, u32),
    ContactPair((u32, u32), (u32, u32)),
    SoftBody(u32, u32),
}

impl Key {
    fn of(object: &DebugRenderObject) -> Key {
        match object {
            DebugRenderObject::RigidBody(h, _) => {
                let (i, g) = h.into_raw_parts();
                Key::RigidBody(i, g)
            }
            DebugRenderObject::Collider(h, _) => {
                let (i, g) = h.into_raw_parts();
                Key::Collider(i, g)
            }
            DebugRenderObject::ColliderAabb(h, _, _) => {
                let (i, g) = h.into_raw_parts();
                Key::ColliderAabb(i, g)
            }
            DebugRenderObject::ImpulseJoint(h, _) => {
                let (i, g) = h.into_raw_parts();
                Key::ImpulseJoint(i, g)
            }
            DebugRenderObject::MultibodyJoint(h, _, _) => {
                let (i, g) = h.into_raw_parts();
                Key::MultibodyJoint(i, g)
            }
            DebugRenderObject::ContactPair(pair, _, _) => Key::ContactPair(
                pair.collider1.into_raw_parts(),
                pair.collider2.into_raw_parts(),
            ),
            DebugRenderObject::SoftBody(h, _) => {
                let (i, g) = h.into_raw_parts();
                Key::SoftBody(i, g)
            }
        }
    }
}

/// How a run of lines is stroked.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pen {
    /// A body's collider in its shade; dashed for a sensor.
    Shade { shade: Shade, sensor: bool },
    /// Scenery or a collider without a body; dashed for a sensor.
    Scenery { sensor: bool },
    /// Straight RGBA: Rapier's colour (joints, contacts, ...) or an overlay's.
    Colour([u8; 4]),
}

/// Lines of one object with one pen, in pixels, and the depth of the object's
/// farthest point.
struct Batch {
    key: Key,
    pen: Pen,
    overlay: bool,
    depth: f64,
    segments: Vec<[(f64, f64); 2]>,
}

/// The frame's [`DebugRenderBackend`]: projects Rapier's lines through the camera,
/// chooses their colour and keeps them for painting.
struct Lines<'a> {
    renderer: &'a Renderer,
    classify: &'a dyn Fn(RigidBodyHandle) -> Shade,
    projection: Projection,
    /// Lines are clipped to this rectangle (the viewport and a margin), in pixels.
    clip: [f64; 4],
    /// True in the second pass: everything drawn, in its own colours.
    overlay: bool,
    /// Shades, one classifier call per body (ordered by handle).
    shades: BTreeMap<(u32, u32), Shade>,
    batches: Vec<Batch>,
    /// Objects with a non-finite line, and whether in the overlay pass: their lines of
    /// that pass are left out.
    broken: BTreeSet<(bool, Key)>,
}

impl Lines<'_> {
    fn pen(&mut self, object: &DebugRenderObject, color: DebugColor) -> Pen {
        if self.overlay {
            return Pen::Colour(hsla_to_rgba(color));
        }
        match object {
            DebugRenderObject::Collider(_, co) => {
                let sensor = co.is_sensor();
                match co.parent() {
                    Some(b) if !self.renderer.is_scenery(b) => {
                        let classify = self.classify;
                        let shade = *self
                            .shades
                            .entry(b.into_raw_parts())
                            .or_insert_with(|| classify(b));
                        Pen::Shade { shade, sensor }
                    }
                    _ => Pen::Scenery { sensor },
                }
            }
            _ => Pen::Colour(hsla_to_rgba(color)),
        }
    }
}

impl DebugRenderBackend for Lines<'_> {
    fn filter_object(&self, object: DebugRenderObject) -> bool {
        // Rapier also draws disabled colliders (dimmed); a frame leaves them out.
        self.overlay
            || match object {
                DebugRenderObject::Collider(_, co) | DebugRenderObject::ColliderAabb(_, co, _) => {
                    co.is_enabled()
                }
                _ => true,
            }
    }

    fn draw_line(&mut self, object: DebugRenderObject, a: Vector, b: Vector, color: DebugColor) {
        let key = Key::of(&object);
        let pen = self.pen(&object, color);
        let (a, b) = (to64(a), to64(b));
        let (pa, pb) = (self.projection.project64(a), self.projection.project64(b));
        let [_, _, forward] = self.projection.basis();
        let depth = camera::dot(a, forward).max(camera::dot(b, forward));
        if ![pa.0, pa.1, pb.0, pb.1, depth]
            .iter()
            .all(|v| v.is_finite())
        {
            self.broken.insert((self.overlay, key));
            return;
        }
        let same = self
            .batches
            .last()
            .is_some_and(|l| l.key == key && l.pen == pen && l.overlay == self.overlay);
        if !same {
            self.batches.push(Batch {
                key,
                pen,
                overlay: self.overlay,
                depth,
                segments: Vec::new(),
            });
        }
        let Some(batch) = self.batches.last_mut() else {
            return;
        };
        batch.depth = batch.depth.max(depth);
        if let Some(segment) = clip(pa, pb, self.clip) {
            batch.segments.push(segment);
        }
    }
}

fn to64(v: Vector) -> [f64; 3] {
    v.to_array().map(f64::from)
}

/// Rapier's HSLA debug colour (hue 0..=360, saturation, lightness and alpha 0..=1) as
/// straight RGBA bytes; out-of-range parts are clamped, NaN reads as 0.
fn hsla_to_rgba([h, s, l, a]: DebugColor) -> [u8; 4] {
    let unit = |v: f32| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let (h, s, l, a) = (
        if h.is_finite() {
            h.rem_euclid(360.0)
        } else {
            0.0
        },
        unit(s),
        unit(l),
        unit(a),
    );
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let x = c * (1.0 - ((h / 60.0).rem_euclid(2.0) - 1.0).abs());
    let m = l - c / 2.0;
    let (r, g, b) = match (h / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let byte = |v: f32| ((v + m).clamp(0.0, 1.0) * 255.0).round() as u8;
    [byte(r), byte(g), byte(b), (a * 255.0).round() as u8]
}

/// The part of segment `a`–`b` inside the rectangle `[x0, y0, x1, y1]`
/// (Liang–Barsky), `None` if it misses it.
fn clip(a: (f64, f64), b: (f64, f64), [x0, y0, x1, y1]: [f64; 4]) -> Option<[(f64, f64); 2]> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then_some([
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ])
}

/// Paints the batches: Rapier's pass farthest object first (stable: ties keep
/// Rapier's order), then the overlay in its order; an object with a broken line is
/// left out of the pass it was broken in.
fn paint(pixmap: &mut Pixmap, mut batches: Vec<Batch>, broken: &BTreeSet<(bool, Key)>) {
    batches.retain(|b| !broken.contains(&(b.overlay, b.key)));
    batches.sort_by(|a, b| a.overlay.cmp(&b.overlay).then(b.depth.total_cmp(&a.depth)));
    for batch in &batches {
        stroke(pixmap, &batch.segments, batch.pen, 1.0);
    }
}

/// Strokes `segments` as one path with `pen` (line widths scaled by `scale`).
fn stroke(pixmap: &mut Pixmap, segments: &[[(f64, f64); 2]], pen: Pen, scale: f32) {
    // Segments that continue the previous one extend its contour (Rapier's outlines
    // come as chains of short segments), so that joins are round and dashes run along
    // the outline instead of restarting at every segment.
    let mut pb = PathBuilder::new();
    let mut last: Option<(f64, f64)> = None;
    for [a, b] in segments {
        if last != Some(*a) {
            pb.move_to(a.0 as f32, a.1 as f32);
        }
        pb.line_to(b.0 as f32, b.1 as f32);
        last = Some(*b);
    }
    let Some(path) = pb.finish() else {
        return;
    };
    let stroke_path = |pixmap: &mut Pixmap, rgba: [u8; 4], width: f32, dashed: bool| {
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
        paint.anti_alias = true;
        let stroke = Stroke {
            width: width * scale,
            line_cap: if dashed {
                LineCap::Butt
            } else {
                LineCap::Round
            },
            line_join: LineJoin::Round,
            dash: if dashed {
                StrokeDash::new(SENSOR_DASH.to_vec(), 0.0)
            } else {
                None
            },
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    };
    let opaque = |[r, g, b]: [u8; 3]| [r, g, b, 255];
    match pen {
        Pen::Shade {
            shade: Shade::Violating,
            sensor,
        } => {
            let casing = VIOLATING_WIDTH + Shade::Violating.outline_width() as f32;
            stroke_path(
                pixmap,
                opaque(Shade::Violating.outline_rgb()),
                casing,
                sensor,
            );
            stroke_path(
                pixmap,
                opaque(Shade::Violating.rgb()),
                VIOLATING_WIDTH,
                sensor,
            );
        }
        Pen::Shade { shade, sensor } => {
            stroke_path(pixmap, opaque(shade.rgb()), LINE_WIDTH, sensor)
        }
        Pen::Scenery { sensor } => stroke_path(pixmap, opaque(SCENERY), LINE_WIDTH, sensor),
        Pen::Colour(rgba) => stroke_path(pixmap, rgba, LINE_WIDTH, false),
    }
}

/// One legend entry's text: its label, where it starts (left, vertical middle) and
/// its size.
struct LegendText {
    label: String,
    at: (f64, f64),
    size: f64,
}

/// The legend in the band starting at `top`: per shade a swatch (a circle stroked
/// like that shade's bodies), then the name and the count, centred; at the legend
/// size if it fits, else smaller, else without counts. Strokes the swatches and
/// returns the texts, which [`set_text`] sets.
fn legend_swatches(
    pixmap: &mut Pixmap,
    counts: &[usize; 5],
    width: f64,
    top: f64,
) -> Vec<LegendText> {
    let gap = 18.0;
    let swatch = 2.0 * f64::from(SWATCH_R) + 8.0;
    let with_counts: Vec<String> = Shade::ALL
        .iter()
        .map(|s| format!("{} {}", s.name(), counts[*s as usize]))
        .collect();
    let plain: Vec<String> = Shade::ALL.iter().map(|s| s.name().to_string()).collect();
    let total = |labels: &[String], size: f64| -> f64 {
        labels
            .iter()
            .map(|l| swatch + text::width(l, size))
            .sum::<f64>()
            + gap * (labels.len() - 1) as f64
    };
    let room = width - 2.0 * PAD;
    let (labels, size) = [
        (&with_counts, LEGEND_SIZE),
        (&with_counts, MIN_SIZE),
        (&plain, MIN_SIZE),
    ]
    .into_iter()
    .find(|(l, s)| total(l, *s) <= room)
    .unwrap_or((&plain, MIN_SIZE));
    let mut x = ((width - total(labels, size)) / 2.0).max(PAD).round();
    let mid = top + BAND / 2.0;
    let mut out = Vec::new();
    for (shade, label) in Shade::ALL.iter().zip(labels) {
        let cx = x + f64::from(SWATCH_R);
        // The circle as short segments, stroked by the bodies' own pen.
        let r = f64::from(SWATCH_R);
        let at = |k: usize| {
            let a = k as f64 * std::f64::consts::TAU / 32.0;
            (cx + r * a.cos(), mid + r * a.sin())
        };
        let segments: Vec<[(f64, f64); 2]> = (0..32).map(|k| [at(k), at(k + 1)]).collect();
        let pen = Pen::Shade {
            shade: *shade,
            sensor: false,
        };
        stroke(pixmap, &segments, pen, 1.0);
        x += swatch;
        out.push(LegendText {
            label: label.clone(),
            at: (x, mid),
            size,
        });
        x += text::width(label, size) + gap;
    }
    out
}

/// Sets the caption (top band, shrunk then cut to fit) and the legend's texts on the
/// RGB pixels with plotters' bitmap back end. Text that cannot be drawn (no font) is
/// left out.
fn set_text(rgb: &mut [u8], (width, height): (u32, u32), caption: &str, legend: &[LegendText]) {
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    if !caption.is_empty() {
        let (caption, size) = fit_caption(caption, f64::from(width) - 2.0 * PAD);
        let style = text::font(size)
            .color(&INK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let _ = root.draw(&Text::new(
            caption,
            (PAD as i32, (BAND / 2.0) as i32),
            style,
        ));
    }
    for item in legend {
        let style = text::font(item.size)
            .color(&INK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let at = (item.at.0.round() as i32, item.at.1.round() as i32);
        let _ = root.draw(&Text::new(item.label.as_str(), at, style));
    }
    let _ = root.present();
}

/// The caption as set in `room` pixels: at the caption size if it fits, else smaller
/// down to the minimum, else cut with "...".
fn fit_caption(caption: &str, room: f64) -> (String, f64) {
    text::fit(&text::clean(caption), CAPTION_SIZE, MIN_SIZE, room)
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
