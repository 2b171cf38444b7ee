//! Painting the kept lines with tiny-skia, and the caption and legend with plotters.

use super::lines::{Batch, Key, Pen};
use super::*;

/// Paints the batches: Rapier's pass farthest object first (stable: ties keep
/// Rapier's order), then the overlay in its order; an object with a broken line is
/// left out of the pass it was broken in.
pub(super) fn paint(pixmap: &mut Pixmap, mut batches: Vec<Batch>, broken: &BTreeSet<(bool, Key)>) {
    batches.retain(|b| !broken.contains(&(b.overlay, b.key)));
    batches.sort_by(|a, b| a.overlay.cmp(&b.overlay).then(b.depth.total_cmp(&a.depth)));
    for batch in &batches {
        stroke(pixmap, &batch.segments, batch.pen, 1.0);
    }
}

/// Strokes `segments` as one path with `pen` (line widths scaled by `scale`).
pub(super) fn stroke(pixmap: &mut Pixmap, segments: &[[(f64, f64); 2]], pen: Pen, scale: f32) {
    // Segments that continue the previous one extend its contour (Rapier's outlines
    // come as chains of short segments), so that joins are round and dashes run along
    // the outline instead of restarting at every segment.
    let mut pb = PathBuilder::new();
    let mut last: Option<(f64, f64)> = None;
    for [a, b] in segments {
        if last != Some(*a) {
            pb.move_to(a.0 as f32, a.1 as f32);
        }
        pb.line_to(b.0 as f32, b.1 as f32);
        last = Some(*b);
    }
    let Some(path) = pb.finish() else {
        return;
    };
    let stroke_path = |pixmap: &mut Pixmap, rgba: [u8; 4], width: f32, dashed: bool| {
        let mut paint = Paint::default();
        paint.set_color_rgba8(rgba[0], rgba[1], rgba[2], rgba[3]);
        paint.anti_alias = true;
        let stroke = Stroke {
            width: width * scale,
            line_cap: if dashed {
                LineCap::Butt
            } else {
                LineCap::Round
            },
            line_join: LineJoin::Round,
            dash: if dashed {
                StrokeDash::new(SENSOR_DASH.to_vec(), 0.0)
            } else {
                None
            },
            ..Stroke::default()
        };
        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
    };
    let opaque = |[r, g, b]: [u8; 3]| [r, g, b, 255];
    match pen {
        Pen::Shade {
            shade: Shade::Violating,
            sensor,
        } => {
            let casing = VIOLATING_WIDTH + Shade::Violating.outline_width() as f32;
            stroke_path(
                pixmap,
                opaque(Shade::Violating.outline_rgb()),
                casing,
                sensor,
            );
            stroke_path(
                pixmap,
                opaque(Shade::Violating.rgb()),
                VIOLATING_WIDTH,
                sensor,
            );
        }
        Pen::Shade { shade, sensor } => {
            stroke_path(pixmap, opaque(shade.rgb()), LINE_WIDTH, sensor)
        }
        Pen::Scenery { sensor } => stroke_path(pixmap, opaque(SCENERY), LINE_WIDTH, sensor),
        Pen::Colour(rgba) => stroke_path(pixmap, rgba, LINE_WIDTH, false),
    }
}

/// One legend entry's text: its label, where it starts (left, vertical middle) and
/// its size.
pub(super) struct LegendText {
    pub(super) label: String,
    pub(super) at: (f64, f64),
    pub(super) size: f64,
}

/// The legend in the band starting at `top`: per shade a swatch (a circle stroked
/// like that shade's bodies), then the name and the count, centred; at the legend
/// size if it fits, else smaller, else without counts. Strokes the swatches and
/// returns the texts, which [`set_text`] sets.
pub(super) fn legend_swatches(
    pixmap: &mut Pixmap,
    counts: &[usize; 5],
    width: f64,
    top: f64,
) -> Vec<LegendText> {
    let gap = 18.0;
    let swatch = 2.0 * f64::from(SWATCH_R) + 8.0;
    let with_counts: Vec<String> = Shade::ALL
        .iter()
        .map(|s| format!("{} {}", s.name(), counts[*s as usize]))
        .collect();
    let plain: Vec<String> = Shade::ALL.iter().map(|s| s.name().to_string()).collect();
    let total = |labels: &[String], size: f64| -> f64 {
        labels
            .iter()
            .map(|l| swatch + text::width(l, size))
            .sum::<f64>()
            + gap * (labels.len() - 1) as f64
    };
    let room = width - 2.0 * PAD;
    let (labels, size) = [
        (&with_counts, LEGEND_SIZE),
        (&with_counts, MIN_SIZE),
        (&plain, MIN_SIZE),
    ]
    .into_iter()
    .find(|(l, s)| total(l, *s) <= room)
    .unwrap_or((&plain, MIN_SIZE));
    let mut x = ((width - total(labels, size)) / 2.0).max(PAD).round();
    let mid = top + BAND / 2.0;
    let mut out = Vec::new();
    for (shade, label) in Shade::ALL.iter().zip(labels) {
        let cx = x + f64::from(SWATCH_R);
        // The circle as short segments, stroked by the bodies' own pen.
        let r = f64::from(SWATCH_R);
        let at = |k: usize| {
            let a = k as f64 * std::f64::consts::TAU / 32.0;
            (cx + r * a.cos(), mid + r * a.sin())
        };
        let segments: Vec<[(f64, f64); 2]> = (0..32).map(|k| [at(k), at(k + 1)]).collect();
        let pen = Pen::Shade {
            shade: *shade,
            sensor: false,
        };
        stroke(pixmap, &segments, pen, 1.0);
        x += swatch;
        out.push(LegendText {
            label: label.clone(),
            at: (x, mid),
            size,
        });
        x += text::width(label, size) + gap;
    }
    out
}

/// Sets the caption (top band, shrunk then cut to fit) and the legend's texts on the
/// RGB pixels with plotters' bitmap back end. Text that cannot be drawn (no font) is
/// left out.
pub(super) fn set_text(
    rgb: &mut [u8],
    (width, height): (u32, u32),
    caption: &str,
    legend: &[LegendText],
) {
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    if !caption.is_empty() {
        let (caption, size) = fit_caption(caption, f64::from(width) - 2.0 * PAD);
        let style = text::font(size)
            .color(&INK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let _ = root.draw(&Text::new(
            caption,
            (PAD as i32, (BAND / 2.0) as i32),
            style,
        ));
    }
    for item in legend {
        let style = text::font(item.size)
            .color(&INK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let at = (item.at.0.round() as i32, item.at.1.round() as i32);
        let _ = root.draw(&Text::new(item.label.as_str(), at, style));
    }
    let _ = root.present();
}

/// The caption as set in `room` pixels: at the caption size if it fits, else smaller
/// down to the minimum, else cut with "...".
pub(super) fn fit_caption(caption: &str, room: f64) -> (String, f64) {
    text::fit(&text::clean(caption), CAPTION_SIZE, MIN_SIZE, room)
}
