//! The chart's layout: title and caption, the margins the tick labels and axis
//! descriptions need, the mesh (grid, ticks, labels) and frame, and the "no data" note.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axes;
use super::palette::{
    AXIS_LABEL_SIZE, FRAME, GRID_MAJOR, GRID_MINOR, INK, MIN_SIZE, MUTED, SMALL_SIZE, TICK_LEN,
    TICK_SIZE, TITLE_SIZE, TITLE_Y,
};
use super::{Bounds, Coords};
use crate::report::{text, ChartPoint, ChartSpec};

/// Draws the title and the caption under it, centred on width `w`; returns the top of
/// the plot area below them.
pub(super) fn headings<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    spec: &ChartSpec,
    caption_text: &str,
    w: f64,
) -> Result<f64, DrawingAreaErrorKind<DB::ErrorType>> {
    let (title, title_size) = text::fit(&text::clean(spec.title), TITLE_SIZE, MIN_SIZE, w - 24.0);
    let caption_y = TITLE_Y + text::height(title_size) + 6.0;
    let (caption, caption_size) = text::fit(caption_text, SMALL_SIZE, MIN_SIZE, w - 24.0);
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
    Ok((caption_y + text::height(caption_size) + 12.0).round())
}

/// The line under the title: counts, so that left-out points are not silent.
pub(super) fn caption(points: &[ChartPoint], visible: &[usize], front: &[usize]) -> String {
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

/// The margins around the plot area (label areas: tick marks, tick labels, gap, axis
/// description; then outer margins) and the axis descriptions fitted to them.
struct Margins {
    top: f64,
    left: f64,
    bottom: f64,
    right: f64,
    outer_left: f64,
    outer_bottom: f64,
    x_desc: String,
    y_desc: String,
    /// The descriptions' common font size.
    desc_size: f64,
}

impl Margins {
    fn new(spec: &ChartSpec, axes: &Axes, top: f64, w: f64, h: f64) -> Margins {
        let tick_w = axes
            .y
            .labels
            .iter()
            .map(|l| text::width(l, TICK_SIZE))
            .fold(0.0, f64::max);
        let axis_h = text::height(AXIS_LABEL_SIZE);
        let tick_h = text::height(TICK_SIZE);
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
        Margins {
            top,
            left,
            bottom,
            right,
            outer_left,
            outer_bottom,
            x_desc,
            y_desc,
            desc_size: x_desc_size.min(y_desc_size),
        }
    }
}

/// The chart with its mesh and frame drawn, and the plot area's pixel bounds.
type Framed<'a, DB> = (ChartContext<'a, DB, Coords>, Bounds);

/// Builds the chart on `root` below `top` (`w` × `h` pixels), draws its mesh and frame;
/// returns it with the plot area's pixel bounds.
pub(super) fn frame<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    spec: &ChartSpec,
    axes: &Axes,
    top: f64,
    (w, h): (f64, f64),
) -> Result<Framed<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let m = Margins::new(spec, axes, top, w, h);
    let mut chart = ChartBuilder::on(root)
        .margin_top(m.top as i32)
        .margin_right(m.right as i32)
        .margin_left(m.outer_left as i32)
        .margin_bottom(m.outer_bottom as i32)
        .x_label_area_size(m.bottom as i32)
        .y_label_area_size(m.left as i32)
        .build_cartesian_2d(axes.x.clone(), axes.y.clone())?;
    let mut mesh = chart.configure_mesh();
    mesh.label_style(text::font(TICK_SIZE).color(&INK))
        .axis_desc_style(text::font(AXIS_LABEL_SIZE).color(&INK))
        .bold_line_style(GRID_MAJOR.stroke_width(1))
        .light_line_style(GRID_MINOR.stroke_width(1))
        .axis_style(FRAME.stroke_width(1))
        .set_all_tick_mark_size(TICK_LEN);
    if !m.x_desc.is_empty() {
        mesh.x_desc(m.x_desc)
            .axis_desc_style(text::font(m.desc_size).color(&INK));
    }
    if !m.y_desc.is_empty() {
        mesh.y_desc(m.y_desc)
            .axis_desc_style(text::font(m.desc_size).color(&INK));
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
    Ok((chart, plot))
}

/// "no data" in the middle of the plot area.
pub(super) fn no_data<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &Bounds,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (cx, cy) = ((plot.x0 + plot.x1) / 2.0, (plot.y0 + plot.y1) / 2.0);
    let style = text::font(TITLE_SIZE)
        .color(&MUTED)
        .pos(Pos::new(HPos::Center, VPos::Center));
    root.draw(&Text::new("no data", (cx as i32, cy as i32), style))
}
