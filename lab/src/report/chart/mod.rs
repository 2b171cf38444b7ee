//! The chart drawn with plotters: from points and a [`ChartSpec`] to any plotters back
//! end (SVG text or an RGB bitmap).
//!
//! plotters provides the coordinate system, the mesh (grid, ticks, tick labels, axis
//! descriptions), the elements (paths, circles, polygons, rectangles, text) and the
//! legend box; this module decides *what* goes where. [`draw`] picks the drawable points
//! and the front, then draws back to front: title and caption, the mesh and frame with
//! margins sized from the tick labels (`layout.rs`), on axes with "nice" ticks
//! (`axis.rs`); the equivalence band, the front's step line and the markers (`series.rs`,
//! `marker.rs`); the legend in the plot corner it covers least (`legend.rs`) and the
//! labels placed greedily around what they would cover (`place.rs`). Colours and sizes
//! are in `palette.rs`.
//!
//! Cost: O(n log n) for n points to order the markers, and O(n²) at most to place the
//! labels (each against the markers and labels placed before it).

mod axis;
mod layout;
mod legend;
mod marker;
mod palette;
mod place;
mod series;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{pareto_front, ChartPoint, ChartSpec};
use axis::{Axes, Axis};
use palette::LIMIT;
use place::Obstacles;

// What the report's tests read of the chart.
#[cfg(test)]
pub(crate) use marker::style;
#[cfg(test)]
pub(crate) use palette::VIOLATION;

/// The chart's coordinate system: one linear axis per direction (a log axis is linear
/// over the logs, see `axis.rs`).
type Coords = Cartesian2d<Axis, Axis>;

/// An axis-aligned box in pixels, for collision tests (its methods in `place.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bounds {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

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

    let caption = layout::caption(points, &visible, &front);
    let top = layout::headings(root, spec, &caption, w)?;
    let band = spec
        .band
        .filter(|b| b.is_finite() && *b > 0.0 && *b < LIMIT);
    let axes = Axes::new(points, &visible, spec.log_y, band, w, h);
    let (mut chart, plot) = layout::frame(root, spec, &axes, top, (w, h))?;
    if let Some(b) = band {
        series::band(root, &mut chart, &axes, b)?;
    }
    let steps = series::front_steps(points, &front, &axes);
    let has_front = steps.len() >= 2;
    if has_front {
        series::front_line(&mut chart, &steps)?;
    }
    let placed = series::markers(&mut chart, points, &visible, &front, &axes)?;

    // The legend and the labels, around what they should not cover.
    let obstacles = Obstacles::new(&placed, &series::to_pixels(&chart, &steps));
    let mut taken = Vec::new();
    if let Some(b) = legend::legend(&mut chart, points, &visible, has_front, &plot, &obstacles)? {
        taken.push(b);
    }
    for i in place::to_label(points, &visible, &front) {
        if let Some(p) = placed.iter().find(|p| p.index == i) {
            place::label(root, &points[i].label, p, &plot, &obstacles, &mut taken)?;
        }
    }

    if visible.is_empty() {
        layout::no_data(root, &plot)?;
    }
    Ok(())
}
