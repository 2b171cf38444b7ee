//! Charts of the speed-versus-accuracy run (paper §7, Tables 4–5) and frames of a
//! scene, drawn with well-kept libraries.
//!
//! The main job measures every configuration (reference, brute force, contact graph,
//! the 2^7 speed-up combinations, stock Rapier) as a [`ChartPoint`]: how far its
//! trajectories drift from the reference (`deviation`, in sphere radii, lower is
//! better), how much faster it runs than brute force (`speedup`, higher is better),
//! and how many plausibility violations it produced. [`pareto_front`] picks the
//! configurations nothing beats on both axes; [`svg()`] and [`png()`] draw the scatter
//! chart with that front.
//!
//! [`frames`] draws pictures of a scene: what Rapier's own debug renderer draws, each
//! collider's lines in the colour of its body's state, as in the paper's Fig. 17.
//!
//! plotters draws the charts (SVG and bitmap back ends, one drawing routine), text is
//! DejaVu Sans through plotters' pure-Rust `ab_glyph`, the `png` crate encodes and
//! tiny-skia rasterises the frames' lines. Deterministic (same input, same bytes) and
//! forgiving (non-finite points left out and counted; nothing panics on data). Choices
//! and rejected libraries: `docs/ARCHITECTURE.md` ("Charts").
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
pub mod frames;
mod text;

use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};

/// One configuration's point on the chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPoint {
    /// The configuration's name, e.g. `"cache+tweak+fixate"`; shown next to labelled
    /// points and in the SVG tooltip.
    pub label: String,
    /// x: accuracy loss against the reference, lower is better. The DIKU chart puts
    /// the accuracy number of [`crate::accuracy`] here (the worst observable's
    /// |paired mean difference| / tolerance; 1 = the reference's own error); the
    /// stability suite a deviation in sphere radii.
    pub deviation: f64,
    /// y: speed-up over brute force (higher is better).
    pub speedup: f64,
    /// Plausibility violations counted during the run (paper §8).
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
    /// The equivalence band: when set (finite, positive), the region `x <= band` is
    /// shaded green and labelled, and the x axis reaches at least a little past it.
    /// The DIKU chart sets 1.0: configurations left of it differ from the reference
    /// by less than the reference's own discretisation error.
    pub band: Option<f64>,
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
            band: None,
        }
    }
}

/// The size a chart is drawn at: `spec`'s, clamped to 320..=8192 × 240..=8192.
fn chart_size(spec: &ChartSpec) -> (u32, u32) {
    (spec.width.clamp(320, 8192), spec.height.clamp(240, 8192))
}

/// The chart as an SVG document (UTF-8 text), `spec.width` × `spec.height` pixels
/// (clamped), drawn by plotters' SVG back end; text in DejaVu Sans or the viewer's
/// sans-serif.
pub fn svg(points: &[ChartPoint], spec: &ChartSpec) -> String {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, chart_size(spec)).into_drawing_area();
        // A back-end error leaves the picture as far as it got (see the module docs).
        let _ = chart::draw(&root, points, spec);
        let _ = root.present();
    }
    out
}

/// The chart as RGB pixels (row-major from the top-left corner, 3 bytes a pixel) with
/// its width and height, drawn by plotters' bitmap back end.
pub fn rgb(points: &[ChartPoint], spec: &ChartSpec) -> (u32, u32, Vec<u8>) {
    let (w, h) = chart_size(spec);
    let mut pixels = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (w, h)).into_drawing_area();
        let _ = chart::draw(&root, points, spec);
        let _ = root.present();
    }
    (w, h, pixels)
}

/// The chart as the bytes of a PNG file: [`rgb`] encoded by the `png` crate (8-bit
/// RGB, zlib-compressed).
pub fn png(points: &[ChartPoint], spec: &ChartSpec) -> Vec<u8> {
    let (w, h, pixels) = rgb(points, spec);
    encode_png(w, h, &pixels)
}

/// RGB pixels as a PNG file (8-bit RGB, zlib at the `png` crate's balanced level,
/// adaptive filtering). `rgb` must hold `width * height * 3` bytes; a mismatch (a
/// bug here, not data) gives an empty vector rather than a panic.
pub(crate) fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = ::png::Encoder::new(&mut out, width, height);
    encoder.set_color(::png::ColorType::Rgb);
    encoder.set_depth(::png::BitDepth::Eight);
    encoder.set_compression(::png::Compression::Balanced);
    let written = encoder
        .write_header()
        .and_then(|mut writer| writer.write_image_data(rgb).and_then(|_| writer.finish()));
    if written.is_err() {
        out.clear();
    }
    out
}

#[cfg(test)]
mod tests;
