//! What is drawn in data coordinates, back to front: the equivalence band, the Pareto
//! front's step line and the points' markers.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axes;
use super::marker::{style, Marker};
use super::palette::{BAND, BAND_EDGE, FRONT, SMALL_SIZE};
use super::place::Placed;
use super::Coords;
use crate::report::{text, ChartPoint};

/// The equivalence band behind everything else: x from the axis' start to `band`.
pub(super) fn band<'a, DB: DrawingBackend + 'a>(
    root: &DrawingArea<DB, Shift>,
    chart: &mut ChartContext<'a, DB, Coords>,
    axes: &Axes,
    band: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    // Drawing space: the axes' `place` pins to their ends.
    let ((x0, _), (y0, y1)) = (axes.x.span(), axes.y.span());
    let x1 = axes.x.place(band);
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
    Ok(())
}

/// The front as a step line in drawing space: from each point right to the next one's
/// deviation, then up to its speed-up (the best speed-up available at that accuracy).
pub(super) fn front_steps(points: &[ChartPoint], front: &[usize], axes: &Axes) -> Vec<(f64, f64)> {
    let mut steps: Vec<(f64, f64)> = Vec::new();
    for &i in front {
        let (x, y) = axes.at(&points[i]);
        if let Some(&(_, previous_y)) = steps.last() {
            steps.push((x, previous_y));
        }
        steps.push((x, y));
    }
    steps
}

/// Draws the front's step line.
pub(super) fn front_line<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Coords>,
    steps: &[(f64, f64)],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart.draw_series(std::iter::once(PathElement::new(
        steps.to_vec(),
        FRONT.stroke_width(3),
    )))?;
    Ok(())
}

/// Draws the visible points' markers, violations first, the rest next, special
/// configurations last (on top); returns them in pixels, in drawing order.
pub(super) fn markers<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Coords>,
    points: &[ChartPoint],
    visible: &[usize],
    front: &[usize],
    axes: &Axes,
) -> Result<Vec<Placed>, DrawingAreaErrorKind<DB::ErrorType>> {
    let layer = |p: &ChartPoint| match (p.kind.is_special(), p.violations > 0) {
        (true, _) => 2,
        (false, true) => 0,
        (false, false) => 1,
    };
    let mut order = visible.to_vec();
    order.sort_by_key(|&i| (layer(&points[i]), i));
    chart.draw_series(order.iter().map(|&i| {
        let p = &points[i];
        Marker::new(axes.at(p), p.kind, p.violations, front.contains(&i))
    }))?;
    Ok(order
        .iter()
        .map(|&i| {
            let (x, y) = chart.backend_coord(&axes.at(&points[i]));
            Placed {
                index: i,
                x: f64::from(x),
                y: f64::from(y),
                r: style(points[i].kind).2 + 2.0,
            }
        })
        .collect())
}

/// `steps` (drawing space) in pixels.
pub(super) fn to_pixels<'a, DB: DrawingBackend + 'a>(
    chart: &ChartContext<'a, DB, Coords>,
    steps: &[(f64, f64)],
) -> Vec<(f64, f64)> {
    steps
        .iter()
        .map(|s| {
            let (x, y) = chart.backend_coord(s);
            (f64::from(x), f64::from(y))
        })
        .collect()
}
