//! Charts of the speed-versus-accuracy run (design brief §5 and §7), without
//! dependencies.
//!
//! The main job measures every configuration (reference, brute force, contact graph,
//! the 2^7 speed-up combinations, stock Rapier) as a [`ChartPoint`]: how far its
//! trajectories drift from the reference (`deviation`, in sphere radii, lower is
//! better), how much faster it runs than brute force (`speedup`, higher is better),
//! and how many plausibility violations it produced. [`pareto_front`] picks the
//! configurations nothing beats on both axes; [`svg`] and [`png`] draw the scatter
//! chart with that front.
//!
//! [`frames`] draws pictures of a scene with the same machinery: PNG frames of a
//! Rapier world with every body coloured by its state, as in the paper's Fig. 17.
//!
//! # Design
//! - **One layout, two back ends.** `chart` turns the points and the [`ChartSpec`]
//!   into a display list in pixel coordinates (lines, markers, text boxes): axis
//!   ranges and "nice" ticks, the front as a step line, label placement, the legend.
//!   `svg` serialises that list as SVG text; `raster` paints it into an RGB buffer
//!   that `png` encodes. Both pictures therefore agree to the pixel on where things
//!   are; only text is set by the viewer's monospace font in SVG and by the built-in
//!   5×9 bitmap font (`font`) in PNG, with the same advance (6 px per character at
//!   scale 1).
//! - **No dependencies.** Rasterisation uses signed distances with a one-pixel
//!   antialiasing ramp (lines are capsules, markers are circles or polygons); the PNG
//!   is written with stored deflate blocks, CRC-32 and Adler-32 done here.
//! - **Deterministic.** No hashing, no clocks, no threads; numbers in the SVG are
//!   printed with fixed precision. Same input, same bytes.
//! - **Forgiving.** Points with a non-finite deviation or speed-up (and, on a log
//!   axis, a speed-up ≤ 0) are left out and counted in the caption; an empty input
//!   gives empty axes that say "no data"; a degenerate range (one point, all
//!   deviations 0) is widened. Nothing here panics on data.
//! - **Little clutter.** Only the front's points and the special configurations
//!   (reference, brute force, contact graph, stock Rapier) are labelled, placed
//!   greedily where they overlap nothing, with a leader line when pushed away;
//!   every point carries a tooltip in the SVG.
//!
//! ```
//! use rcg_lab::report::{self, ChartPoint, ChartSpec, PointKind};
//!
//! let points = vec![
//!     ChartPoint::new("reference", 0.0, 0.3, 0, PointKind::Reference),
//!     ChartPoint::new("brute force", 0.05, 1.0, 0, PointKind::BruteForce),
//!     ChartPoint::new("cache+tweak", 0.4, 9.0, 0, PointKind::Combination),
//!     ChartPoint::new("tweak+fixate", 0.3, 12.0, 3, PointKind::Combination),
//! ];
//! // The point with violations is not a candidate: the front is the other three.
//! assert_eq!(report::pareto_front(&points, true), vec![0, 1, 2]);
//! let spec = ChartSpec { title: "DIKU, 120 spheres", ..ChartSpec::default() };
//! let svg = report::svg(&points, &spec);
//! assert!(svg.starts_with("<svg"));
//! let png = report::png(&points, &spec);
//! assert_eq!(&png[1..4], b"PNG");
//! ```

mod chart;
mod font;
pub mod frames;
mod png;
mod raster;
mod svg;

/// One configuration's point on the chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPoint {
    /// The configuration's name, e.g. `"cache+tweak+fixate"`; shown next to labelled
    /// points and in the SVG tooltip.
    pub label: String,
    /// x: accuracy loss against the reference, in sphere radii (lower is better).
    pub deviation: f64,
    /// y: speed-up over brute force (higher is better).
    pub speedup: f64,
    /// Plausibility violations counted during the run (design brief §6).
    pub violations: u64,
    /// What kind of configuration this is; chooses the marker.
    pub kind: PointKind,
}

impl ChartPoint {
    /// A point from its fields.
    pub fn new(
        label: impl Into<String>,
        deviation: f64,
        speedup: f64,
        violations: u64,
        kind: PointKind,
    ) -> Self {
        ChartPoint {
            label: label.into(),
            deviation,
            speedup,
            violations,
            kind,
        }
    }

    /// Whether both coordinates are finite numbers.
    pub fn is_finite(&self) -> bool {
        self.deviation.is_finite() && self.speedup.is_finite()
    }
}

/// The kind of configuration a point stands for; each has its own marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PointKind {
    /// The reference run (no speed-ups, no sleep, 4× solver iterations); black diamond.
    Reference,
    /// Brute force: no groups, no speed-ups; grey square.
    BruteForce,
    /// The contact graph alone (groups + sleepy); green triangle.
    ContactGraph,
    /// Stock Rapier defaults; purple downward triangle.
    StockRapier,
    /// One of the 2^7 speed-up combinations; blue dot.
    Combination,
    /// A combination with repairs applied (later work); teal star.
    Repaired,
}

impl PointKind {
    /// All kinds, in legend order.
    pub const ALL: [PointKind; 6] = [
        PointKind::Reference,
        PointKind::BruteForce,
        PointKind::ContactGraph,
        PointKind::StockRapier,
        PointKind::Combination,
        PointKind::Repaired,
    ];

    /// The kind's name in the legend.
    pub fn name(self) -> &'static str {
        match self {
            PointKind::Reference => "reference",
            PointKind::BruteForce => "brute force",
            PointKind::ContactGraph => "contact graph",
            PointKind::StockRapier => "stock Rapier",
            PointKind::Combination => "speed-up combination",
            PointKind::Repaired => "repaired",
        }
    }

    /// Whether points of this kind are always labelled (the fixed configurations the
    /// combinations are compared with).
    pub fn is_special(self) -> bool {
        matches!(
            self,
            PointKind::Reference
                | PointKind::BruteForce
                | PointKind::ContactGraph
                | PointKind::StockRapier
        )
    }
}

/// Indices of the Pareto-optimal points: minimal deviation and maximal speed-up.
///
/// A point is dominated if another candidate has a deviation `<=` and a speed-up
/// `>=` with at least one of the two strict; the front is the candidates nobody
/// dominates. Candidates are the points with finite coordinates and, if
/// `zero_violations_only`, no violations. Identical points do not dominate each
/// other, so ties are all kept.
///
/// The indices come sorted by deviation, then by speed-up (descending), then by
/// index: the order in which the front is drawn. Quadratic in the number of points,
/// which is ~140 here.
pub fn pareto_front(points: &[ChartPoint], zero_violations_only: bool) -> Vec<usize> {
    let candidates: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].is_finite() && (!zero_violations_only || points[i].violations == 0))
        .collect();
    let dominates = |a: &ChartPoint, b: &ChartPoint| {
        a.deviation <= b.deviation
            && a.speedup >= b.speedup
            && (a.deviation < b.deviation || a.speedup > b.speedup)
    };
    let mut front: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| {
            !candidates
                .iter()
                .any(|&j| dominates(&points[j], &points[i]))
        })
        .collect();
    front.sort_by(|&a, &b| {
        let (pa, pb) = (&points[a], &points[b]);
        pa.deviation
            .total_cmp(&pb.deviation)
            .then(pb.speedup.total_cmp(&pa.speedup))
            .then(a.cmp(&b))
    });
    front
}

/// What to draw around the points: titles and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChartSpec<'a> {
    /// Title at the top of the chart.
    pub title: &'a str,
    /// Label of the x axis (deviation).
    pub x_label: &'a str,
    /// Label of the y axis (speed-up).
    pub y_label: &'a str,
    /// Width in pixels (clamped to 320..=8192).
    pub width: u32,
    /// Height in pixels (clamped to 240..=8192).
    pub height: u32,
    /// Logarithmic y axis (points with speed-up ≤ 0 are then left out).
    pub log_y: bool,
}

impl Default for ChartSpec<'static> {
    /// The main job's chart: 900×600, log speed-up axis, the usual axis labels.
    fn default() -> Self {
        ChartSpec {
            title: "Speed-up versus deviation",
            x_label: "deviation from the reference (sphere radii)",
            y_label: "speed-up over brute force",
            width: 900,
            height: 600,
            log_y: true,
        }
    }
}

/// The chart as an SVG document (UTF-8 text), `spec.width` × `spec.height` pixels.
///
/// Each drawn point is one `<g class="point">` element with a `<title>` tooltip
/// giving its label, coordinates and violations.
pub fn svg(points: &[ChartPoint], spec: &ChartSpec) -> String {
    svg::render(&chart::layout(points, spec))
}

/// The chart as the bytes of a PNG file (8-bit RGB, uncompressed deflate, so about
/// 3 bytes per pixel).
pub fn png(points: &[ChartPoint], spec: &ChartSpec) -> Vec<u8> {
    let scene = chart::layout(points, spec);
    let canvas = raster::render(&scene);
    png::encode_rgb(canvas.width, canvas.height, &canvas.rgb)
}

#[cfg(test)]
mod tests;
