//! SVG back end: the display list as SVG 1.1 text.
//!
//! One element per item: `<rect>`, `<polyline>`, `<circle>` / `<polygon>` / `<path>`
//! (cross) for markers, `<text>` for text and `<g>` for groups (with a `class` and an
//! optional `<title>` tooltip). Text is set in the viewer's monospace font at
//! `10 × scale` px, whose advance (~0.6 em) matches the bitmap font's 6 px per
//! character, and `textLength` pins each string to the width the layout reserved, so
//! labels land where the PNG puts them whatever font the viewer picks. Coordinates
//! are printed with at most two decimals; text is XML-escaped.

use std::fmt::Write;

use super::chart::{Color, Item, Scene, Shape, Stroke};
use super::font;

/// The scene as an SVG document.
pub(crate) fn render(scene: &Scene) -> String {
    let mut out = String::with_capacity(64 * 1024);
    let (w, h) = (scene.width, scene.height);
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"DejaVu Sans Mono, Menlo, Consolas, monospace\">"
    );
    let _ = writeln!(
        out,
        "<rect width=\"{w}\" height=\"{h}\" fill=\"{}\"/>",
        hex(scene.background)
    );
    for item in &scene.items {
        write_item(&mut out, item, 0);
    }
    out.push_str("</svg>\n");
    out
}

fn write_item(out: &mut String, item: &Item, depth: usize) {
    let indent = "  ".repeat(depth);
    out.push_str(&indent);
    match item {
        Item::Rect {
            x,
            y,
            w,
            h,
            fill,
            opacity,
            stroke,
        } => {
            let _ = write!(
                out,
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"",
                num(*x),
                num(*y),
                num(*w),
                num(*h)
            );
            paint(out, *fill, *stroke);
            if fill.is_some() && *opacity < 1.0 {
                let _ = write!(out, " fill-opacity=\"{}\"", num(*opacity));
            }
            out.push_str("/>\n");
        }
        Item::Line { points, stroke } => {
            out.push_str("<polyline points=\"");
            out.push_str(&point_list(points));
            out.push('"');
            paint(out, None, Some(*stroke));
            out.push_str(" stroke-linecap=\"round\" stroke-linejoin=\"round\"/>\n");
        }
        Item::Polygon {
            points,
            fill,
            stroke,
        } => {
            let _ = write!(out, "<polygon points=\"{}\"", point_list(points));
            paint(out, *fill, *stroke);
            out.push_str("/>\n");
        }
        Item::Marker {
            shape,
            x,
            y,
            r,
            fill,
            stroke,
        } => {
            match (shape, shape.polygon(*x, *y, *r)) {
                (Shape::Cross, _) => {
                    let [a, b] = Shape::cross_segments(*x, *y, *r);
                    let _ = write!(
                        out,
                        "<path d=\"M{} {}L{} {}M{} {}L{} {}\" stroke-linecap=\"round\"",
                        num(a[0].0),
                        num(a[0].1),
                        num(a[1].0),
                        num(a[1].1),
                        num(b[0].0),
                        num(b[0].1),
                        num(b[1].0),
                        num(b[1].1)
                    );
                    paint(out, None, *stroke);
                }
                (_, Some(poly)) => {
                    let _ = write!(out, "<polygon points=\"{}\"", point_list(&poly));
                    paint(out, *fill, *stroke);
                }
                (_, None) => {
                    let _ = write!(
                        out,
                        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"",
                        num(*x),
                        num(*y),
                        num(*r)
                    );
                    paint(out, *fill, *stroke);
                }
            }
            out.push_str("/>\n");
        }
        Item::Text {
            x,
            y,
            text,
            scale,
            color,
            vertical,
        } => {
            let s = f64::from(*scale);
            let cap = f64::from(font::CAP_HEIGHT) * s;
            let length = f64::from(font::text_width(text)) * s;
            let common = format!(
                "font-size=\"{}\" fill=\"{}\" textLength=\"{}\" lengthAdjust=\"spacingAndGlyphs\"",
                num(10.0 * s),
                hex(*color),
                num(length)
            );
            if *vertical {
                let _ = write!(
                    out,
                    "<text transform=\"translate({} {}) rotate(-90)\" {common}>",
                    num(x + cap),
                    num(y + length)
                );
            } else {
                let _ = write!(
                    out,
                    "<text x=\"{}\" y=\"{}\" {common}>",
                    num(*x),
                    num(y + cap)
                );
            }
            out.push_str(&escape(text));
            out.push_str("</text>\n");
        }
        Item::Group {
            class,
            tooltip,
            items,
        } => {
            let _ = writeln!(out, "<g class=\"{class}\">");
            if let Some(t) = tooltip {
                let _ = writeln!(out, "{indent}  <title>{}</title>", escape(t));
            }
            for i in items {
                write_item(out, i, depth + 1);
            }
            out.push_str(&indent);
            out.push_str("</g>\n");
        }
    }
}

/// ` fill=".." stroke=".." stroke-width=".."` attributes.
fn paint(out: &mut String, fill: Option<Color>, stroke: Option<Stroke>) {
    match fill {
        Some(c) => {
            let _ = write!(out, " fill=\"{}\"", hex(c));
        }
        None => out.push_str(" fill=\"none\""),
    }
    if let Some(s) = stroke {
        let _ = write!(
            out,
            " stroke=\"{}\" stroke-width=\"{}\"",
            hex(s.color),
            num(s.width)
        );
    }
}

fn point_list(points: &[(f64, f64)]) -> String {
    points
        .iter()
        .map(|&(x, y)| format!("{},{}", num(x), num(y)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn hex(c: Color) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

/// A coordinate with at most two decimals, trailing zeros dropped, never "-0".
fn num(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// XML-escapes text content and attribute values.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Characters XML 1.0 forbids become U+FFFD.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_escapes() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(0.126), "0.13");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(12.50), "12.5");
        assert_eq!(
            escape("a<b & \"c\"\u{1}"),
            "a&lt;b &amp; &quot;c&quot;\u{FFFD}"
        );
    }
}
