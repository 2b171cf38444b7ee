//! Text for the charts and the frames: one TTF font, registered with plotters once.
//!
//! plotters draws text through a font back end chosen by feature. Its default, `ttf`,
//! goes through `font-kit`, which looks fonts up with the system's fontconfig and
//! FreeType: a CI machine with only a Rust toolchain has neither. The `ab_glyph`
//! back end instead rasterises a font handed to it as bytes, in pure Rust; the bytes
//! here are DejaVu Sans from the `dejavu` crate (Bitstream Vera licence, with the
//! DejaVu changes in the public domain: free to embed and redistribute). It is
//! registered under the CSS font list [`FAMILY`], which is also what the SVG's
//! `font-family` attributes say, so a viewer with DejaVu Sans shows the same font and
//! any other falls back to its sans-serif.
//!
//! Sizes are plotters' font sizes: about the distance from the ascender to the
//! descender in pixels (a capital is about 0.72 of it).

use std::sync::OnceLock;

use plotters::style::{register_font, FontDesc, FontFamily, FontStyle};

/// The family name the font is registered under (and the SVG's `font-family`).
pub(crate) const FAMILY: &str = "DejaVu Sans, sans-serif";

/// Registers the font with plotters on first use; false if the bytes were refused
/// (not expected: they are a known-good TTF). Text then measures by a fallback rule
/// and draws nothing, instead of failing the chart.
pub(crate) fn registered() -> bool {
    static DONE: OnceLock<bool> = OnceLock::new();
    *DONE.get_or_init(|| register_font(FAMILY, FontStyle::Normal, dejavu::sans::regular()).is_ok())
}

/// The font at `size`.
pub(crate) fn font(size: f64) -> FontDesc<'static> {
    registered();
    FontDesc::new(FontFamily::Name(FAMILY), size, FontStyle::Normal)
}

/// Width of `text` at `size`, in pixels (about 0.55 `size` per character if the font
/// is missing).
pub(crate) fn width(text: &str, size: f64) -> f64 {
    match font(size).box_size(text) {
        Ok((w, _)) => f64::from(w),
        Err(_) => 0.55 * size * text.chars().count() as f64,
    }
}

/// Height of a line at `size`, in pixels: what plotters reserves for it.
pub(crate) fn height(size: f64) -> f64 {
    (size / 1.24).floor()
}

/// `text` with the characters XML 1.0 forbids (control characters other than tab,
/// newline and carriage return) replaced by U+FFFD, so that the SVG stays well formed.
pub(crate) fn clean(text: &str) -> String {
    text.chars()
        .map(|c| {
            if ((c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r')) || c == '\u{7f}' {
                '\u{FFFD}'
            } else {
                c
            }
        })
        .collect()
}

/// `text` cut to at most `max` characters, ending in "..." when cut.
pub(crate) fn shorten(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(max.saturating_sub(3)).collect();
        s.push_str("...");
        s
    }
}

/// The largest size from `size` down to `min_size` (steps of 1) at which `text` fits
/// in `room` pixels; if it fits at none, `text` cut with "..." until it fits at
/// `min_size` (down to "..." alone).
pub(crate) fn fit(text: &str, size: f64, min_size: f64, room: f64) -> (String, f64) {
    let mut s = size;
    while s >= min_size {
        if width(text, s) <= room {
            return (text.to_string(), s);
        }
        s -= 1.0;
    }
    // Binary search on the number of characters kept: width grows with it.
    let chars: Vec<char> = text.chars().collect();
    let (mut lo, mut hi) = (0usize, chars.len());
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        let candidate: String = chars[..mid].iter().collect::<String>() + "...";
        if width(&candidate, min_size) <= room {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    (chars[..lo].iter().collect::<String>() + "...", min_size)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_font_is_registered_and_measures_text() {
        assert!(registered());
        let (a, b) = (width("speed-up", 14.0), width("speed-up", 28.0));
        assert!(a > 30.0 && a < 100.0, "{a}");
        assert!((b / a - 2.0).abs() < 0.1, "{a} {b}");
        assert!(width("MMMM", 14.0) > width("iiii", 14.0), "proportional");
        assert_eq!(clean("a\u{0}b\tc\u{1b}"), "a\u{FFFD}b\tc\u{FFFD}");
        assert_eq!(shorten("abcdefgh", 6), "abc...");
        assert_eq!(shorten("abc", 6), "abc");
    }

    #[test]
    fn fit_shrinks_then_cuts() {
        let (t, s) = fit("short", 20.0, 10.0, 500.0);
        assert_eq!((t.as_str(), s), ("short", 20.0));
        let long = "x".repeat(40);
        let (t, s) = fit(&long, 20.0, 10.0, width(&long, 15.0) + 0.5);
        assert_eq!((t.len(), s), (40, 15.0));
        let (t, s) = fit(&long, 20.0, 10.0, 100.0);
        assert!(t.ends_with("...") && t.len() < 40 && s == 10.0);
        assert!(width(&t, s) <= 100.0);
        let (t, _) = fit(&long, 20.0, 10.0, 0.0);
        assert_eq!(t, "...");
    }
}
