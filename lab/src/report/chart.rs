//! The chart drawn with plotters: from points and a [`ChartSpec`] to any plotters
//! back end (SVG text or an RGB bitmap).
//!
//! plotters provides the coordinate system, the mesh (grid, ticks, tick labels, axis
//! descriptions), the elements (paths, circles, polygons, rectangles, text) and the
//! legend box; this module decides *what* goes where. Steps of [`draw`]: pick the
//! drawable points; compute the front; choose axis ranges (padded data range, widened
//! when degenerate) and "nice" ticks (1-2-5 steps; decades on a log axis), handed to
//! plotters as fixed key points; size the margins from the tick labels; then draw, back
//! to front: mesh and frame, the front's step line, the markers (violations first,
//! special configurations last), the legend (in the plot corner it covers least), the
//! labels (greedy placement), title and caption.
//!
//! A log axis is drawn as a linear axis over log₁₀ of the values, its ticks at the
//! logs of 1-2-5 values and labelled with the values: the tick choice stays ours
//! (plotters' own log key points are sparse on short ranges) and both axes have one
//! coordinate type.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendCoord, DrawingErrorKind};

use super::text;
use super::{pareto_front, ChartPoint, ChartSpec, PointKind};

const INK: RGBColor = RGBColor(0x22, 0x22, 0x22);
const MUTED: RGBColor = RGBColor(0x66, 0x66, 0x66);
const FRAME: RGBColor = RGBColor(0x44, 0x44, 0x44);
const GRID_MAJOR: RGBColor = RGBColor(0xDD, 0xDD, 0xDD);
const GRID_MINOR: RGBColor = RGBColor(0xF0, 0xF0, 0xF0);
/// The Pareto front's line and rings.
pub(crate) const FRONT: RGBColor = RGBColor(0xFF, 0x7F, 0x0E);
/// The cross marking a point with violations.
pub(crate) const VIOLATION: RGBColor = RGBColor(0xD6, 0x27, 0x28);
/// The equivalence band's fill (green, drawn at 35 % over the grid) and its edge.
const BAND: RGBColor = RGBColor(0x9C, 0xD8, 0x90);
const BAND_EDGE: RGBColor = RGBColor(0x2C, 0x8A, 0x2C);
const LEADER: RGBColor = RGBColor(0x99, 0x99, 0x99);
const LEGEND_BORDER: RGBColor = RGBColor(0xBB, 0xBB, 0xBB);

// Font sizes (plotters' sizes: about ascender-to-descender in pixels).
const TITLE_SIZE: f64 = 24.0;
const AXIS_LABEL_SIZE: f64 = 19.0;
const TICK_SIZE: f64 = 17.0;
const SMALL_SIZE: f64 = 15.0;
/// The points' labels: smaller than the legend's, there are many.
const LABEL_SIZE: f64 = 13.5;
/// No text is set smaller than this; what does not fit is cut with "...".
const MIN_SIZE: f64 = 10.0;
/// Labels longer than this are shortened with "...".
const MAX_LABEL_CHARS: usize = 40;
/// Largest magnitude an axis reaches (smallest positive value on a log axis: its
/// inverse).
const LIMIT: f64 = 1e150;
/// Top of the title.
const TITLE_Y: f64 = 10.0;
/// Length of the tick marks outside the frame.
const TICK_LEN: i32 = 5;

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
    fn new(at: C, kind: PointKind, violations: u64, on_front: bool) -> Self {
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

/// The chart's coordinate system: one linear axis per direction (see the module docs
/// for the log axis).
type Coords = Cartesian2d<Axis, Axis>;

/// Draws the chart of `points` onto `root`, which must be `spec`'s size after
/// clamping. Stops at the first error of the back end (none is expected: the SVG
/// back end writes to a string, the bitmap one to memory); nothing here panics on
/// data.
pub(crate) fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    points: &[ChartPoint],
    spec: &ChartSpec,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, height) = root.dim_in_pixel();
    let (w, h) = (f64::from(width), f64::from(height));
    root.fill(&WHITE)?;

    let drawable = |p: &ChartPoint| p.is_finite() && (!spec.log_y || p.speedup > 0.0);
    let visible: Vec<usize> = (0..points.len())
        .filter(|&i| drawable(&points[i]))
        .collect();
    let front: Vec<usize> = pareto_front(points, true)
        .into_iter()
        .filter(|&i| drawable(&points[i]))
        .collect();

    // Title and the caption under it.
    let (title, title_size) = text::fit(&text::clean(spec.title), TITLE_SIZE, MIN_SIZE, w - 24.0);
    let caption_y = TITLE_Y + text::height(title_size) + 6.0;
    let (caption, caption_size) = text::fit(
        &caption(points, &visible, &front),
        SMALL_SIZE,
        MIN_SIZE,
        w - 24.0,
    );
    let centred = |size: f64, color: &RGBColor| {
        text::font(size)
            .color(color)
            .pos(Pos::new(HPos::Center, VPos::Top))
    };
    let mid = (w / 2.0).round() as i32;
    if !title.is_empty() {
        root.draw(&Text::new(
            title,
            (mid, TITLE_Y as i32),
            centred(title_size, &INK),
        ))?;
    }
    root.draw(&Text::new(
        caption,
        (mid, caption_y as i32),
        centred(caption_size, &MUTED),
    ))?;

    // Axes, and the margins their text needs.
    let band = spec
        .band
        .filter(|b| b.is_finite() && *b > 0.0 && *b < LIMIT);
    let (x_axis, y_axis) = axes(points, &visible, spec.log_y, band, w, h);
    let tick_w = y_axis
        .labels
        .iter()
        .map(|l| text::width(l, TICK_SIZE))
        .fold(0.0, f64::max);
    let axis_h = text::height(AXIS_LABEL_SIZE);
    let tick_h = text::height(TICK_SIZE);
    let top = (caption_y + text::height(caption_size) + 12.0).round();
    // Label areas (tick marks, tick labels, gap, axis description), and outer margins.
    let (outer_left, outer_bottom, right) = (10.0, 8.0, 24.0);
    let left = (axis_h + 10.0 + tick_w + 8.0 + f64::from(TICK_LEN)).round();
    let bottom = (f64::from(TICK_LEN) + 6.0 + tick_h + 8.0 + axis_h).round();
    let (x_desc, x_desc_size) = text::fit(
        &text::clean(spec.x_label),
        AXIS_LABEL_SIZE,
        MIN_SIZE,
        (w - outer_left - left - right).max(1.0),
    );
    let (y_desc, y_desc_size) = text::fit(
        &text::clean(spec.y_label),
        AXIS_LABEL_SIZE,
        MIN_SIZE,
        (h - top - bottom - outer_bottom).max(1.0),
    );

    let mut chart = ChartBuilder::on(root)
        .margin_top(top as i32)
        .margin_right(right as i32)
        .margin_left(outer_left as i32)
        .margin_bottom(outer_bottom as i32)
        .x_label_area_size(bottom as i32)
        .y_label_area_size(left as i32)
        .build_cartesian_2d(x_axis.clone(), y_axis.clone())?;
    let mut mesh = chart.configure_mesh();
    mesh.label_style(text::font(TICK_SIZE).color(&INK))
        .axis_desc_style(text::font(AXIS_LABEL_SIZE).color(&INK))
        .bold_line_style(GRID_MAJOR.stroke_width(1))
        .light_line_style(GRID_MINOR.stroke_width(1))
        .axis_style(FRAME.stroke_width(1))
        .set_all_tick_mark_size(TICK_LEN);
    if !x_desc.is_empty() {
        mesh.x_desc(x_desc)
            .axis_desc_style(text::font(x_desc_size.min(y_desc_size)).color(&INK));
    }
    if !y_desc.is_empty() {
        mesh.y_desc(y_desc)
            .axis_desc_style(text::font(x_desc_size.min(y_desc_size)).color(&INK));
    }
    mesh.draw()?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let plot = Bounds {
        x0: f64::from(xs.start),
        y0: f64::from(ys.start),
        x1: f64::from(xs.end),
        y1: f64::from(ys.end),
    };
    root.draw(&Rectangle::new(
        [(xs.start, ys.start), (xs.end - 1, ys.end - 1)],
        FRAME.stroke_width(1),
    ))?;

    // The equivalence band behind everything else: x from the axis' start to `band`.
    if let Some(b) = band {
        // Drawing space: the axes' `place` pins to their ends.
        let ((x0, _), (y0, y1)) = (x_axis.span(), y_axis.span());
        let x1 = x_axis.place(b);
        if x1 > x0 {
            let corners = [(x0, y1), (x1, y0)];
            chart.draw_series(std::iter::once(Rectangle::new(
                corners,
                BAND.mix(0.35).filled(),
            )))?;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x1, y0), (x1, y1)],
                BAND_EDGE.stroke_width(2),
            )))?;
            let (px, py) = chart.backend_coord(&(x1, y0.max(y1)));
            root.draw(&Text::new(
                "equivalent",
                (px - 4, py + 4),
                text::font(SMALL_SIZE)
                    .color(&BAND_EDGE)
                    .pos(Pos::new(HPos::Right, VPos::Top)),
            ))?;
        }
    }

    // The front as a step line: from each point right to the next one's deviation,
    // then up to its speed-up (the best speed-up available at that accuracy).
    let at = |i: usize| {
        (
            x_axis.place(points[i].deviation),
            y_axis.place(points[i].speedup),
        )
    };
    let mut steps: Vec<(f64, f64)> = Vec::new();
    for &i in &front {
        let (x, y) = at(i);
        if let Some(&(_, previous_y)) = steps.last() {
            steps.push((x, previous_y));
        }
        steps.push((x, y));
    }
    let has_front = steps.len() >= 2;
    if has_front {
        chart.draw_series(std::iter::once(PathElement::new(
            steps.clone(),
            FRONT.stroke_width(3),
        )))?;
    }

    // Markers, in drawing order: violations, then the rest, specials last (on top).
    let layer = |p: &ChartPoint| match (p.kind.is_special(), p.violations > 0) {
        (true, _) => 2,
        (false, true) => 0,
        (false, false) => 1,
    };
    let mut order = visible.clone();
    order.sort_by_key(|&i| (layer(&points[i]), i));
    chart.draw_series(order.iter().map(|&i| {
        let p = &points[i];
        Marker::new(at(i), p.kind, p.violations, front.contains(&i))
    }))?;
    let placed: Vec<Placed> = order
        .iter()
        .map(|&i| {
            let (x, y) = chart.backend_coord(&at(i));
            Placed {
                index: i,
                x: f64::from(x),
                y: f64::from(y),
                r: style(points[i].kind).2 + 2.0,
            }
        })
        .collect();
    let front_px: Vec<(f64, f64)> = steps
        .iter()
        .map(|s| {
            let (x, y) = chart.backend_coord(s);
            (f64::from(x), f64::from(y))
        })
        .collect();

    // What the legend and the labels should not cover.
    let obstacles = Obstacles::new(&placed, &front_px);
    let mut taken = Vec::new();
    if let Some(b) = legend(&mut chart, points, &visible, has_front, &plot, &obstacles)? {
        taken.push(b);
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
            label(root, &points[i].label, p, &plot, &obstacles, &mut taken)?;
        }
    }

    if visible.is_empty() {
        let (cx, cy) = ((plot.x0 + plot.x1) / 2.0, (plot.y0 + plot.y1) / 2.0);
        let style = text::font(TITLE_SIZE)
            .color(&MUTED)
            .pos(Pos::new(HPos::Center, VPos::Center));
        root.draw(&Text::new("no data", (cx as i32, cy as i32), style))?;
    }
    Ok(())
}

/// Axis ranges and ticks for the visible points, about one labelled tick per 110 px
/// across and per 70 px up.
fn axes(
    points: &[ChartPoint],
    visible: &[usize],
    log_y: bool,
    band: Option<f64>,
    w: f64,
    h: f64,
) -> (Axis, Axis) {
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
    // The band's edge stays in view, with a little room beyond it.
    let x_hi = band.map_or(x_hi, |b| x_hi.max(b * 1.15));
    let x = Axis::linear(x_lo.min(0.0), x_hi.max(0.0), x_target);
    let y = if log_y {
        let (lo, hi) = min_max(&|p| p.speedup.clamp(1.0 / LIMIT, LIMIT)).unwrap_or((1.0, 10.0));
        Axis::log(lo, hi, y_target)
    } else {
        let (lo, hi) = min_max(&|p| p.speedup.clamp(-LIMIT, LIMIT)).unwrap_or((0.0, 1.0));
        Axis::linear(lo.min(0.0), hi.max(0.0), y_target)
    };
    (x, y)
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

/// The legend (kinds shown, violations, front) through plotters' series labels, in
/// the plot corner it covers least; returns its box, `None` if there is nothing to
/// explain.
fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Coords>,
    points: &[ChartPoint],
    visible: &[usize],
    has_front: bool,
    plot: &Bounds,
    obstacles: &Obstacles,
) -> Result<Option<Bounds>, DrawingAreaErrorKind<DB::ErrorType>> {
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
        return Ok(None);
    }

    // The box plotters will draw: the lines' block, the symbol column, margins.
    let label_style = text::font(SMALL_SIZE).color(&INK);
    let mut block = MultiLineText::<_, &str>::new((0, 0), &label_style);
    for (_, name) in &entries {
        block.push_line(*name);
    }
    let (tw, th) = block
        .estimate_dimension()
        .unwrap_or((200, 18 * entries.len() as i32));
    const SYMBOLS: i32 = 30;
    const MARGIN: i32 = 6;
    let (lw, lh) = (
        f64::from(tw + SYMBOLS + 2 * MARGIN),
        f64::from(th + 2 * MARGIN),
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
    let Some((_, b)) = best else {
        return Ok(None);
    };

    // Legend-only series, in legend order; plotters draws their symbols at the
    // left margin of the box: shifted right to the middle of the symbol column.
    for (sample, name) in entries {
        let anno = chart.draw_series(std::iter::empty::<Marker<(f64, f64)>>())?;
        let anno = anno.label(name);
        match sample {
            Some((kind, violations)) => anno.legend(move |(x, y)| {
                Marker::new((x + SYMBOLS / 2 - MARGIN, y), kind, violations, false).into_dyn()
            }),
            None => anno.legend(|(x, y)| {
                let x = x + SYMBOLS / 2 - MARGIN;
                PathElement::new(vec![(x - 11, y), (x + 11, y)], FRONT.stroke_width(3)).into_dyn()
            }),
        };
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::Coordinate(
            (b.x0 - plot.x0) as i32,
            (b.y0 - plot.y0) as i32,
        ))
        .legend_area_size(SYMBOLS)
        .margin(MARGIN)
        .label_font(label_style.clone())
        .background_style(WHITE.mix(0.9))
        .border_style(LEGEND_BORDER)
        .draw()?;
    Ok(Some(b))
}

/// A point's label, placed greedily: the candidate spot (east, west, the diagonals,
/// north, south; at growing distances) with the least weighted overlap of labels
/// already placed and the legend (`taken`), other markers and the front line, plus a
/// penalty per step of distance; joined to the point by a leader line when pushed
/// away. Nothing is drawn if no spot fits inside the plot.
fn label<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text_in: &str,
    p: &Placed,
    plot: &Bounds,
    obstacles: &Obstacles,
    taken: &mut Vec<Bounds>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let label = text::shorten(&text::clean(text_in), MAX_LABEL_CHARS);
    if label.is_empty() {
        return Ok(());
    }
    let (tw, th) = (
        text::width(&label, LABEL_SIZE).ceil() + 2.0,
        text::height(LABEL_SIZE) + 2.0,
    );
    let own = Bounds::around(p.x, p.y, p.r);
    let area = plot.grow(-2.0);
    let mut best: Option<(f64, Bounds, usize)> = None;
    for level in 0..4 {
        let gap = p.r + 2.0 + 14.0 * level as f64;
        let diagonal = gap * 0.7;
        let (cx, cy) = (p.x, p.y - th / 2.0);
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
            let b = Bounds::new(x.round(), y.round(), tw, th);
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
    let Some((_, b, level)) = best else {
        return Ok(());
    };
    taken.push(b.grow(1.0));
    if level > 0 {
        // Leader from the marker's edge to the nearest point of the label box.
        let (nx, ny) = (p.x.clamp(b.x0, b.x1), p.y.clamp(b.y0, b.y1));
        let (dx, dy) = (nx - p.x, ny - p.y);
        let d = (dx * dx + dy * dy).sqrt().max(1e-9);
        let start = (p.x + dx / d * (p.r - 1.0), p.y + dy / d * (p.r - 1.0));
        root.draw(&PathElement::new(
            vec![
                (start.0.round() as i32, start.1.round() as i32),
                (nx.round() as i32, ny.round() as i32),
            ],
            LEADER.stroke_width(1),
        ))?;
    }
    root.draw(&Rectangle::new(
        [(b.x0 as i32, b.y0 as i32), (b.x1 as i32, b.y1 as i32)],
        WHITE.mix(0.75).filled(),
    ))?;
    let style = text::font(LABEL_SIZE)
        .color(&INK)
        .pos(Pos::new(HPos::Left, VPos::Top));
    root.draw(&Text::new(label, (b.x0 as i32 + 1, b.y0 as i32 + 1), style))?;
    Ok(())
}

/// A point that will be drawn, in pixels; `r` is the radius kept clear around it.
struct Placed {
    index: usize,
    x: f64,
    y: f64,
    r: f64,
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

    /// `v` in the axis' drawing space: itself, or its log₁₀ on a log axis.
    fn to_space(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// The ends in drawing space.
    fn span(&self) -> (f64, f64) {
        (self.to_space(self.lo), self.to_space(self.hi))
    }

    /// `v` in drawing space, pinned to the ends (values beyond the axis sit on the
    /// frame).
    fn place(&self, v: f64) -> f64 {
        let (a, b) = self.span();
        self.to_space(v).clamp(a.min(b), a.max(b))
    }

    /// The label of the tick at `v` (drawing space; plotters hands back the key points
    /// it was given), or the nearest tick's.
    fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .zip(&self.labels)
            .min_by(|a, b| {
                (self.to_space(*a.0) - v)
                    .abs()
                    .total_cmp(&(self.to_space(*b.0) - v).abs())
            })
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    }
}

/// An axis is a plotters coordinate over its drawing space: the labelled ticks are its
/// bold key points, the unlabelled ones its light (grid-only) points.
impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        // As plotters' own f64 coordinate, with non-finite fractions pinned.
        let (a, b) = self.span();
        let fraction = (v - a) / (b - a);
        let length = limit.1 - limit.0;
        if !fraction.is_finite() || length == 0 {
            return if fraction.is_sign_negative() {
                limit.0
            } else {
                limit.1
            };
        }
        limit.0 + (f64::from(length) * fraction + 1e-3).floor() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let points = if hint.weight().allow_light_points() {
            &self.minor
        } else {
            &self.major
        };
        points.iter().map(|&v| self.to_space(v)).collect()
    }

    fn range(&self) -> std::ops::Range<f64> {
        let (a, b) = self.span();
        a..b
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(v: &f64) -> String {
        format!("{v}")
    }

    fn format_ext(&self, v: &f64) -> String {
        self.label(*v)
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
        // Drawn in log space, labelled with the values.
        let (lo, hi) = a.span();
        assert!(a.place(3.0) > lo && a.place(3.0) < hi);
        assert_eq!(a.place(1e9), hi);
        assert_eq!(a.label(a.to_space(a.major[0])), a.labels[0]);
        assert_eq!(a.range(), lo..hi);
        assert_eq!(a.map(&lo, (10, 110)), 10);
        assert_eq!(a.map(&hi, (10, 110)), 110);
    }
}
