//! Tests of the public chart API: the Pareto front on hand-made sets, the PNG checked
//! by the `png` crate's decoder, the SVG's markers and tag balance, edge cases, and a
//! sample chart written to the temporary directory (`chart_test.png`,
//! `chart_test.svg`) to look at.

use super::*;

/// The PNG signature.
const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];

/// Decodes a PNG with the `png` crate, checking it is 8-bit RGB; returns width,
/// height and pixels.
pub(crate) fn decode_checked(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
    let decoder = ::png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("image too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    if (info.color_type, info.bit_depth) != (::png::ColorType::Rgb, ::png::BitDepth::Eight) {
        return Err(format!("{:?} {:?}", info.color_type, info.bit_depth));
    }
    buf.truncate(info.buffer_size());
    Ok((info.width, info.height, buf))
}

/// `#RRGGBB` as plotters writes colours into SVG.
fn hex(c: plotters::prelude::RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// Filled markers in the SVG: elements filled with a kind's colour (one per point
/// drawn without violations, and one per kind in the legend).
fn filled_markers(svg: &str) -> usize {
    PointKind::ALL
        .iter()
        .map(|&k| count(svg, &format!("fill=\"{}\"", hex(chart::style(k).1))))
        .sum()
}

/// Violation crosses in the SVG: two strokes each.
fn crosses(svg: &str) -> usize {
    count(svg, &format!("stroke=\"{}\"", hex(chart::VIOLATION))) / 2
}

/// What [`filled_markers`] and [`crosses`] should find: the drawable points' markers
/// plus the legend's samples.
fn expected_markers(points: &[ChartPoint], log_y: bool) -> (usize, usize) {
    let drawn: Vec<&ChartPoint> = points
        .iter()
        .filter(|p| p.is_finite() && (!log_y || p.speedup > 0.0))
        .collect();
    let filled = drawn.iter().filter(|p| p.violations == 0).count();
    let legend = PointKind::ALL
        .iter()
        .filter(|&&k| {
            drawn
                .iter()
                .any(|p| p.kind == k && (p.violations == 0 || k != PointKind::Combination))
        })
        .count();
    let violating = drawn.iter().filter(|p| p.violations > 0).count();
    (filled + legend, violating + usize::from(violating > 0))
}

fn p(label: &str, deviation: f64, speedup: f64, violations: u64) -> ChartPoint {
    ChartPoint::new(
        label,
        deviation,
        speedup,
        violations,
        PointKind::Combination,
    )
}

#[test]
fn pareto_front_excludes_dominated_points() {
    let points = vec![
        p("a", 0.0, 1.0, 0),
        p("b", 1.0, 2.0, 0),
        p("c", 1.0, 1.5, 0), // same deviation as b, slower
        p("d", 2.0, 2.0, 0), // same speed-up as b, less accurate
        p("e", 0.5, 0.5, 0), // worse than a on both
        p("f", 3.0, 5.0, 0),
    ];
    assert_eq!(pareto_front(&points, false), vec![0, 1, 5]);
    assert_eq!(pareto_front(&points, true), vec![0, 1, 5]);
}

#[test]
fn pareto_front_keeps_ties_and_sorts_by_deviation() {
    let points = vec![
        p("late", 2.0, 4.0, 0),
        p("twin-1", 1.0, 2.0, 0),
        p("twin-2", 1.0, 2.0, 0),
        p("early", 0.0, 1.0, 0),
    ];
    assert_eq!(pareto_front(&points, true), vec![3, 1, 2, 0]);
}

#[test]
fn pareto_front_can_ignore_points_with_violations() {
    let points = vec![
        p("ok-slow", 0.1, 1.0, 0),
        p("bad-dominant", 0.05, 10.0, 3), // dominates everything, but violates
        p("ok-fast", 0.5, 5.0, 0),
        p("ok-dominated", 0.6, 4.0, 0),
    ];
    assert_eq!(pareto_front(&points, false), vec![1]);
    assert_eq!(pareto_front(&points, true), vec![0, 2]);
}

#[test]
fn pareto_front_skips_non_finite_and_handles_empty_input() {
    assert!(pareto_front(&[], true).is_empty());
    let points = vec![
        p("nan", f64::NAN, 100.0, 0),
        p("inf", 0.0, f64::INFINITY, 0),
        p("neg-inf", f64::NEG_INFINITY, 1.0, 0),
        p("fine", 1.0, 1.0, 0),
    ];
    assert_eq!(pareto_front(&points, true), vec![3]);
    assert_eq!(pareto_front(&points[..3], false), Vec::<usize>::new());
}

/// ~140 plausible points: the fixed configurations, the 2^7 combinations with
/// speed-ups and errors that compound, a few repaired ones and two broken values.
fn sample_points() -> Vec<ChartPoint> {
    const NAMES: [&str; 7] = [
        "cache", "tweak", "reduce", "zero", "damp", "subgroup", "fixate",
    ];
    const SPEED: [f64; 7] = [1.3, 3.0, 1.2, 1.05, 1.15, 1.4, 1.6];
    const ERROR: [f64; 7] = [0.02, 0.35, 0.12, 0.05, 0.2, 0.15, 0.25];
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut noise = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut points = vec![
        ChartPoint::new("reference", 0.0, 0.28, 0, PointKind::Reference),
        ChartPoint::new("brute force", 0.04, 1.0, 0, PointKind::BruteForce),
        ChartPoint::new("contact graph", 0.08, 2.5, 0, PointKind::ContactGraph),
        ChartPoint::new("stock Rapier", 0.45, 1.9, 0, PointKind::StockRapier),
    ];
    for mask in 0u32..128 {
        let on = |k: usize| mask & (1 << k) != 0;
        let mut speed = 2.5;
        let mut dev = 0.08;
        let mut names = Vec::new();
        for k in 0..7 {
            if on(k) {
                speed *= SPEED[k];
                dev += ERROR[k];
                names.push(NAMES[k]);
            }
        }
        speed *= 0.85 + 0.3 * noise();
        dev *= 0.8 + 0.4 * noise();
        let violations = if on(6) && !on(5) {
            3 + (noise() * 20.0) as u64
        } else if on(1) && on(2) {
            (noise() * 3.0) as u64
        } else {
            0
        };
        let label = if names.is_empty() {
            "none".to_string()
        } else {
            names.join("+")
        };
        points.push(ChartPoint::new(
            label,
            dev,
            speed,
            violations,
            PointKind::Combination,
        ));
    }
    for k in 0..6 {
        let t = k as f64;
        points.push(ChartPoint::new(
            format!("repaired #{k}"),
            0.3 + 0.15 * t,
            6.0 + 3.0 * t,
            0,
            PointKind::Repaired,
        ));
    }
    points.push(ChartPoint::new(
        "broken-nan",
        f64::NAN,
        3.0,
        0,
        PointKind::Combination,
    ));
    points.push(ChartPoint::new(
        "broken-inf",
        0.5,
        f64::INFINITY,
        0,
        PointKind::Combination,
    ));
    points
}

/// Checks that every tag is closed in order; returns the number of elements.
fn check_balanced(svg: &str) -> Result<usize, String> {
    let mut stack: Vec<&str> = Vec::new();
    let mut elements = 0;
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        let end = start + rest[start..].find('>').ok_or("unterminated tag")?;
        let tag = &rest[start + 1..end];
        if let Some(name) = tag.strip_prefix('/') {
            match stack.pop() {
                Some(open) if open == name.trim() => {}
                other => return Err(format!("</{name}> closes {other:?}")),
            }
        } else if !tag.starts_with('?') && !tag.starts_with('!') {
            let name = tag.split_whitespace().next().ok_or("empty tag")?;
            let name = name.trim_end_matches('/');
            elements += 1;
            if !tag.ends_with('/') {
                stack.push(name);
            }
        }
        rest = &rest[end + 1..];
    }
    if stack.is_empty() {
        Ok(elements)
    } else {
        Err(format!("unclosed {stack:?}"))
    }
}

fn count(haystack: &str, needle: &str) -> usize {
    haystack.matches(needle).count()
}

#[test]
fn svg_has_one_marker_per_finite_point_and_balanced_tags() {
    let points = sample_points();
    let spec = ChartSpec::default();
    let svg = svg(&points, &spec);
    let finite = points.iter().filter(|p| p.is_finite()).count();
    assert_eq!(finite, points.len() - 2);
    // Every finite point is one filled marker or one cross; the legend adds one sample
    // per kind and one cross.
    let (filled, crossed) = expected_markers(&points, spec.log_y);
    assert_eq!(filled + crossed, finite + 6 + 1);
    assert_eq!(filled_markers(&svg), filled);
    assert_eq!(crosses(&svg), crossed);
    assert!(check_balanced(&svg).unwrap() > finite);
    assert!(svg.starts_with("<svg "));
    assert!(svg.contains("xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.contains("font-family=\"DejaVu Sans, sans-serif\""));
    assert!(svg.trim_end().ends_with("</svg>"));
    // The special points and the legend entries are labelled (plotters writes a text
    // element's content on a line of its own).
    for text in [
        "reference",
        "brute force",
        "contact graph",
        "stock Rapier",
        "with violations",
        "repaired",
        "Pareto front (0 violations)",
    ] {
        assert!(
            svg.contains(&format!(">\n{text}\n</text>")),
            "missing {text}"
        );
    }
    assert!(svg.contains("2 not drawn"));
    assert_eq!(svg, super::svg(&points, &spec), "not deterministic");
}

#[test]
fn svg_escapes_labels() {
    let points = vec![ChartPoint::new(
        "a<b & \"c\"\u{1}",
        0.0,
        1.0,
        0,
        PointKind::Reference,
    )];
    let svg = svg(
        &points,
        &ChartSpec {
            title: "<&>",
            ..ChartSpec::default()
        },
    );
    check_balanced(&svg).unwrap();
    assert!(svg.contains("a&lt;b &amp; &quot;c&quot;\u{FFFD}"));
    assert!(svg.contains("&lt;&amp;&gt;") && !svg.contains("<&>"));
}

#[test]
fn png_is_a_valid_file_of_the_requested_size() {
    let points = sample_points();
    let spec = ChartSpec::default();
    let png = png(&points, &spec);
    assert_eq!(png[..8], SIGNATURE);
    let (w, h, rgb) = decode_checked(&png).unwrap();
    assert_eq!((w, h), (900, 600));
    assert_eq!((w, h, rgb.clone()), super::rgb(&points, &spec));
    let has = |c: [u8; 3]| rgb.chunks_exact(3).filter(|px| *px == c).count();
    assert!(has([0xFF, 0x7F, 0x0E]) > 100, "front line missing");
    assert!(has([0xD6, 0x27, 0x28]) > 50, "violation crosses missing");
    assert!(has([0x1F, 0x77, 0xB4]) > 500, "combination markers missing");
    assert!(has([0x17, 0xBE, 0xCF]) > 50, "repaired stars missing");
    // Text: anti-aliased, so count the dark pixels (ink and its near shades).
    let dark = rgb
        .chunks_exact(3)
        .filter(|px| px.iter().all(|&c| c < 0x60))
        .count();
    assert!(dark > 1000, "text missing: {dark}");
    // Compressed: far below the 3 bytes a pixel of the raw image.
    assert!(png.len() < rgb.len() / 10, "{} bytes", png.len());
    assert_eq!(png, super::png(&points, &spec), "not deterministic");
}

#[test]
fn edge_cases_do_not_panic_and_give_valid_output() {
    let one = vec![p("only", 0.3, 2.0, 0)];
    let zero_dev = vec![
        p("x", 0.0, 1.0, 0),
        p("y", 0.0, 3.0, 2),
        p("z", 0.0, 2.0, 0),
    ];
    let broken = vec![
        p("nan", f64::NAN, f64::NAN, 0),
        p("inf", f64::INFINITY, 1.0, 0),
    ];
    let nonpositive = vec![
        p("zero", 0.1, 0.0, 0),
        p("neg", 0.2, -1.0, 0),
        p("ok", 0.3, 2.0, 0),
    ];
    let extreme = vec![
        p("big", 1e300, 1e300, 0),
        p("small", 1e-300, 1e-300, 0),
        p("neg", -5.0, 2.0, 1),
    ];
    let cases: [(&str, Vec<ChartPoint>); 6] = [
        ("empty", vec![]),
        ("one", one),
        ("zero deviations", zero_dev),
        ("non-finite", broken),
        ("non-positive", nonpositive),
        ("extreme", extreme),
    ];
    for (name, points) in &cases {
        for log_y in [false, true] {
            for (width, height) in [(900, 600), (0, 0), (321, 241)] {
                let spec = ChartSpec {
                    log_y,
                    width,
                    height,
                    ..ChartSpec::default()
                };
                let svg = svg(points, &spec);
                check_balanced(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
                let (filled, crossed) = expected_markers(points, log_y);
                assert_eq!(
                    (filled_markers(&svg), crosses(&svg)),
                    (filled, crossed),
                    "{name}, log_y {log_y}"
                );
                assert!(
                    !svg.contains("NaN") && !svg.contains("inf"),
                    "{name}: {svg}"
                );
                let (w, h, _) = decode_checked(&png(points, &spec)).unwrap();
                assert_eq!((w, h), (width.clamp(320, 8192), height.clamp(240, 8192)));
            }
        }
    }
    let empty = svg(&[], &ChartSpec::default());
    assert!(empty.contains(">\nno data\n</text>"));
    assert_eq!((filled_markers(&empty), crosses(&empty)), (0, 0));
}

#[test]
fn svg_and_png_put_the_markers_in_the_same_places() {
    // One drawing routine, two back ends: every combination marker's centre in the
    // SVG is a pixel of its colour in the bitmap.
    let points = sample_points();
    let spec = ChartSpec::default();
    let svg = svg(&points, &spec);
    let (w, _, rgb) = super::rgb(&points, &spec);
    let colour = chart::style(PointKind::Combination).1;
    let fill = format!("fill=\"{}\"", hex(colour));
    let attr = |tag: &str, name: &str| -> i64 {
        let start = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        tag[start..].split('"').next().unwrap().parse().unwrap()
    };
    // (A few are covered by a later marker or a label's translucent box.)
    let (mut checked, mut same) = (0, 0);
    for tag in svg
        .split('<')
        .filter(|t| t.starts_with("circle") && t.contains(&fill))
    {
        let (x, y) = (attr(tag, "cx"), attr(tag, "cy"));
        let i = (y as usize * w as usize + x as usize) * 3;
        same += usize::from(rgb[i..i + 3] == [colour.0, colour.1, colour.2]);
        checked += 1;
    }
    assert!(checked > 50, "{checked}");
    assert!(same * 10 >= checked * 9, "{same} of {checked}");
}

#[test]
fn writes_sample_chart_for_inspection() {
    let points = sample_points();
    let spec = ChartSpec {
        title: "DIKU scene, 1,200 spheres: speed-up vs deviation",
        ..ChartSpec::default()
    };
    let dir = std::env::temp_dir();
    std::fs::write(dir.join("chart_test.png"), png(&points, &spec)).unwrap();
    std::fs::write(dir.join("chart_test.svg"), svg(&points, &spec)).unwrap();
    let linear = ChartSpec {
        log_y: false,
        ..spec
    };
    std::fs::write(dir.join("chart_test_linear.png"), png(&points, &linear)).unwrap();
}
