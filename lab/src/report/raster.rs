//! A small software rasteriser for the display list: an RGB canvas and one drawing
//! primitive, the signed-distance fill.
//!
//! Every shape is a signed distance function `d(x, y)` (negative inside): a stroke
//! of width `w` along a polyline is `distance to the nearest segment - w/2` (a
//! capsule per segment, so caps and joins are round), a filled circle is
//! `|p - c| - r`, a polygon is its edge distance signed by the even-odd inside test,
//! and an outline is `|d| - w/2` of the filled shape. A pixel is painted with
//! coverage `clamp(0.5 - d(centre), 0, 1)`: a one-pixel antialiasing ramp, exact for
//! axis-aligned edges on pixel boundaries (so one-pixel lines through pixel centres
//! stay crisp). Rectangles use their exact area coverage. Text is the bitmap font,
//! each cell an opaque `scale × scale` block, not antialiased.
//!
//! Only pixels in a shape's bounding box are visited, and everything is clipped to
//! the canvas, so no input coordinate can make it panic or loop long.

use super::chart::{Color, Item, Scene, Shape, Stroke};
use super::font;

/// An RGB image, row-major, 3 bytes per pixel.
pub(crate) struct Canvas {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Canvas {
    /// A canvas filled with `background`.
    pub(crate) fn new(width: u32, height: u32, background: Color) -> Canvas {
        let n = width as usize * height as usize;
        let mut rgb = Vec::with_capacity(n * 3);
        for _ in 0..n {
            rgb.extend_from_slice(&[background.r, background.g, background.b]);
        }
        Canvas { width, height, rgb }
    }

    /// The colour at `(x, y)`, for tests.
    #[cfg(test)]
    pub(crate) fn pixel(&self, x: u32, y: u32) -> Color {
        let i = (y as usize * self.width as usize + x as usize) * 3;
        Color {
            r: self.rgb[i],
            g: self.rgb[i + 1],
            b: self.rgb[i + 2],
        }
    }

    /// Mixes `color` into pixel `(x, y)` with weight `alpha` (0..=1); off-canvas
    /// pixels are ignored.
    fn blend(&mut self, x: i64, y: i64, color: Color, alpha: f64) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let a = alpha.clamp(0.0, 1.0);
        if a <= 0.0 {
            return;
        }
        let i = (y as usize * self.width as usize + x as usize) * 3;
        for (k, c) in [color.r, color.g, color.b].into_iter().enumerate() {
            let old = f64::from(self.rgb[i + k]);
            self.rgb[i + k] = (old + (f64::from(c) - old) * a).round() as u8;
        }
    }

    /// The whole-pixel range `[lo, hi)` covering `[a, b]` plus one pixel of ramp,
    /// clipped to `0..limit`.
    fn span(a: f64, b: f64, limit: u32) -> std::ops::Range<i64> {
        if !(a.is_finite() && b.is_finite()) {
            return 0..0;
        }
        let lo = (a.min(b) - 1.0).floor().max(0.0) as i64;
        let hi = ((a.max(b) + 1.0).ceil() as i64).min(i64::from(limit));
        lo..hi.max(lo)
    }

    /// Paints `color` (times `opacity`) where the signed distance `sd` is below ½,
    /// within the box `[x0, x1] × [y0, y1]`.
    fn fill_sdf(
        &mut self,
        bounds: [f64; 4],
        color: Color,
        opacity: f64,
        sd: impl Fn(f64, f64) -> f64,
    ) {
        let [x0, y0, x1, y1] = bounds;
        for y in Self::span(y0, y1, self.height) {
            for x in Self::span(x0, x1, self.width) {
                let d = sd(x as f64 + 0.5, y as f64 + 0.5);
                let coverage = (0.5 - d).clamp(0.0, 1.0);
                if coverage > 0.0 {
                    self.blend(x, y, color, coverage * opacity);
                }
            }
        }
    }

    /// A polyline of round-capped segments. Each segment is visited only within its
    /// own bounding box; coverage is merged by maximum in a scratch buffer over the
    /// whole polyline, then blended once, so joins are not painted twice.
    fn polyline(&mut self, points: &[(f64, f64)], stroke: Stroke) {
        if points.is_empty() {
            return;
        }
        let half = stroke.width / 2.0;
        let [x0, y0, x1, y1] = bounding_box(points, half);
        let (xs, ys) = (
            Self::span(x0, x1, self.width),
            Self::span(y0, y1, self.height),
        );
        let cols = (xs.end - xs.start) as usize;
        if cols == 0 || ys.is_empty() {
            return;
        }
        let mut coverage = vec![0f64; cols * (ys.end - ys.start) as usize];
        let segments: Vec<[(f64, f64); 2]> = if points.len() == 1 {
            vec![[points[0], points[0]]]
        } else {
            points.windows(2).map(|w| [w[0], w[1]]).collect()
        };
        for [a, b] in segments {
            let [sx0, sy0, sx1, sy1] = bounding_box(&[a, b], half);
            for y in Self::span(sy0, sy1, self.height) {
                for x in Self::span(sx0, sx1, self.width) {
                    let d = segment_distance((x as f64 + 0.5, y as f64 + 0.5), a, b) - half;
                    let cell = (y - ys.start) as usize * cols + (x - xs.start) as usize;
                    coverage[cell] = coverage[cell].max((0.5 - d).clamp(0.0, 1.0));
                }
            }
        }
        for y in ys.clone() {
            for x in xs.clone() {
                let c = coverage[(y - ys.start) as usize * cols + (x - xs.start) as usize];
                if c > 0.0 {
                    self.blend(x, y, stroke.color, c);
                }
            }
        }
    }

    /// A rectangle filled with its exact area coverage.
    fn fill_rect(&mut self, x: f64, y: f64, w: f64, h: f64, color: Color, opacity: f64) {
        let (x1, y1) = (x + w, y + h);
        for py in Self::span(y, y1, self.height) {
            let cy = (y1.min(py as f64 + 1.0) - y.max(py as f64)).max(0.0);
            for px in Self::span(x, x1, self.width) {
                let cx = (x1.min(px as f64 + 1.0) - x.max(px as f64)).max(0.0);
                self.blend(px, py, color, cx * cy * opacity);
            }
        }
    }

    /// Text in the bitmap font.
    fn text(&mut self, x: f64, y: f64, text: &str, scale: u32, color: Color, vertical: bool) {
        let s = i64::from(scale.max(1));
        let (x, y) = (x.round() as i64, y.round() as i64);
        let length = i64::from(font::text_width(text)) * s;
        for (i, c) in text.chars().enumerate() {
            let glyph = font::glyph(c);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..font::WIDTH {
                    if bits & (1 << (font::WIDTH - 1 - col)) == 0 {
                        continue;
                    }
                    let along = i as i64 * i64::from(font::ADVANCE) + i64::from(col);
                    let (bx, by) = if vertical {
                        // Rotated a quarter turn anticlockwise: reads bottom to top.
                        (x + row as i64 * s, y + length - (along + 1) * s)
                    } else {
                        (x + along * s, y + row as i64 * s)
                    };
                    for dy in 0..s {
                        for dx in 0..s {
                            self.blend(bx + dx, by + dy, color, 1.0);
                        }
                    }
                }
            }
        }
    }

    /// A data marker: fill, then outline.
    fn marker(
        &mut self,
        shape: Shape,
        cx: f64,
        cy: f64,
        r: f64,
        fill: Option<Color>,
        stroke: Option<Stroke>,
    ) {
        if shape == Shape::Cross {
            if let Some(stroke) = stroke {
                for segment in Shape::cross_segments(cx, cy, r) {
                    self.polyline(&segment, stroke);
                }
            }
            return;
        }
        let margin = stroke.map_or(0.0, |s| s.width) + 2.0 * r;
        let bounds = [cx - margin, cy - margin, cx + margin, cy + margin];
        let polygon = shape.polygon(cx, cy, r);
        let sd = |x: f64, y: f64| match &polygon {
            Some(poly) => polygon_distance((x, y), poly),
            None => ((x - cx).powi(2) + (y - cy).powi(2)).sqrt() - r,
        };
        if let Some(color) = fill {
            self.fill_sdf(bounds, color, 1.0, sd);
        }
        if let Some(stroke) = stroke {
            let half = stroke.width / 2.0;
            self.fill_sdf(bounds, stroke.color, 1.0, |x, y| sd(x, y).abs() - half);
        }
    }

    /// A filled polygon, then its outline (centred on the edges).
    fn polygon(&mut self, points: &[(f64, f64)], fill: Option<Color>, stroke: Option<Stroke>) {
        if points.len() < 3 || points.iter().any(|p| !(p.0.is_finite() && p.1.is_finite())) {
            return;
        }
        let margin = stroke.map_or(0.0, |s| s.width);
        let bounds = bounding_box(points, margin);
        if let Some(color) = fill {
            self.fill_sdf(bounds, color, 1.0, |x, y| polygon_distance((x, y), points));
        }
        if let Some(stroke) = stroke {
            let half = stroke.width / 2.0;
            self.fill_sdf(bounds, stroke.color, 1.0, |x, y| {
                polygon_distance((x, y), points).abs() - half
            });
        }
    }

    /// Paints one display-list item.
    fn item(&mut self, item: &Item) {
        match item {
            Item::Rect {
                x,
                y,
                w,
                h,
                fill,
                opacity,
                stroke,
            } => {
                if let Some(color) = fill {
                    self.fill_rect(*x, *y, *w, *h, *color, *opacity);
                }
                if let Some(stroke) = stroke {
                    let (x1, y1) = (x + w, y + h);
                    // A closed polyline: the outer corners come out rounded by half
                    // the stroke width, invisible at the widths used here.
                    let ring = [(*x, *y), (x1, *y), (x1, y1), (*x, y1), (*x, *y)];
                    self.polyline(&ring, *stroke);
                }
            }
            Item::Line { points, stroke } => self.polyline(points, *stroke),
            Item::Polygon {
                points,
                fill,
                stroke,
            } => self.polygon(points, *fill, *stroke),
            Item::Marker {
                shape,
                x,
                y,
                r,
                fill,
                stroke,
            } => self.marker(*shape, *x, *y, *r, *fill, *stroke),
            Item::Text {
                x,
                y,
                text,
                scale,
                color,
                vertical,
            } => self.text(*x, *y, text, *scale, *color, *vertical),
            Item::Group { items, .. } => items.iter().for_each(|i| self.item(i)),
        }
    }
}

/// Paints a scene.
pub(crate) fn render(scene: &Scene) -> Canvas {
    let mut canvas = Canvas::new(scene.width, scene.height, scene.background);
    for item in &scene.items {
        canvas.item(item);
    }
    canvas
}

/// `[x0, y0, x1, y1]` of `points`, grown by `margin`.
fn bounding_box(points: &[(f64, f64)], margin: f64) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for &(x, y) in points {
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    [b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin]
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (p.0 - (a.0 + t * dx), p.1 - (a.1 + t * dy));
    (ex * ex + ey * ey).sqrt()
}

/// Signed distance from `p` to a closed polygon (negative inside, even-odd rule).
fn polygon_distance(p: (f64, f64), poly: &[(f64, f64)]) -> f64 {
    let mut dist = f64::INFINITY;
    let mut inside = false;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        dist = dist.min(segment_distance(p, a, b));
        if (a.1 > p.1) != (b.1 > p.1) && p.0 < a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            inside = !inside;
        }
    }
    if inside {
        -dist
    } else {
        dist
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RED: Color = Color { r: 255, g: 0, b: 0 };

    #[test]
    fn one_pixel_lines_through_pixel_centres_are_crisp() {
        let mut c = Canvas::new(
            10,
            10,
            Color {
                r: 255,
                g: 255,
                b: 255,
            },
        );
        c.polyline(
            &[(0.5, 4.5), (9.5, 4.5)],
            Stroke {
                color: RED,
                width: 1.0,
            },
        );
        assert_eq!(c.pixel(5, 4), RED);
        assert_eq!(
            c.pixel(5, 3),
            Color {
                r: 255,
                g: 255,
                b: 255
            }
        );
        assert_eq!(
            c.pixel(5, 5),
            Color {
                r: 255,
                g: 255,
                b: 255
            }
        );
    }

    #[test]
    fn shapes_fill_their_inside_and_clip_at_the_edges() {
        let mut c = Canvas::new(20, 20, Color { r: 0, g: 0, b: 0 });
        c.marker(Shape::Star, 10.0, 10.0, 5.0, Some(RED), None);
        assert_eq!(c.pixel(10, 10), RED);
        assert_eq!(c.pixel(1, 1), Color { r: 0, g: 0, b: 0 });
        // Off-canvas and non-finite geometry is ignored.
        c.marker(Shape::Circle, -50.0, 30.0, 8.0, Some(RED), None);
        c.polyline(
            &[(f64::NAN, 0.0), (5.0, f64::INFINITY)],
            Stroke {
                color: RED,
                width: 1.0,
            },
        );
        c.text(18.0, 18.0, "long text off the edge", 2, RED, false);
        c.text(0.0, -40.0, "up", 2, RED, true);
    }

    #[test]
    fn polygon_distance_is_signed() {
        let square = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        assert_eq!(polygon_distance((1.0, 1.0), &square), -1.0);
        assert_eq!(polygon_distance((3.0, 1.0), &square), 1.0);
    }
}
