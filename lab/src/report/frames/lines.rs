//! The debug-render backend that keeps Rapier's lines, projected and grouped by the
//! object they belong to, with the pen each is stroked with.

use super::*;

/// What a run of lines belongs to: Rapier's object, by kind and handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Key {
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
pub(super) enum Pen {
    /// A body's collider in its shade; dashed for a sensor.
    Shade { shade: Shade, sensor: bool },
    /// Scenery or a collider without a body; dashed for a sensor.
    Scenery { sensor: bool },
    /// Straight RGBA: Rapier's colour (joints, contacts, ...) or an overlay's.
    Colour([u8; 4]),
}

/// Lines of one object with one pen, in pixels, and the depth of the object's
/// farthest point.
pub(super) struct Batch {
    pub(super) key: Key,
    pub(super) pen: Pen,
    pub(super) overlay: bool,
    pub(super) depth: f64,
    pub(super) segments: Vec<[(f64, f64); 2]>,
}

/// The frame's [`DebugRenderBackend`]: projects Rapier's lines through the camera,
/// chooses their colour and keeps them for painting.
pub(super) struct Lines<'a> {
    pub(super) renderer: &'a Renderer,
    pub(super) classify: &'a dyn Fn(RigidBodyHandle) -> Shade,
    pub(super) projection: Projection,
    /// Lines are clipped to this rectangle (the viewport and a margin), in pixels.
    pub(super) clip: [f64; 4],
    /// True in the second pass: everything drawn, in its own colours.
    pub(super) overlay: bool,
    /// Shades, one classifier call per body (ordered by handle).
    pub(super) shades: BTreeMap<(u32, u32), Shade>,
    pub(super) batches: Vec<Batch>,
    /// Objects with a non-finite line, and whether in the overlay pass: their lines of
    /// that pass are left out.
    pub(super) broken: BTreeSet<(bool, Key)>,
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

pub(super) fn to64(v: Vector) -> [f64; 3] {
    v.to_array().map(f64::from)
}

/// Rapier's HSLA debug colour (hue 0..=360, saturation, lightness and alpha 0..=1) as
/// straight RGBA bytes; out-of-range parts are clamped, NaN reads as 0.
pub(super) fn hsla_to_rgba([h, s, l, a]: DebugColor) -> [u8; 4] {
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
pub(super) fn clip(
    a: (f64, f64),
    b: (f64, f64),
    [x0, y0, x1, y1]: [f64; 4],
) -> Option<[(f64, f64); 2]> {
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
