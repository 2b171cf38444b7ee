//! The camera: an orthographic projection of the world onto a plane, fitted to a
//! pixel rectangle.
//!
//! A [`View`] fixes the plane by an orthonormal basis: `right` and `up` span the
//! picture, `forward` points from the viewer into the scene. The default is the side
//! view of the paper's figures (looking along −z: right = +x, up = +y); a tilted view
//! turns the camera by a yaw about the world's y axis, then pitches it down. A
//! [`Camera`] adds the picture's size and what to fit: given world bounds, or the
//! bounds of whatever the world holds at render time. [`Projection`] is the result:
//! world point → pixel (y grows downwards) and depth along `forward`.
//!
//! Orthographic, not perspective: a ball stays a disc of the same radius wherever it
//! is, so sizes can be compared across the picture and between frames, which is what
//! a figure of a physics scene wants. Perspective was rejected for that reason and
//! because it needs a near plane (bodies behind the viewer).

use rapier3d::math::{Real, Vector};

use rapier_contact_graph::{Error, Result};

/// Smallest and largest accepted picture sides, in pixels (sizes are clamped).
pub(crate) const MIN_SIDE: u32 = 160;
/// See [`MIN_SIDE`].
pub(crate) const MAX_SIDE: u32 = 8192;

/// The direction the camera looks from: a yaw about the world's y axis and a pitch
/// downwards, applied to the side view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    yaw: f64,
    pitch: f64,
}

impl Default for View {
    /// The side view, [`View::SIDE`].
    fn default() -> Self {
        View::SIDE
    }
}

impl View {
    /// The side view: looking along −z, x to the right, y up (the paper's figures).
    pub const SIDE: View = View {
        yaw: 0.0,
        pitch: 0.0,
    };

    /// The side view turned by `yaw_degrees` about the world's y axis (positive moves
    /// the viewer round towards +x: at 90 it looks along −x), then pitched down by
    /// `pitch_degrees` (positive looks down from above; 90 is the top view, with −z
    /// up in the picture at yaw 0). Non-finite angles are an [`Error::NonFinite`].
    pub fn tilted(yaw_degrees: Real, pitch_degrees: Real) -> Result<View> {
        if !yaw_degrees.is_finite() {
            return Err(Error::NonFinite("view yaw"));
        }
        if !pitch_degrees.is_finite() {
            return Err(Error::NonFinite("view pitch"));
        }
        Ok(View {
            yaw: f64::from(yaw_degrees).to_radians(),
            pitch: f64::from(pitch_degrees).to_radians(),
        })
    }

    /// `[right, up, forward]`, an orthonormal basis with `right × up = −forward`.
    pub(crate) fn basis(&self) -> [[f64; 3]; 3] {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let right = [cy, 0.0, -sy];
        // Forward in the horizontal plane after the yaw (the side view's −z turned).
        let level = [-sy, 0.0, -cy];
        let forward = [level[0] * cp, -sp, level[2] * cp];
        let up = [level[0] * sp, cp, level[2] * sp];
        [right, up, forward]
    }
}

/// What to draw and at which size: a [`View`], a picture size and the world box to
/// fit into it.
///
/// ```
/// use rapier3d::math::Vector;
/// use rcg_lab::report::frames::{Camera, View};
///
/// let camera = Camera::new(640, 480)
///     .with_view(View::tilted(30.0, 20.0)?)
///     .with_bounds(Vector::new(-2.0, 0.0, -1.0), Vector::new(2.0, 3.0, 1.0))?;
/// assert_eq!(camera.size(), (640, 480));
/// assert!(Camera::new(640, 480).with_bounds(Vector::ONE, Vector::ZERO).is_err());
/// # Ok::<(), rapier_contact_graph::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    width: u32,
    height: u32,
    view: View,
    bounds: Option<(Vector, Vector)>,
}

impl Camera {
    /// A side-view camera of `width` × `height` pixels (each clamped to 160..=8192)
    /// that fits the world's colliders at each render. O(1).
    pub fn new(width: u32, height: u32) -> Camera {
        Camera {
            width: width.clamp(MIN_SIDE, MAX_SIDE),
            height: height.clamp(MIN_SIDE, MAX_SIDE),
            view: View::SIDE,
            bounds: None,
        }
    }

    /// The same camera looking from `view`. O(1).
    pub fn with_view(mut self, view: View) -> Camera {
        self.view = view;
        self
    }

    /// The same camera fitting the world box `mins`..`maxs` instead of the world's
    /// colliders, so that a sequence of frames keeps one scale and place. A
    /// non-finite corner is an [`Error::NonFinite`]; `mins` above `maxs` on an axis is
    /// an [`Error::InvalidParameter`]. A flat or empty box (equal corners) is
    /// accepted and widened at render time. O(1).
    pub fn with_bounds(mut self, mins: Vector, maxs: Vector) -> Result<Camera> {
        if !mins.is_finite() || !maxs.is_finite() {
            return Err(Error::NonFinite("camera bounds"));
        }
        if mins.cmpgt(maxs).any() {
            return Err(Error::InvalidParameter {
                name: "bounds",
                reason: format!("mins {mins} above maxs {maxs}"),
            });
        }
        self.bounds = Some((mins, maxs));
        Ok(self)
    }

    /// The same camera fitting its world box again at each render. O(1).
    pub fn with_auto_fit(mut self) -> Camera {
        self.bounds = None;
        self
    }

    /// The picture size in pixels, after clamping.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The view.
    pub fn view(&self) -> View {
        self.view
    }

    /// The world box given by [`Self::with_bounds`], `None` when fitting the world.
    pub fn bounds(&self) -> Option<(Vector, Vector)> {
        self.bounds
    }

    /// The projection that fits `bounds` (or, without bounds, `fallback`, or else the
    /// unit cube around the origin) centred into the pixel rectangle `viewport`
    /// (`[x0, y0, x1, y1]`), one scale for both axes. O(1).
    pub(crate) fn projection(
        &self,
        fallback: Option<(Vector, Vector)>,
        viewport: [f64; 4],
    ) -> Projection {
        let [right, up, forward] = self.view.basis();
        let (mins, maxs) = self
            .bounds
            .or(fallback)
            .unwrap_or((Vector::splat(-0.5), Vector::splat(0.5)));
        let (mut u0, mut u1, mut v0, mut v1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for k in 0..8 {
            let c = [
                if k & 1 == 0 { mins.x } else { maxs.x },
                if k & 2 == 0 { mins.y } else { maxs.y },
                if k & 4 == 0 { mins.z } else { maxs.z },
            ]
            .map(f64::from);
            let (u, v) = (dot(c, right), dot(c, up));
            (u0, u1, v0, v1) = (u0.min(u), u1.max(u), v0.min(v), v1.max(v));
        }
        let [x0, y0, x1, y1] = viewport;
        let (pw, ph) = ((x1 - x0).max(1.0), (y1 - y0).max(1.0));
        let (du, dv) = (u1 - u0, v1 - v0);
        // A flat box is widened to the other side's extent (or 1 m), so a single
        // body or a line of bodies still gets a sensible scale.
        let size = du.max(dv).max(1e-9);
        let (du, dv) = (
            if du > 1e-9 { du } else { size.max(1.0) },
            if dv > 1e-9 { dv } else { size.max(1.0) },
        );
        let scale = (pw / du).min(ph / dv);
        Projection {
            right,
            up,
            forward,
            scale,
            centre_uv: ((u0 + u1) / 2.0, (v0 + v1) / 2.0),
            centre_px: ((x0 + x1) / 2.0, (y0 + y1) / 2.0),
        }
    }
}

/// A fitted orthographic projection: world point → pixel and depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    right: [f64; 3],
    up: [f64; 3],
    forward: [f64; 3],
    scale: f64,
    centre_uv: (f64, f64),
    centre_px: (f64, f64),
}

impl Projection {
    /// The pixel of world point `p` (x to the right, y downwards; pixel `(i, j)` covers
    /// `[i, i+1) × [j, j+1)`). O(1).
    pub fn to_pixel(&self, p: Vector) -> (f64, f64) {
        self.project64(p.to_array().map(f64::from))
    }

    pub(crate) fn project64(&self, p: [f64; 3]) -> (f64, f64) {
        (
            self.centre_px.0 + (dot(p, self.right) - self.centre_uv.0) * self.scale,
            self.centre_px.1 - (dot(p, self.up) - self.centre_uv.1) * self.scale,
        )
    }

    /// How far `p` lies from the viewer along the viewing direction, in metres (larger
    /// is farther; only differences mean anything). O(1).
    pub fn depth(&self, p: Vector) -> f64 {
        dot(p.to_array().map(f64::from), self.forward)
    }

    /// Pixels per metre.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The basis `[right, up, forward]` in world coordinates.
    pub(crate) fn basis(&self) -> [[f64; 3]; 3] {
        [self.right, self.up, self.forward]
    }
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-12)
    }

    #[test]
    fn bases_are_orthonormal_and_right_handed() {
        for (yaw, pitch) in [(0.0, 0.0), (30.0, 20.0), (-75.0, 90.0), (200.0, -40.0)] {
            let [r, u, f] = View::tilted(yaw, pitch).unwrap().basis();
            for (a, b) in [(r, u), (u, f), (f, r)] {
                assert!(dot(a, b).abs() < 1e-12);
            }
            for a in [r, u, f] {
                assert!((dot(a, a) - 1.0).abs() < 1e-12);
            }
            let cross = [
                r[1] * u[2] - r[2] * u[1],
                r[2] * u[0] - r[0] * u[2],
                r[0] * u[1] - r[1] * u[0],
            ];
            assert!(close(cross, f.map(|x| -x)), "{yaw} {pitch}");
        }
        let [r, u, f] = View::SIDE.basis();
        assert!(close(r, [1.0, 0.0, 0.0]) && close(u, [0.0, 1.0, 0.0]));
        assert!(close(f, [0.0, 0.0, -1.0]));
        // The top view looks straight down.
        let [_, _, f] = View::tilted(0.0, 90.0).unwrap().basis();
        assert!(close(f, [0.0, -1.0, 0.0]));
    }

    #[test]
    fn projection_fits_the_box_centred_with_one_scale() {
        let cam = Camera::new(400, 200)
            .with_bounds(Vector::new(-2.0, 0.0, -1.0), Vector::new(2.0, 1.0, 1.0))
            .unwrap();
        let p = cam.projection(None, [0.0, 0.0, 400.0, 200.0]);
        // 4 m wide into 400 px, 1 m high into 200 px: the width limits, 100 px/m.
        assert_eq!(p.scale(), 100.0);
        assert_eq!(p.to_pixel(Vector::new(0.0, 0.5, 0.0)), (200.0, 100.0));
        assert_eq!(p.to_pixel(Vector::new(-2.0, 1.0, 0.0)), (0.0, 50.0));
        // Nearer to the viewer (larger z in the side view) is smaller depth.
        assert!(p.depth(Vector::new(0.0, 0.0, 1.0)) < p.depth(Vector::ZERO));
        // A flat box gets a finite scale; no bounds and no fallback: the unit cube.
        let flat = Camera::new(200, 200)
            .with_bounds(Vector::ZERO, Vector::ZERO)
            .unwrap()
            .projection(None, [0.0, 0.0, 200.0, 200.0]);
        assert!(flat.scale().is_finite() && flat.scale() > 0.0);
        let unit = Camera::new(200, 200).projection(None, [0.0, 0.0, 200.0, 200.0]);
        assert_eq!(unit.scale(), 200.0);
    }

    #[test]
    fn bad_parameters_are_errors_and_sizes_are_clamped() {
        assert!(matches!(
            View::tilted(Real::NAN, 0.0),
            Err(Error::NonFinite(_))
        ));
        assert!(matches!(
            View::tilted(0.0, Real::INFINITY),
            Err(Error::NonFinite(_))
        ));
        let cam = Camera::new(0, u32::MAX);
        assert_eq!(cam.size(), (MIN_SIDE, MAX_SIDE));
        assert!(matches!(
            cam.clone().with_bounds(Vector::NAN, Vector::ONE),
            Err(Error::NonFinite(_))
        ));
        assert!(matches!(
            cam.with_bounds(Vector::new(0.0, 2.0, 0.0), Vector::ONE),
            Err(Error::InvalidParameter { .. })
        ));
    }
}
