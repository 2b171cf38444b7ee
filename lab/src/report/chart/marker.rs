//! The points' markers: a shape and colour per kind, drawn as one plotters element so
//! that the legend shows exactly what the plot does.

use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use super::palette::{FRONT, VIOLATION};
use crate::report::PointKind;

/// Marker shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    Circle,
    Square,
    Diamond,
    TriangleUp,
    TriangleDown,
    Star,
}

impl Shape {
    /// The outline of a polygonal shape centred on `(x, y)` with nominal radius `r`
    /// (sizes chosen so that all shapes look about as heavy as a circle of radius
    /// `r`); `None` for the circle.
    pub(crate) fn polygon(self, x: f64, y: f64, r: f64) -> Option<Vec<(f64, f64)>> {
        let regular = |n: usize, radius: f64, phase: f64| -> Vec<(f64, f64)> {
            (0..n)
                .map(|k| {
                    let a = phase + k as f64 * std::f64::consts::TAU / n as f64;
                    (x + radius * a.cos(), y + radius * a.sin())
                })
                .collect()
        };
        let up = -std::f64::consts::FRAC_PI_2;
        match self {
            Shape::Circle => None,
            Shape::Square => {
                let s = r * 0.88;
                Some(vec![
                    (x - s, y - s),
                    (x + s, y - s),
                    (x + s, y + s),
                    (x - s, y + s),
                ])
            }
            Shape::Diamond => {
                let s = r * 1.25;
                Some(vec![(x, y - s), (x + s, y), (x, y + s), (x - s, y)])
            }
            Shape::TriangleUp => Some(regular(3, r * 1.3, up)),
            Shape::TriangleDown => Some(regular(3, r * 1.3, -up)),
            Shape::Star => {
                let outer = regular(5, r * 1.4, up);
                let inner = regular(5, r * 0.6, up + std::f64::consts::PI / 5.0);
                Some(
                    outer
                        .into_iter()
                        .zip(inner)
                        .flat_map(|(o, i)| [o, i])
                        .collect(),
                )
            }
        }
    }
}

/// How a kind is drawn: shape, fill colour and nominal radius in pixels.
pub(crate) fn style(kind: PointKind) -> (Shape, RGBColor, f64) {
    match kind {
        PointKind::Reference => (Shape::Diamond, RGBColor(0x11, 0x11, 0x11), 5.5),
        PointKind::BruteForce => (Shape::Square, RGBColor(0x7F, 0x7F, 0x7F), 5.5),
        PointKind::ContactGraph => (Shape::TriangleUp, RGBColor(0x2C, 0xA0, 0x2C), 6.0),
        PointKind::StockRapier => (Shape::TriangleDown, RGBColor(0x94, 0x67, 0xBD), 6.0),
        PointKind::Combination => (Shape::Circle, RGBColor(0x1F, 0x77, 0xB4), 4.5),
        PointKind::Repaired => (Shape::Star, RGBColor(0x17, 0xBE, 0xCF), 6.0),
    }
}

/// A point's marker as a plotters element at `at` (data coordinates on the chart,
/// pixels in the legend): the kind's filled marker with a white rim, or for a point
/// with violations a red cross (over a hollow kind marker for the special kinds, so
/// they stay recognisable); ringed in orange when on the front. One element, so that
/// the legend draws exactly what the plot does.
pub(crate) struct Marker<C> {
    at: C,
    kind: PointKind,
    violations: u64,
    on_front: bool,
}

impl<C> Marker<C> {
    pub(super) fn new(at: C, kind: PointKind, violations: u64, on_front: bool) -> Self {
        Marker {
            at,
            kind,
            violations,
            on_front,
        }
    }
}

impl<'a, C: 'a> PointCollection<'a, C> for &'a Marker<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Marker<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((px, py)) = pos.next() else {
            return Ok(());
        };
        let (x, y) = (f64::from(px), f64::from(py));
        let (shape, color, r) = style(self.kind);
        let pixels = |poly: Vec<(f64, f64)>| -> Vec<BackendCoord> {
            poly.into_iter()
                .map(|(a, b)| (a.round() as i32, b.round() as i32))
                .collect()
        };
        let closed = |mut poly: Vec<BackendCoord>| {
            if let Some(&first) = poly.first() {
                poly.push(first);
            }
            poly
        };
        if self.on_front {
            let ring = (r + 3.5).round() as u32;
            backend.draw_circle((px, py), ring, &FRONT.stroke_width(2), false)?;
        }
        if self.violations == 0 {
            match shape.polygon(x, y, r) {
                None => {
                    let radius = r.round() as u32;
                    backend.draw_circle((px, py), radius, &color.filled(), true)?;
                    backend.draw_circle((px, py), radius, &WHITE.stroke_width(1), false)?;
                }
                Some(poly) => {
                    let poly = pixels(poly);
                    backend.fill_polygon(poly.clone(), &color.filled())?;
                    backend.draw_path(closed(poly), &WHITE.stroke_width(1))?;
                }
            }
            return Ok(());
        }
        if self.kind != PointKind::Combination {
            match shape.polygon(x, y, r + 1.0) {
                None => {
                    let radius = (r + 1.0).round() as u32;
                    backend.draw_circle((px, py), radius, &color.stroke_width(2), false)?;
                }
                Some(poly) => backend.draw_path(closed(pixels(poly)), &color.stroke_width(2))?,
            }
        }
        let s = 4;
        let cross = VIOLATION.stroke_width(2);
        backend.draw_path([(px - s, py - s), (px + s, py + s)], &cross)?;
        backend.draw_path([(px - s, py + s), (px + s, py - s)], &cross)?;
        Ok(())
    }
}
