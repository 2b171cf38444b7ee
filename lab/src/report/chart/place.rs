//! Placing text where it covers the least: boxes, the markers and the front line as
//! obstacles with an overlap cost, and the points' labels placed greedily.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::palette::{INK, LABEL_SIZE, LEADER, MAX_LABEL_CHARS};
use super::Bounds;
use crate::report::{text, ChartPoint};

/// A point that will be drawn, in pixels; `r` is the radius kept clear around it.
pub(super) struct Placed {
    pub(super) index: usize,
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) r: f64,
}

/// Boxes around the markers and along the front line, for collision costs.
pub(super) struct Obstacles {
    markers: Vec<Bounds>,
    front: Vec<Bounds>,
}

impl Obstacles {
    pub(super) fn new(placed: &[Placed], steps: &[(f64, f64)]) -> Obstacles {
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
    pub(super) fn cost(&self, b: &Bounds, own: Option<&Bounds>, marker_weight: f64) -> f64 {
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

/// The points to label, in order: special configurations first, then the rest of the
/// front.
pub(super) fn to_label(points: &[ChartPoint], visible: &[usize], front: &[usize]) -> Vec<usize> {
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
    to_label
}

/// A point's label, placed greedily at the best spot ([`spot`]) and joined to the point
/// by a leader line when pushed away. Nothing is drawn if no spot fits inside the plot.
pub(super) fn label<DB: DrawingBackend>(
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
    let size = (
        text::width(&label, LABEL_SIZE).ceil() + 2.0,
        text::height(LABEL_SIZE) + 2.0,
    );
    let Some((b, level)) = spot(p, size, plot, obstacles, taken) else {
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

/// The best spot for a label of size `(tw, th)` at point `p`, with its distance level:
/// the candidate (east, west, the diagonals, north, south; at growing distances) inside
/// the plot with the least weighted overlap of labels already placed and the legend
/// (`taken`), other markers and the front line, plus a penalty per step of distance.
fn spot(
    p: &Placed,
    (tw, th): (f64, f64),
    plot: &Bounds,
    obstacles: &Obstacles,
    taken: &[Bounds],
) -> Option<(Bounds, usize)> {
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
    best.map(|(_, b, level)| (b, level))
}

/// Boxes for collision tests.
impl Bounds {
    pub(super) fn new(x: f64, y: f64, w: f64, h: f64) -> Bounds {
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
