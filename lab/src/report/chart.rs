//! Layout: from points and a [`ChartSpec`] to a display list in pixel coordinates.
//!
//! Everything that decides *where* things go lives here, so that the SVG and the
//! PNG back ends only translate [`Item`]s. Coordinates are pixels with the origin at
//! the top-left corner; the plot frame is snapped to whole pixels and one-pixel lines
//! are drawn through pixel centres (`n + 0.5`) so that both back ends render them
//! crisp. Text boxes are given by their top-left corner and sized with the bitmap
//! font's metrics ([`font`]).
//!
//! Steps of [`layout`]: pick the drawable points; compute the front; choose axis
//! ranges (padded data range, widened when degenerate) and "nice" ticks (1-2-5 steps;
//! decades on a log axis); size the margins from the tick labels; then emit, back to
//! front: grid, ticks and frame, the front's step line, the markers (violations
//! first, special configurations last), the labels (greedy placement), the legend
//! (in the emptiest corner), title, caption and axis labels.

use super::{font, pareto_front, ChartPoint, ChartSpec, PointKind};

/// An opaque sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Color {
    pub r: u8,
    pub g: u8,
    pub b: u8,
}

impl Color {
    /// From `0xRRGGBB`.
    pub(crate) const fn hex(v: u32) -> Color {
        Color {
            r: (v >> 16) as u8,
            g: (v >> 8) as u8,
            b: v as u8,
        }
    }
}

pub(crate) const WHITE: Color = Color::hex(0xFFFFFF);
const INK: Color = Color::hex(0x222222);
const MUTED: Color = Color::hex(0x666666);
const FRAME: Color = Color::hex(0x444444);
const GRID_MAJOR: Color = Color::hex(0xDDDDDD);
const GRID_MINOR: Color = Color::hex(0xF0F0F0);
const FRONT: Color = Color::hex(0xFF7F0E);
const VIOLATION: Color = Color::hex(0xD62728);
const LEADER: Color = Color::hex(0x999999);

/// A line style.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Stroke {
    pub color: Color,
    pub width: f64,
}

/// Marker shapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    Circle,
    Square,
    Diamond,
    TriangleUp,
    TriangleDown,
    Star,
    /// An × made of two strokes (the fill is ignored).
    Cross,
}

impl Shape {
    /// The outline of a polygonal shape centred on `(x, y)` with nominal radius `r`
    /// (sizes chosen so that all shapes look about as heavy as a circle of radius
    /// `r`); `None` for the circle and the cross.
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
            Shape::Circle | Shape::Cross => None,
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

    /// The two strokes of the cross.
    pub(crate) fn cross_segments(x: f64, y: f64, r: f64) -> [[(f64, f64); 2]; 2] {
        let s = r * 0.8;
        [
            [(x - s, y - s), (x + s, y + s)],
            [(x - s, y + s), (x + s, y - s)],
        ]
    }
}

/// One element of the display list.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Item {
    /// An axis-aligned rectangle.
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Option<Color>,
        /// Opacity of the fill, 0..=1.
        opacity: f64,
        stroke: Option<Stroke>,
    },
    /// A polyline with round joins and caps.
    Line {
        points: Vec<(f64, f64)>,
        stroke: Stroke,
    },
    /// A data marker centred on `(x, y)`.
    Marker {
        shape: Shape,
        x: f64,
        y: f64,
        r: f64,
        fill: Option<Color>,
        stroke: Option<Stroke>,
    },
    /// A closed polygon (even-odd fill), its outline centred on the edges.
    Polygon {
        points: Vec<(f64, f64)>,
        fill: Option<Color>,
        stroke: Option<Stroke>,
    },
    /// Text in the bitmap font at an integer scale; `(x, y)` is the top-left corner of
    /// the box (capitals reach from `y` to `y + 7 * scale`). Vertical text reads
    /// bottom to top, its box `9 * scale` wide and starting at the bottom.
    Text {
        x: f64,
        y: f64,
        text: String,
        scale: u32,
        color: Color,
        vertical: bool,
    },
    /// Items that belong together; the SVG keeps the class and the tooltip.
    Group {
        class: &'static str,
        tooltip: Option<String>,
        items: Vec<Item>,
    },
}

/// A laid-out chart.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Scene {
    pub width: u32,
    pub height: u32,
    pub background: Color,
    pub items: Vec<Item>,
}

// Text sizes (integer scales of the 5×9 font: scale 1 = 6 px per character).
const TITLE_SCALE: u32 = 2;
const AXIS_LABEL_SCALE: u32 = 2;
const TICK_SCALE: u32 = 2;
const SMALL_SCALE: u32 = 1;
/// Labels longer than this are shortened with "...".
const MAX_LABEL_CHARS: usize = 40;
/// Largest magnitude an axis reaches (smallest positive value on a log axis: its
/// inverse).
const LIMIT: f64 = 1e150;

/// How a kind is drawn: shape, fill colour and nominal radius.
fn style(kind: PointKind) -> (Shape, Color, f64) {
    match kind {
        PointKind::Reference => (Shape::Diamond, Color::hex(0x111111), 5.5),
        PointKind::BruteForce => (Shape::Square, Color::hex(0x7F7F7F), 5.5),
        PointKind::ContactGraph => (Shape::TriangleUp, Color::hex(0x2CA02C), 6.0),
        PointKind::StockRapier => (Shape::TriangleDown, Color::hex(0x9467BD), 6.0),
        PointKind::Combination => (Shape::Circle, Color::hex(0x1F77B4), 4.5),
        PointKind::Repaired => (Shape::Star, Color::hex(0x17BECF), 6.0),
    }
}

/// A point's marker items: the kind's marker, or for a point with violations a red
/// cross (over a hollow kind marker for the special kinds, so they stay recognisable).
fn marker_items(kind: PointKind, violations: u64, x: f64, y: f64, out: &mut Vec<Item>) {
    let (shape, color, r) = style(kind);
    if violations == 0 {
        let stroke = Some(Stroke {
            color: WHITE,
            width: 1.0,
        });
        out.push(Item::Marker {
            shape,
            x,
            y,
            r,
            fill: Some(color),
            stroke,
        });
        return;
    }
    if kind != PointKind::Combination {
        let stroke = Some(Stroke { color, width: 1.5 });
        out.push(Item::Marker {
            shape,
            x,
            y,
            r: r + 1.0,
            fill: None,
            stroke,
        });
    }
    let stroke = Some(Stroke {
        color: VIOLATION,
        width: 2.0,
    });
    out.push(Item::Marker {
        shape: Shape::Cross,
        x,
        y,
        r: 4.5,
        fill: None,
        stroke,
    });
}

/// An axis: data domain, mapping and ticks.
#[derive(Clone, Debug, PartialEq)]
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    /// Labelled ticks.
    major: Vec<f64>,
    /// Unlabelled grid lines.
    minor: Vec<f64>,
    labels: Vec<String>,
}

impl Axis {
    /// A linear axis over `[lo, hi]` (padded by 4% each side), about `target` ticks.
    fn linear(lo: f64, hi: f64, target: usize) -> Axis {
        let (lo, hi) = widen(lo, hi);
        let pad = (hi - lo) * 0.04;
        let (lo, hi) = (lo - pad, hi + pad);
        let (major, decimals) = nice_ticks(lo, hi, target);
        let labels = major.iter().map(|&v| tick_label(v, decimals)).collect();
        Axis {
            lo,
            hi,
            log: false,
            major,
            minor: Vec::new(),
            labels,
        }
    }

    /// A log₁₀ axis over positive `[lo, hi]` (padded by 5% of the decades each side).
    fn log(lo: f64, hi: f64, target: usize) -> Axis {
        let (mut a, mut b) = (lo.log10(), hi.log10());
        if b - a < 0.3 {
            let mid = 0.5 * (a + b);
            (a, b) = (mid - 0.15, mid + 0.15);
        }
        let pad = (b - a) * 0.05;
        let (lo, hi) = (10f64.powf(a - pad), 10f64.powf(b + pad));
        let (major, minor, labels) = log_ticks(lo, hi, target);
        Axis {
            lo,
            hi,
            log: true,
            major,
            minor,
            labels,
        }
    }

    /// Where `v` falls between the ends, 0..1.
    fn fraction(&self, v: f64) -> f64 {
        if self.log {
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

/// A non-degenerate range: an empty span is widened around its value.
fn widen(lo: f64, hi: f64) -> (f64, f64) {
    if hi - lo > 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        (lo, hi)
    } else if lo == 0.0 {
        (0.0, 1.0)
    } else {
        let d = lo.abs() * 0.5;
        if d.is_normal() && (lo - d) < lo && (hi + d) > hi {
            (lo - d, hi + d)
        } else {
            // A subnormal range (or one the half-width cannot widen): a unit around it.
            (lo - 0.5, hi + 0.5)
        }
    }
}

/// The power-of-ten exponent of a 1-2-5 step.
fn step_exponent(step: f64) -> i32 {
    (step.log10() + 1e-9).floor() as i32
}

/// Ticks at multiples of a 1-2-5 step inside `[lo, hi]`, about `target` of them, and
/// the number of decimals their labels need.
fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, usize) {
    let raw = (hi - lo) / target.max(2) as f64;
    let base = 10f64.powf(raw.log10().floor());
    // The 1-2-5 step nearest to the raw step (by ratio).
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .min_by(|a, b| (a / raw).ln().abs().total_cmp(&(b / raw).ln().abs()))
        .unwrap_or(base);
    let first = (lo / step).ceil();
    let last = (hi / step + 1e-9).floor();
    // A degenerate step (an underflowed range) gives the two ends only.
    if !(step.is_normal() && first.is_finite() && last.is_finite() && last - first < 10_000.0) {
        return (vec![lo, hi], 3);
    }
    let (first, last) = (first as i64, last as i64);
    let ticks = (first..=last)
        .map(|k| if k == 0 { 0.0 } else { k as f64 * step })
        .collect();
    (ticks, (-step_exponent(step)).max(0) as usize)
}

/// Log-axis ticks: decades if they give at least three, else 1-2-5 per decade, else
/// 1..9 per decade, else (a range narrower than about a factor 2) linear ticks.
/// Returns (labelled, grid-only, labels).
fn log_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, Vec<f64>, Vec<String>) {
    let in_range = |v: f64| v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9);
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let decade_step = ((k1 - k0) as usize).div_ceil(target.max(1) * 3 / 2).max(1);
    let with = |mantissas: &[u32], every: usize| -> Vec<(u32, i32)> {
        (k0..=k1)
            .filter(|k| (k - k0) as usize % every == 0)
            .flat_map(|k| mantissas.iter().map(move |&m| (m, k)))
            .filter(|&(m, k)| in_range(f64::from(m) * 10f64.powi(k)))
            .collect()
    };
    let all: Vec<u32> = (1..=9).collect();
    for set in [&[1][..], &[1, 2, 5][..], &all[..]] {
        let every = if set.len() == 1 { decade_step } else { 1 };
        let major = with(set, every);
        if major.len() >= 3 {
            let minor = if set.len() == 9 || (k1 - k0) > 8 {
                Vec::new()
            } else {
                with(&all, 1)
                    .into_iter()
                    .filter(|t| !major.contains(t))
                    .collect()
            };
            let value = |&(m, k): &(u32, i32)| f64::from(m) * 10f64.powi(k);
            let labels = major.iter().map(|&(m, k)| fmt_power(m, k)).collect();
            return (
                major.iter().map(value).collect(),
                minor.iter().map(value).collect(),
                labels,
            );
        }
    }
    let (ticks, decimals) = nice_ticks(lo, hi, target);
    let ticks: Vec<f64> = ticks.into_iter().filter(|&v| v > 0.0).collect();
    let labels = ticks.iter().map(|&v| tick_label(v, decimals)).collect();
    (ticks, Vec::new(), labels)
}

/// A linear tick's label: fixed-point, or scientific when that would be long.
fn tick_label(v: f64, decimals: usize) -> String {
    if decimals > 6 || v.abs() >= 1e7 {
        if v == 0.0 {
            "0".to_string()
        } else {
            format!("{v:.2e}")
        }
    } else {
        fmt_fixed(v, decimals)
    }
}

/// `v` with `decimals` decimals, never "-0".
fn fmt_fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// `m × 10^k` as a plain number, or as `me k` when that would be long.
fn fmt_power(m: u32, k: i32) -> String {
    if (-4..=5).contains(&k) {
        fmt_fixed(f64::from(m) * 10f64.powi(k), (-k).max(0) as usize)
    } else {
        format!("{m}e{k}")
    }
}

/// An axis-aligned box, for collision tests.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bounds {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Bounds {
    fn new(x: f64, y: f64, w: f64, h: f64) -> Bounds {
        Bounds {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        }
    }
    fn around(x: f64, y: f64, r: f64) -> Bounds {
        Bounds {
            x0: x - r,
            y0: y - r,
            x1: x + r,
            y1: y + r,
        }
    }
    fn overlap(&self, o: &Bounds) -> f64 {
        let w = self.x1.min(o.x1) - self.x0.max(o.x0);
        let h = self.y1.min(o.y1) - self.y0.max(o.y0);
        if w > 0.0 && h > 0.0 {
            w * h
        } else {
            0.0
        }
    }
    fn inside(&self, o: &Bounds) -> bool {
        self.x0 >= o.x0 && self.y0 >= o.y0 && self.x1 <= o.x1 && self.y1 <= o.y1
    }
    fn grow(&self, d: f64) -> Bounds {
        Bounds {
            x0: self.x0 - d,
            y0: self.y0 - d,
            x1: self.x1 + d,
            y1: self.y1 + d,
        }
    }
}

/// Size in pixels of a text box at `scale` (height includes descenders).
fn text_size(text: &str, scale: u32) -> (f64, f64) {
    (
        f64::from(font::text_width(text) * scale),
        f64::from(font::HEIGHT * scale),
    )
}

/// `text` cut to at most `max` characters, ending in "..." when cut.
fn shorten(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(max.saturating_sub(3)).collect();
        s.push_str("...");
        s
    }
}

/// The largest scale (≤ `scale`) at which `text` fits in `room` pixels, with the
/// text shortened if it fits at no scale.
fn fit(text: &str, scale: u32, room: f64) -> (String, u32) {
    for s in (1..=scale).rev() {
        if text_size(text, s).0 <= room {
            return (text.to_string(), s);
        }
    }
    let chars = (room / f64::from(font::ADVANCE)).floor().max(4.0) as usize;
    (shorten(text, chars), 1)
}

fn text(x: f64, y: f64, text: impl Into<String>, scale: u32, color: Color) -> Item {
    Item::Text {
        x,
        y,
        text: text.into(),
        scale,
        color,
        vertical: false,
    }
}

fn line(a: (f64, f64), b: (f64, f64), color: Color, width: f64) -> Item {
    Item::Line {
        points: vec![a, b],
        stroke: Stroke { color, width },
    }
}

/// A point that will be drawn, in pixels; `r` is the radius kept clear around it.
struct Placed {
    index: usize,
    x: f64,
    y: f64,
    r: f64,
}

/// The plot area and the axes that map data into it.
struct Frame {
    plot: Bounds,
    x: Axis,
    y: Axis,
}

impl Frame {
    /// Pixel column of deviation `v` (values beyond the axis are pinned to the frame).
    fn px(&self, v: f64) -> f64 {
        self.plot.x0 + self.x.fraction(v).clamp(0.0, 1.0) * (self.plot.x1 - self.plot.x0)
    }
    /// Pixel row of speed-up `v`.
    fn py(&self, v: f64) -> f64 {
        self.plot.y1 - self.y.fraction(v).clamp(0.0, 1.0) * (self.plot.y1 - self.plot.y0)
    }
}

/// Top of the title and of the caption under it.
const TITLE_Y: f64 = 12.0;
const CAPTION_Y: f64 = TITLE_Y + (font::HEIGHT * TITLE_SCALE) as f64 + 4.0;
/// Length of the tick marks outside the frame.
const TICK_LEN: f64 = 5.0;

/// Lays out the chart.
pub(crate) fn layout(points: &[ChartPoint], spec: &ChartSpec) -> Scene {
    let width = spec.width.clamp(320, 8192);
    let height = spec.height.clamp(240, 8192);
    let (w, h) = (f64::from(width), f64::from(height));

    let drawable = |p: &ChartPoint| p.is_finite() && (!spec.log_y || p.speedup > 0.0);
    let visible: Vec<usize> = (0..points.len())
        .filter(|&i| drawable(&points[i]))
        .collect();
    let front: Vec<usize> = pareto_front(points, true)
        .into_iter()
        .filter(|&i| drawable(&points[i]))
        .collect();

    let frame = frame(points, &visible, spec.log_y, w, h);
    let mut items = vec![axes(&frame)];

    // The front as a step line: from each point right to the next one's deviation,
    // then up to its speed-up (the best speed-up available at that accuracy).
    let mut steps: Vec<(f64, f64)> = Vec::new();
    for &i in &front {
        let (x, y) = (frame.px(points[i].deviation), frame.py(points[i].speedup));
        if let Some(&(_, previous_y)) = steps.last() {
            steps.push((x, previous_y));
        }
        steps.push((x, y));
    }
    let has_front = steps.len() >= 2;
    if has_front {
        items.push(Item::Group {
            class: "front",
            tooltip: Some("Pareto front over the configurations without violations".into()),
            items: vec![Item::Line {
                points: steps.clone(),
                stroke: Stroke {
                    color: FRONT,
                    width: 2.5,
                },
            }],
        });
    }

    // Markers, in drawing order: violations, then the rest, specials last (on top).
    let layer = |p: &ChartPoint| match (p.kind.is_special(), p.violations > 0) {
        (true, _) => 2,
        (false, true) => 0,
        (false, false) => 1,
    };
    let mut order = visible.clone();
    order.sort_by_key(|&i| (layer(&points[i]), i));
    let placed: Vec<Placed> = order
        .iter()
        .map(|&i| Placed {
            index: i,
            x: frame.px(points[i].deviation),
            y: frame.py(points[i].speedup),
            r: style(points[i].kind).2 + 2.0,
        })
        .collect();
    for p in &placed {
        let point = &points[p.index];
        let on_front = front.contains(&p.index);
        let mut marker = Vec::new();
        if on_front {
            let stroke = Some(Stroke {
                color: FRONT,
                width: 1.5,
            });
            let r = style(point.kind).2 + 3.5;
            marker.push(Item::Marker {
                shape: Shape::Circle,
                x: p.x,
                y: p.y,
                r,
                fill: None,
                stroke,
            });
        }
        marker_items(point.kind, point.violations, p.x, p.y, &mut marker);
        items.push(Item::Group {
            class: "point",
            tooltip: Some(tooltip(point, on_front)),
            items: marker,
        });
    }

    // What the legend and the labels should not cover.
    let obstacles = Obstacles::new(&placed, &steps);
    let mut taken = Vec::new();
    if let Some((legend, bounds)) = legend(points, &visible, has_front, &frame.plot, &obstacles) {
        items.push(legend);
        taken.push(bounds);
    }
    // Labels: special configurations first, then the rest of the front.
    let mut to_label: Vec<usize> = visible
        .iter()
        .copied()
        .filter(|&i| points[i].kind.is_special())
        .collect();
    to_label.extend(
        front
            .iter()
            .copied()
            .filter(|&i| !points[i].kind.is_special()),
    );
    for i in to_label {
        if let Some(p) = placed.iter().find(|p| p.index == i) {
            items.extend(label(
                &points[i].label,
                p,
                &frame.plot,
                &obstacles,
                &mut taken,
            ));
        }
    }

    if visible.is_empty() {
        let msg = "no data";
        let (tw, th) = text_size(msg, 2);
        let (cx, cy) = (
            (frame.plot.x0 + frame.plot.x1) / 2.0,
            (frame.plot.y0 + frame.plot.y1) / 2.0,
        );
        items.push(text(
            (cx - tw / 2.0).round(),
            (cy - th / 2.0).round(),
            msg,
            2,
            MUTED,
        ));
    }
    items.extend(titles(
        spec,
        &caption(points, &visible, &front),
        &frame.plot,
        w,
        h,
    ));
    Scene {
        width,
        height,
        background: WHITE,
        items,
    }
}

/// Axis ranges and ticks, and the plot area left by the margins' text.
fn frame(points: &[ChartPoint], visible: &[usize], log_y: bool, w: f64, h: f64) -> Frame {
    let min_max = |f: &dyn Fn(&ChartPoint) -> f64| {
        visible
            .iter()
            .map(|&i| f(&points[i]))
            .fold(None, |acc: Option<(f64, f64)>, v| {
                Some(acc.map_or((v, v), |(a, b)| (a.min(v), b.max(v))))
            })
    };
    let x_target = ((w - 160.0) / 110.0).round().clamp(2.0, 12.0) as usize;
    let y_target = ((h - 140.0) / 70.0).round().clamp(2.0, 10.0) as usize;
    // Deviation and (on a linear axis) speed-up include 0. Ranges beyond ±1e150 (or
    // 1e±150 on the log axis) are cut there, so that the padding and tick arithmetic
    // cannot overflow; points beyond sit on the frame.
    let (x_lo, x_hi) = min_max(&|p| p.deviation.clamp(-LIMIT, LIMIT)).unwrap_or((0.0, 1.0));
    let x = Axis::linear(x_lo.min(0.0), x_hi.max(0.0), x_target);
    let y = if log_y {
        let (lo, hi) = min_max(&|p| p.speedup.clamp(1.0 / LIMIT, LIMIT)).unwrap_or((1.0, 10.0));
        Axis::log(lo, hi, y_target)
    } else {
        let (lo, hi) = min_max(&|p| p.speedup.clamp(-LIMIT, LIMIT)).unwrap_or((0.0, 1.0));
        Axis::linear(lo.min(0.0), hi.max(0.0), y_target)
    };

    // Left: y label (vertical), y tick labels, ticks. Bottom: ticks, x tick labels,
    // x label. Top: title and caption.
    let axis_label_h = f64::from(font::HEIGHT * AXIS_LABEL_SCALE);
    let tick_label_h = f64::from(font::CAP_HEIGHT * TICK_SCALE);
    let y_tick_w = y
        .labels
        .iter()
        .map(|l| text_size(l, TICK_SCALE).0)
        .fold(0.0, f64::max);
    let plot = Bounds {
        x0: (12.0 + axis_label_h + 10.0 + y_tick_w + 6.0 + TICK_LEN).round(),
        y0: (CAPTION_Y + f64::from(font::HEIGHT * SMALL_SCALE) + 10.0).round(),
        x1: w - 24.0,
        y1: (h - (TICK_LEN + 6.0 + tick_label_h + 12.0 + axis_label_h + 10.0)).round(),
    };
    Frame { plot, x, y }
}

/// Grid lines, ticks, tick labels and the frame.
fn axes(frame: &Frame) -> Item {
    let Frame {
        plot,
        x: x_axis,
        y: y_axis,
    } = frame;
    let mut items = Vec::new();
    for &v in &y_axis.minor {
        let y = frame.py(v).round() + 0.5;
        items.push(line((plot.x0, y), (plot.x1, y), GRID_MINOR, 1.0));
    }
    let tick_label_h = f64::from(font::CAP_HEIGHT * TICK_SCALE);
    for (&v, label) in x_axis.major.iter().zip(&x_axis.labels) {
        let x = frame.px(v).round() + 0.5;
        items.push(line((x, plot.y0), (x, plot.y1), GRID_MAJOR, 1.0));
        items.push(line((x, plot.y1), (x, plot.y1 + TICK_LEN), FRAME, 1.0));
        let tx = (x - text_size(label, TICK_SCALE).0 / 2.0).round();
        items.push(text(
            tx,
            plot.y1 + TICK_LEN + 6.0,
            label.clone(),
            TICK_SCALE,
            INK,
        ));
    }
    for (&v, label) in y_axis.major.iter().zip(&y_axis.labels) {
        let y = frame.py(v).round() + 0.5;
        items.push(line((plot.x0, y), (plot.x1, y), GRID_MAJOR, 1.0));
        items.push(line((plot.x0 - TICK_LEN, y), (plot.x0, y), FRAME, 1.0));
        let tx = plot.x0 - TICK_LEN - 6.0 - text_size(label, TICK_SCALE).0;
        items.push(text(
            tx,
            (y - tick_label_h / 2.0).round(),
            label.clone(),
            TICK_SCALE,
            INK,
        ));
    }
    items.push(Item::Rect {
        x: plot.x0 + 0.5,
        y: plot.y0 + 0.5,
        w: plot.x1 - plot.x0 - 1.0,
        h: plot.y1 - plot.y0 - 1.0,
        fill: None,
        opacity: 1.0,
        stroke: Some(Stroke {
            color: FRAME,
            width: 1.0,
        }),
    });
    Item::Group {
        class: "axes",
        tooltip: None,
        items,
    }
}

/// Boxes around the markers and along the front line, for collision costs.
struct Obstacles {
    markers: Vec<Bounds>,
    front: Vec<Bounds>,
}

impl Obstacles {
    fn new(placed: &[Placed], steps: &[(f64, f64)]) -> Obstacles {
        let markers = placed
            .iter()
            .map(|p| Bounds::around(p.x, p.y, p.r))
            .collect();
        // The front line as small boxes every ~6 px.
        let front = steps
            .windows(2)
            .flat_map(|s| {
                let ((x0, y0), (x1, y1)) = (s[0], s[1]);
                let n = ((x1 - x0).abs().max((y1 - y0).abs()) / 6.0).ceil().max(1.0) as usize;
                (0..=n).map(move |k| {
                    let t = k as f64 / n as f64;
                    Bounds::around(x0 + t * (x1 - x0), y0 + t * (y1 - y0), 2.0)
                })
            })
            .collect();
        Obstacles { markers, front }
    }

    /// Overlap of `b` with the markers (except `own`) and the front, weighted.
    fn cost(&self, b: &Bounds, own: Option<&Bounds>, marker_weight: f64) -> f64 {
        let markers: f64 = self
            .markers
            .iter()
            .filter(|m| Some(*m) != own)
            .map(|m| b.overlap(m))
            .sum();
        let front: f64 = self.front.iter().map(|m| b.overlap(m)).sum();
        markers * marker_weight + front
    }
}

/// The legend (kinds shown, violations, front) in the plot corner it covers least;
/// `None` if there is nothing to explain.
fn legend(
    points: &[ChartPoint],
    visible: &[usize],
    has_front: bool,
    plot: &Bounds,
    obstacles: &Obstacles,
) -> Option<(Item, Bounds)> {
    let mut entries: Vec<(Option<(PointKind, u64)>, &str)> = Vec::new();
    for kind in PointKind::ALL {
        // A kind is listed if its marker shows: combinations with violations are
        // drawn as crosses only.
        let shows = |p: &ChartPoint| {
            p.kind == kind && (p.violations == 0 || kind != PointKind::Combination)
        };
        if visible.iter().any(|&i| shows(&points[i])) {
            entries.push((Some((kind, 0)), kind.name()));
        }
    }
    if visible.iter().any(|&i| points[i].violations > 0) {
        entries.push((Some((PointKind::Combination, 1)), "with violations"));
    }
    if has_front {
        entries.push((None, "Pareto front (0 violations)"));
    }
    if entries.is_empty() {
        return None;
    }

    let row = 16.0;
    let text_w = entries
        .iter()
        .map(|(_, t)| text_size(t, SMALL_SCALE).0)
        .fold(0.0, f64::max);
    let (lw, lh) = (
        (8.0 + 24.0 + 6.0 + text_w + 10.0).round(),
        8.0 + row * entries.len() as f64,
    );
    let inset = 8.0;
    // Corners in order of preference; the area above-left of the front is empty by
    // definition, so the top-left corner usually wins.
    let corners = [
        (plot.x0 + inset, plot.y0 + inset),
        (plot.x1 - inset - lw, plot.y0 + inset),
        (plot.x1 - inset - lw, plot.y1 - inset - lh),
        (plot.x0 + inset, plot.y1 - inset - lh),
    ];
    let mut best: Option<(f64, Bounds)> = None;
    for (x, y) in corners {
        let b = Bounds::new(x.round(), y.round(), lw, lh);
        let c = obstacles.cost(&b, None, 4.0);
        if best.is_none_or(|(bc, _)| c < bc) {
            best = Some((c, b));
        }
    }
    let (_, b) = best?;

    let mut items = vec![Item::Rect {
        x: b.x0 + 0.5,
        y: b.y0 + 0.5,
        w: lw,
        h: lh,
        fill: Some(WHITE),
        opacity: 0.9,
        stroke: Some(Stroke {
            color: Color::hex(0xBBBBBB),
            width: 1.0,
        }),
    }];
    for (k, (sample, label)) in entries.iter().enumerate() {
        let cy = b.y0 + 4.0 + row * (k as f64 + 0.5);
        let sx = b.x0 + 8.0 + 12.0;
        match sample {
            Some((kind, violations)) => marker_items(*kind, *violations, sx, cy, &mut items),
            None => items.push(line((sx - 11.0, cy), (sx + 11.0, cy), FRONT, 2.5)),
        }
        let ty = (cy - f64::from(font::CAP_HEIGHT * SMALL_SCALE) / 2.0).round();
        items.push(text(b.x0 + 8.0 + 24.0 + 6.0, ty, *label, SMALL_SCALE, INK));
    }
    Some((
        Item::Group {
            class: "legend",
            tooltip: None,
            items,
        },
        b,
    ))
}

/// A point's label, placed greedily: the candidate spot (east, west, the diagonals,
/// north, south; at growing distances) with the least weighted overlap of labels
/// already placed and the legend (`taken`), other markers and the front line, plus a
/// penalty per step of distance; joined to the point by a leader line when pushed
/// away. Nothing is drawn if no spot fits inside the plot.
fn label(
    text_in: &str,
    p: &Placed,
    plot: &Bounds,
    obstacles: &Obstacles,
    taken: &mut Vec<Bounds>,
) -> Option<Item> {
    let label = shorten(text_in, MAX_LABEL_CHARS);
    if label.is_empty() {
        return None;
    }
    let (tw, th) = text_size(&label, SMALL_SCALE);
    let own = Bounds::around(p.x, p.y, p.r);
    let area = plot.grow(-2.0);
    let mut best: Option<(f64, Bounds, usize)> = None;
    for level in 0..4 {
        let gap = p.r + 2.0 + 14.0 * level as f64;
        let diagonal = gap * 0.7;
        let (cx, cy) = (p.x, p.y - th / 2.0 + 1.0);
        let candidates = [
            (cx + gap, cy),
            (cx - gap - tw, cy),
            (cx + diagonal, cy - diagonal - th / 2.0),
            (cx + diagonal, cy + diagonal + th / 2.0),
            (cx - diagonal - tw, cy - diagonal - th / 2.0),
            (cx - diagonal - tw, cy + diagonal + th / 2.0),
            (cx - tw / 2.0, cy - gap - th / 2.0),
            (cx - tw / 2.0, cy + gap + th / 2.0),
        ];
        for (x, y) in candidates {
            let b = Bounds::new(x.round(), y.round(), tw, th).grow(1.0);
            if !b.inside(&area) {
                continue;
            }
            let c = taken.iter().map(|t| b.overlap(t)).sum::<f64>() * 20.0
                + obstacles.cost(&b, Some(&own), 3.0)
                + 60.0 * level as f64;
            if best.is_none_or(|(bc, _, _)| c < bc) {
                best = Some((c, b, level));
            }
        }
    }
    let (_, b, level) = best?;
    taken.push(b.grow(1.0));
    let mut items = Vec::new();
    if level > 0 {
        // Leader from the marker's edge to the nearest point of the label box.
        let (nx, ny) = (p.x.clamp(b.x0, b.x1), p.y.clamp(b.y0, b.y1));
        let (dx, dy) = (nx - p.x, ny - p.y);
        let d = (dx * dx + dy * dy).sqrt().max(1e-9);
        let start = (p.x + dx / d * (p.r - 1.0), p.y + dy / d * (p.r - 1.0));
        items.push(line(start, (nx, ny), LEADER, 1.0));
    }
    items.push(Item::Rect {
        x: b.x0,
        y: b.y0,
        w: b.x1 - b.x0,
        h: b.y1 - b.y0,
        fill: Some(WHITE),
        opacity: 0.75,
        stroke: None,
    });
    items.push(text(b.x0 + 1.0, b.y0 + 1.0, label, SMALL_SCALE, INK));
    Some(Item::Group {
        class: "label",
        tooltip: None,
        items,
    })
}

/// Title, caption and axis labels, each at the largest scale that fits.
fn titles(spec: &ChartSpec, caption: &str, plot: &Bounds, w: f64, h: f64) -> Vec<Item> {
    let mut items = Vec::new();
    let (title, ts) = fit(spec.title, TITLE_SCALE, w - 24.0);
    let tw = text_size(&title, ts).0;
    items.push(text(((w - tw) / 2.0).round(), TITLE_Y, title, ts, INK));
    let (caption, cs) = fit(caption, SMALL_SCALE, w - 24.0);
    let cw = text_size(&caption, cs).0;
    items.push(text(
        ((w - cw) / 2.0).round(),
        CAPTION_Y,
        caption,
        cs,
        MUTED,
    ));
    let (xl, xs) = fit(spec.x_label, AXIS_LABEL_SCALE, plot.x1 - plot.x0);
    let xw = text_size(&xl, xs).0;
    let xy = h - 10.0 - f64::from(font::HEIGHT * xs);
    items.push(text(
        ((plot.x0 + plot.x1 - xw) / 2.0).round(),
        xy,
        xl,
        xs,
        INK,
    ));
    let (yl, ys) = fit(spec.y_label, AXIS_LABEL_SCALE, plot.y1 - plot.y0);
    let yh = text_size(&yl, ys).0;
    items.push(Item::Text {
        x: 12.0,
        y: ((plot.y0 + plot.y1 - yh) / 2.0).round(),
        text: yl,
        scale: ys,
        color: INK,
        vertical: true,
    });
    items
}

/// The SVG tooltip of a point.
fn tooltip(p: &ChartPoint, on_front: bool) -> String {
    format!(
        "{} ({}): deviation {:.4} radii, speed-up {:.3}x, {} violation{}{}",
        p.label,
        p.kind.name(),
        p.deviation,
        p.speedup,
        p.violations,
        if p.violations == 1 { "" } else { "s" },
        if on_front {
            ", on the Pareto front"
        } else {
            ""
        }
    )
}

/// The line under the title: counts, so that left-out points are not silent.
fn caption(points: &[ChartPoint], visible: &[usize], front: &[usize]) -> String {
    let violating = visible
        .iter()
        .filter(|&&i| points[i].violations > 0)
        .count();
    let mut s = format!(
        "{} configurations, {} with violations, {} on the front",
        visible.len(),
        violating,
        front.len()
    );
    let skipped = points.len() - visible.len();
    if skipped > 0 {
        s.push_str(&format!(
            ", {skipped} not drawn (not finite / not > 0 on a log axis)"
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ticks_use_1_2_5_steps() {
        let (t, d) = nice_ticks(0.0, 1.0, 5);
        assert_eq!(t, vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]);
        assert_eq!(d, 1);
        let (t, d) = nice_ticks(-0.04, 2.3, 6);
        let labels: Vec<String> = t.iter().map(|&v| fmt_fixed(v, d)).collect();
        assert_eq!(labels, ["0.0", "0.5", "1.0", "1.5", "2.0"]);
        let (t, d) = nice_ticks(-3.0, 1200.0, 5);
        assert_eq!((t[0], t.len(), d), (0.0, 7, 0));
    }

    #[test]
    fn log_ticks_pick_decades_or_finer() {
        let (major, minor, labels) = log_ticks(0.2, 50.0, 6);
        assert_eq!(labels, ["0.2", "0.5", "1", "2", "5", "10", "20", "50"]);
        assert_eq!(major.len(), 8);
        assert!(!minor.is_empty());
        let (_, _, labels) = log_ticks(0.05, 2000.0, 6);
        assert_eq!(labels, ["0.1", "1", "10", "100", "1000"]);
        let (_, _, labels) = log_ticks(1.1, 1.9, 6);
        assert!(labels.len() >= 2, "{labels:?}");
        assert_eq!(fmt_power(1, 7), "1e7");
        assert_eq!(tick_label(2e150, 0), "2.00e150");
        assert_eq!(tick_label(3e-9, 9), "3.00e-9");
        assert_eq!(tick_label(0.0, 9), "0");
        assert_eq!(fmt_fixed(-0.0001, 2), "0.00");
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(widen(0.0, 0.0), (0.0, 1.0));
        assert_eq!(widen(2.0, 2.0), (1.0, 3.0));
        let a = Axis::log(3.0, 3.0, 6);
        assert!(a.lo < 3.0 && a.hi > 3.0 && a.major.len() >= 2);
    }
}
