//! The legend: the kinds shown, violations and the front, through plotters' series
//! labels, in the plot corner it covers least.

use plotters::prelude::*;

use super::marker::Marker;
use super::palette::{FRONT, INK, LEGEND_BORDER, SMALL_SIZE};
use super::place::Obstacles;
use super::{Bounds, Coords};
use crate::report::{text, ChartPoint, PointKind};

/// Width of the legend's symbol column, in pixels.
const SYMBOLS: i32 = 30;
/// The legend box's inner margin, in pixels.
const MARGIN: i32 = 6;

/// A legend line: a marker sample (kind, violations) or the front's line (`None`), and
/// its text.
type Entry = (Option<(PointKind, u64)>, &'static str);

/// The legend (kinds shown, violations, front) through plotters' series labels, in
/// the plot corner it covers least; returns its box, `None` if there is nothing to
/// explain.
pub(super) fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Coords>,
    points: &[ChartPoint],
    visible: &[usize],
    has_front: bool,
    plot: &Bounds,
    obstacles: &Obstacles,
) -> Result<Option<Bounds>, DrawingAreaErrorKind<DB::ErrorType>> {
    let entries = entries(points, visible, has_front);
    if entries.is_empty() {
        return Ok(None);
    }
    let label_style = text::font(SMALL_SIZE).color(&INK);
    let Some(b) = corner(&entries, &label_style, plot, obstacles) else {
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

/// The legend's lines: each kind whose marker shows, violations, the front.
fn entries(points: &[ChartPoint], visible: &[usize], has_front: bool) -> Vec<Entry> {
    let mut entries: Vec<Entry> = Vec::new();
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
    entries
}

/// The legend's box in the plot corner where it covers the markers and the front least.
fn corner(
    entries: &[Entry],
    label_style: &TextStyle,
    plot: &Bounds,
    obstacles: &Obstacles,
) -> Option<Bounds> {
    // The box plotters will draw: the lines' block, the symbol column, margins.
    let mut block = MultiLineText::<_, &str>::new((0, 0), label_style);
    for (_, name) in entries {
        block.push_line(*name);
    }
    let (tw, th) = block
        .estimate_dimension()
        .unwrap_or((200, 18 * entries.len() as i32));
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
    best.map(|(_, b)| b)
}
