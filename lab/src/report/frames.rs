//! Headless pictures of a scene, coloured as the paper's Fig. 17: PNG frames of a
//! [`PhysicsWorld`] with every body in the colour of its state.
//!
//! The paper's caption: "Purple means sleepy, red moving, blue absolute rest, green
//! fixed." A fifth colour, amber with a thick dark-orange outline, marks bodies in a
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
//! let top = scene.body("s2").unwrap();
//! let (x, y) = frame.projection().to_pixel(scene.world.bodies[top].translation());
//! assert_eq!(frame.pixel(x as u32, y as u32), Some(Shade::Moving.rgb()));
//! // frame.write_png("target/frames/stack.png")?;
//! # Ok::<(), rapier_contact_graph::Error>(())
//! ```
//!
//! # Design
//! - **The chart's rasteriser, reused.** A frame is laid out as the same display list
//!   the charts use (discs, polygons, rectangles, bitmap text; see the parent module)
//!   and painted by the same signed-distance rasteriser into an RGB buffer that the
//!   same PNG encoder writes. One antialiasing rule for everything, no dependency, and
//!   the frame can be had as SVG too ([`Frame::svg`]). Rejected: a second rasteriser
//!   with a z-buffer. Antialiased edges do not mix with a z-buffer, and exact depth per
//!   pixel would need each shape's surface, not its outline.
//! - **Orthographic camera** ([`Camera`], [`View`]): a disc of radius r stays r
//!   wherever the ball is, so frames compare. The side view (x right, y up, looking
//!   along −z) is the default, as in the paper's figures; a tilted view turns and
//!   pitches it. The camera fits given world bounds (use them for a sequence: the scale
//!   stays put) or, without them, the world's colliders at each render.
//! - **Outlines, by shape.** A ball is an exact disc. A cuboid is the convex hull of its
//!   8 projected corners, its exact silhouette. Any other convex shape (capsule,
//!   cylinder, cone, convex polyhedron, round shapes, triangle, segment) is the polygon
//!   of its support points in 48 directions of the picture plane: the silhouette of a
//!   convex body under orthographic projection is the projection of those support
//!   points, so this is exact up to the 48-gon. A compound draws its parts. Non-convex
//!   shapes (triangle mesh, height field, polyline, voxels) are drawn as the convex
//!   hull of their projected bounding box: an approximation, documented here and fine
//!   for the paper's scenes of spheres and boxes; drawing each triangle was rejected
//!   (a terrain of 10⁵ triangles per frame, for a figure). Half-spaces have no
//!   extent and are not drawn; neither are disabled colliders. Sensors are drawn as an
//!   outline without fill.
//! - **Painter's order by the farthest point.** Pieces are painted farthest first,
//!   each at the depth of its farthest point along the viewing direction (ties in
//!   collider order). Rejected: the centre's depth, which puts a large ground slab in
//!   front of the bodies standing on its far half in a tilted view. The farthest point
//!   gets that case right; two large shapes crossing each other can still come out in
//!   the wrong order, which no per-shape order avoids.
//! - **Colours from the caller.** The renderer asks a `&dyn Fn(RigidBodyHandle) ->
//!   Shade` once per body; [`Classifier`] is the paper's classification (fixated →
//!   fixed, sleepy, absolute rest, moving, violations from the monitor). Bodies listed
//!   as scenery ([`Renderer::with_scenery`]) and colliders without a body are drawn in
//!   a neutral grey instead: a ground slab painted "fixed" green would take most of the
//!   picture, and the green is more useful for what the `fixate` speed-up froze.
//! - **Legend and caption.** A caption line at the top (the caller's text: scene name
//!   and time) and a legend at the bottom with the five colours, their names and how
//!   many bodies are in each, set in the built-in font (scale 2, or 1 when it does not
//!   fit).
//! - **Deterministic and forgiving.** No clocks, threads or hash order: the same world
//!   gives the same bytes. Colliders with non-finite poses or outlines are left out and
//!   counted ([`Frame::skipped`]); sizes are clamped; nothing here panics on data.
//!
//! # Cost
//! [`Renderer::render`]: O(c log c) for c drawn pieces (about one per collider), 48
//! support-point queries per non-box convex shape, one classifier call per body, plus
//! O(pixels covered) painting. Measured on the `frames` example (8 bodies, release
//! build, 2 shared cores): 7–11 ms to render an 800 × 480 side view and 19 ms a tilted
//! one (the slab's faces cover more pixels); the PNG is 1.15 MB, since the encoder
//! stores without compression, and takes 6–8 ms to write.

mod camera;
mod shade;

use std::collections::BTreeMap;
use std::path::Path;

use parry3d::shape::{Shape, ShapeType};
use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle};

pub use camera::{Camera, Projection, View};
pub use shade::{violating_bodies, Classifier, Shade, DEFAULT_REST_SPEED};

use super::chart::{Color, Item, Scene, Shape as Marker, Stroke, WHITE};
use super::{font, png, raster, svg};

/// Directions sampled for the silhouette of a convex shape.
const SILHOUETTE_DIRECTIONS: usize = 48;
/// Compounds nested deeper than this are not drawn (parry does not nest them; a guard).
const MAX_COMPOUND_DEPTH: u32 = 4;

const INK: Color = Color::hex(0x222222);
const BORDER: Color = Color::hex(0xBBBBBB);
const SCENERY_FILL: Color = Color::hex(0xC9C9C9);
const SCENERY_OUTLINE: Color = Color::hex(0x7A7A7A);

/// Layout, in pixels.
const PAD: f64 = 10.0;
const BAND: f64 = 34.0;
const SWATCH_R: f64 = 7.0;

/// Draws frames of a world through a [`Camera`]; holds what stays the same from frame
/// to frame (camera, scenery, legend on or off).
#[derive(Clone, Debug, PartialEq)]
pub struct Renderer {
    camera: Camera,
    /// Sorted by raw handle parts.
    scenery: Vec<RigidBodyHandle>,
    legend: bool,
}

impl Renderer {
    /// A renderer through `camera`, with a legend and no scenery. O(1).
    pub fn new(camera: Camera) -> Self {
        Renderer {
            camera,
            scenery: Vec::new(),
            legend: true,
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

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    fn is_scenery(&self, h: RigidBodyHandle) -> bool {
        self.scenery
            .binary_search_by_key(&h.into_raw_parts(), |s| s.into_raw_parts())
            .is_ok()
    }

    /// Draws `world`, each body in the shade `classify` gives it (called once per
    /// body with a collider to draw), with `caption` at the top (e.g. `"hanging
    /// sleeper  t = 1.20 s"`; empty: no caption band) and the legend at the bottom.
    /// Cost in the module docs.
    pub fn render(
        &self,
        world: &PhysicsWorld,
        classify: &dyn Fn(RigidBodyHandle) -> Shade,
        caption: &str,
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

        // Shades, one call per body, in handle order (deterministic).
        let mut shades: BTreeMap<(u32, u32), Shade> = BTreeMap::new();
        let mut pieces: Vec<Piece> = Vec::new();
        let mut skipped = 0;
        for (_, co) in world.colliders.iter() {
            if !co.is_enabled() {
                continue;
            }
            let style = match co.parent() {
                Some(b) if !self.is_scenery(b) => Some(
                    *shades
                        .entry(b.into_raw_parts())
                        .or_insert_with(|| classify(b)),
                ),
                _ => None,
            };
            let before = pieces.len();
            let ok = outline(
                co.shape(),
                co.position(),
                &projection,
                0,
                &mut pieces,
                style,
                co.is_sensor(),
            );
            if !ok {
                pieces.truncate(before);
                skipped += 1;
            }
        }
        // Farthest first; the sort is stable, so ties keep collider order.
        pieces.sort_by(|a, b| b.depth.total_cmp(&a.depth));

        let mut counts = [0usize; 5];
        for s in shades.values() {
            counts[*s as usize] += 1;
        }

        let mut items = Vec::with_capacity(pieces.len() + 16);
        let [x0, y0, x1, y1] = viewport;
        items.push(Item::Rect {
            x: x0.round() - 0.5,
            y: y0.round() - 0.5,
            w: (x1 - x0).round() + 1.0,
            h: (y1 - y0).round() + 1.0,
            fill: None,
            opacity: 1.0,
            stroke: Some(Stroke {
                color: BORDER,
                width: 1.0,
            }),
        });
        items.extend(pieces.into_iter().map(Piece::into_item));
        if !caption.is_empty() {
            items.extend(text_line(caption, PAD, (BAND - 14.0) / 2.0, w - 2.0 * PAD));
        }
        if self.legend {
            legend(&mut items, &counts, w, h - BAND);
        }
        let scene = Scene {
            width,
            height,
            background: WHITE,
            items,
        };
        let canvas = raster::render(&scene);
        Frame {
            width,
            height,
            rgb: canvas.rgb,
            projection,
            counts,
            skipped,
            scene,
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

/// One painted piece: a disc or a convex polygon in pixels, with its style and depth.
struct Piece {
    geometry: Geometry,
    /// `None`: scenery grey.
    style: Option<Shade>,
    sensor: bool,
    /// Depth of the farthest point.
    depth: f64,
}

enum Geometry {
    Disc {
        centre: (f64, f64),
        r: f64,
    },
    Polygon(Vec<(f64, f64)>),
    /// A box: its silhouette and its faces turned to the viewer, each with a tint
    /// (see [`face_tint`]).
    Faces {
        hull: Vec<(f64, f64)>,
        faces: Vec<(Vec<(f64, f64)>, f64)>,
    },
}

impl Piece {
    fn into_item(self) -> Item {
        let (fill, outline, width) = match self.style {
            Some(s) => (
                rgb(s.rgb()),
                rgb(s.outline_rgb()),
                if self.sensor { 1.5 } else { s.outline_width() },
            ),
            None => (SCENERY_FILL, SCENERY_OUTLINE, 1.0),
        };
        let fill = (!self.sensor).then_some(fill);
        // Sensors are outlined in the fill colour, which reads better than the dark one.
        let color = if self.sensor {
            self.style.map_or(SCENERY_OUTLINE, |s| rgb(s.rgb()))
        } else {
            outline
        };
        let stroke = Some(Stroke { color, width });
        match self.geometry {
            Geometry::Disc { centre, r } => Item::Marker {
                shape: Marker::Circle,
                x: centre.0,
                y: centre.1,
                r,
                fill,
                stroke,
            },
            Geometry::Polygon(points) => Item::Polygon {
                points,
                fill,
                stroke,
            },
            Geometry::Faces { hull, faces } => {
                let mut items: Vec<Item> = faces
                    .into_iter()
                    .map(|(points, tint)| Item::Polygon {
                        points,
                        fill: fill.map(|c| tinted(c, tint)),
                        stroke: Some(Stroke {
                            color: outline,
                            width: 1.0,
                        }),
                    })
                    .collect();
                items.push(Item::Polygon {
                    points: hull,
                    fill: None,
                    stroke,
                });
                Item::Group {
                    class: "body",
                    tooltip: None,
                    items,
                }
            }
        }
    }
}

/// `c` lightened towards white (`tint > 0`) or darkened towards black (`tint < 0`) by
/// `|tint|` (clamped to 1).
fn tinted(c: Color, tint: f64) -> Color {
    let t = tint.clamp(-1.0, 1.0);
    let target = if t > 0.0 { 255.0 } else { 0.0 };
    let mix = |v: u8| (f64::from(v) + (target - f64::from(v)) * t.abs()).round() as u8;
    Color {
        r: mix(c.r),
        g: mix(c.g),
        b: mix(c.b),
    }
}

/// The tint of a face with outward unit normal `n`: lighter the more it faces up
/// (world +y), darker the more it turns away from the viewer. A face looking straight
/// at the viewer with a horizontal normal gets 0, the plain colour, so the side view
/// shows boxes in exactly their shade's colour.
fn face_tint(n: [f64; 3], forward: [f64; 3]) -> f64 {
    let facing = -camera::dot(n, forward);
    0.3 * n[1] - 0.25 * (1.0 - facing)
}

fn rgb([r, g, b]: [u8; 3]) -> Color {
    Color { r, g, b }
}

fn to64(v: Vector) -> [f64; 3] {
    v.to_array().map(f64::from)
}

/// Appends the pieces of `shape` at `pose`; false if some geometry was not finite or
/// the shape cannot be drawn (half-space, compound nested too deep).
fn outline(
    shape: &dyn Shape,
    pose: &Pose,
    proj: &Projection,
    nesting: u32,
    out: &mut Vec<Piece>,
    style: Option<Shade>,
    sensor: bool,
) -> bool {
    let [right, up, forward] = proj.basis();
    let piece = |geometry: Geometry, depth: f64| Piece {
        geometry,
        style,
        sensor,
        depth,
    };
    if let Some(ball) = shape.as_ball() {
        let c = to64(pose.translation);
        let r = f64::from(ball.radius);
        let centre = proj.project64(c);
        let depth = camera::dot(c, forward) + r;
        let r_px = r * proj.scale();
        if !(centre.0.is_finite() && centre.1.is_finite() && r_px.is_finite() && depth.is_finite())
        {
            return false;
        }
        out.push(piece(Geometry::Disc { centre, r: r_px }, depth));
        return true;
    }
    if let Some(compound) = shape.as_compound() {
        if nesting >= MAX_COMPOUND_DEPTH {
            return false;
        }
        return compound.shapes().iter().all(|(p, s)| {
            outline(
                s.as_ref(),
                &(*pose * *p),
                proj,
                nesting + 1,
                out,
                style,
                sensor,
            )
        });
    }
    if shape.shape_type() == ShapeType::HalfSpace {
        return false;
    }
    let mut faces = Vec::new();
    let points: Vec<[f64; 3]> = if let Some(cuboid) = shape.as_cuboid() {
        let corners = box_corners(-cuboid.half_extents, cuboid.half_extents, pose);
        // Corner k has bit 0 = +x, bit 1 = +y, bit 2 = +z; a face fixes one bit.
        for axis in 0..3 {
            for side in [0usize, 1] {
                let mut local = Vector::ZERO;
                local[axis] = if side == 1 { 1.0 } else { -1.0 };
                let n = to64(pose.rotation * local);
                if camera::dot(n, forward) >= -1e-9 {
                    continue; // edge-on or turned away
                }
                let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                let quad = [(0, 0), (1, 0), (1, 1), (0, 1)]
                    .map(|(i, j)| side << axis | i << a | j << b)
                    .map(|k| proj.project64(corners[k]));
                faces.push((quad.to_vec(), face_tint(n, forward)));
            }
        }
        corners
    } else if let Some(support) = shape.as_support_map() {
        let inverse = pose.rotation.inverse();
        let mut pts: Vec<[f64; 3]> = (0..SILHOUETTE_DIRECTIONS)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / SILHOUETTE_DIRECTIONS as f64;
                let (s, c) = a.sin_cos();
                let d = [0, 1, 2].map(|i| right[i] * c + up[i] * s);
                let local = inverse * Vector::new(d[0] as f32, d[1] as f32, d[2] as f32);
                to64(pose.transform_point(support.local_support_point(local)))
            })
            .collect();
        // The farthest point, for the depth.
        let f = Vector::new(forward[0] as f32, forward[1] as f32, forward[2] as f32);
        pts.push(to64(
            pose.transform_point(support.local_support_point(inverse * f)),
        ));
        pts
    } else {
        let aabb = shape.compute_local_aabb();
        box_corners(aabb.mins, aabb.maxs, pose)
    };
    if points.iter().flatten().any(|x| !x.is_finite()) {
        return false;
    }
    let depth = points
        .iter()
        .map(|&p| camera::dot(p, forward))
        .fold(f64::NEG_INFINITY, f64::max);
    let projected: Vec<(f64, f64)> = points.iter().map(|&p| proj.project64(p)).collect();
    if !depth.is_finite()
        || projected
            .iter()
            .any(|p| !(p.0.is_finite() && p.1.is_finite()))
    {
        return false;
    }
    let hull = convex_hull(projected);
    let geometry = if faces.is_empty() || sensor {
        Geometry::Polygon(hull)
    } else {
        Geometry::Faces { hull, faces }
    };
    out.push(piece(geometry, depth));
    true
}

/// The 8 corners of the box `lo..hi` (local) placed by `pose`, in world coordinates.
fn box_corners(lo: Vector, hi: Vector, pose: &Pose) -> Vec<[f64; 3]> {
    (0..8)
        .map(|k| {
            let c = Vector::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            to64(pose.transform_point(c))
        })
        .collect()
}

/// The convex hull of finite points (Andrew's monotone chain), counter-clockwise in
/// pixel coordinates, without collinear points. Fewer than 3 distinct points come back
/// as they are (drawn as an outline only, since they enclose nothing).
fn convex_hull(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64)> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64)>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Text items for one line starting at `(x, y)` within `max_width` pixels: scale 2,
/// else 1, else cut with "...".
fn text_line(text: &str, x: f64, y: f64, max_width: f64) -> Option<Item> {
    let fits = |t: &str, s: u32| f64::from(font::text_width(t) * s) <= max_width;
    let (text, scale) = if fits(text, 2) {
        (text.to_string(), 2)
    } else if fits(text, 1) {
        (text.to_string(), 1)
    } else {
        let mut t: String = text.chars().collect();
        while !t.is_empty() && !fits(&format!("{t}..."), 1) {
            t.pop();
        }
        (format!("{t}..."), 1)
    };
    let y = if scale == 1 { y + 3.0 } else { y };
    Some(Item::Text {
        x,
        y,
        text,
        scale,
        color: INK,
        vertical: false,
    })
}

/// The legend in the band starting at `top`: a swatch, the name and the count of each
/// shade, centred; scale 2 if it fits, else 1, else without counts.
fn legend(items: &mut Vec<Item>, counts: &[usize; 5], width: f64, top: f64) {
    let gap = 18.0;
    let swatch = 2.0 * SWATCH_R + 6.0;
    let with_counts: Vec<String> = Shade::ALL
        .iter()
        .map(|s| format!("{} {}", s.name(), counts[*s as usize]))
        .collect();
    let plain: Vec<String> = Shade::ALL.iter().map(|s| s.name().to_string()).collect();
    let total = |labels: &[String], scale: u32| -> f64 {
        labels
            .iter()
            .map(|l| swatch + f64::from(font::text_width(l) * scale))
            .sum::<f64>()
            + gap * (labels.len() - 1) as f64
    };
    let room = width - 2.0 * PAD;
    let (labels, scale) = [(&with_counts, 2), (&with_counts, 1), (&plain, 1)]
        .into_iter()
        .find(|(l, s)| total(l, *s) <= room)
        .unwrap_or((&plain, 1));
    let mut x = ((width - total(labels, scale)) / 2.0).max(PAD).round();
    let mid = top + BAND / 2.0;
    for (shade, label) in Shade::ALL.iter().zip(labels) {
        items.push(Item::Marker {
            shape: Marker::Circle,
            x: x + SWATCH_R,
            y: mid,
            r: SWATCH_R,
            fill: Some(rgb(shade.rgb())),
            stroke: Some(Stroke {
                color: rgb(shade.outline_rgb()),
                width: shade.outline_width().min(3.0),
            }),
        });
        x += swatch;
        let text_h = f64::from(font::CAP_HEIGHT * scale);
        items.push(Item::Text {
            x,
            y: (mid - text_h / 2.0).round(),
            text: label.clone(),
            scale,
            color: INK,
            vertical: false,
        });
        x += f64::from(font::text_width(label) * scale) + gap;
    }
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
    scene: Scene,
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

    /// Colliders left out because their pose or outline was not finite, or they
    /// cannot be drawn (half-spaces).
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// The frame as the bytes of a PNG file (8-bit RGB, stored deflate: about 3 bytes
    /// per pixel). O(pixels).
    pub fn png(&self) -> Vec<u8> {
        png::encode_rgb(self.width, self.height, &self.rgb)
    }

    /// Writes [`Self::png`] to `path`; the directory must exist. O(pixels).
    pub fn write_png(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        std::fs::write(path, self.png())
    }

    /// The same picture as an SVG document (vector shapes; text in the viewer's
    /// monospace font). O(pieces).
    pub fn svg(&self) -> String {
        svg::render(&self.scene)
    }
}

#[cfg(test)]
mod tests;
