//! The chart's colours, font sizes and limits.

use plotters::prelude::RGBColor;

pub(super) const INK: RGBColor = RGBColor(0x22, 0x22, 0x22);
pub(super) const MUTED: RGBColor = RGBColor(0x66, 0x66, 0x66);
pub(super) const FRAME: RGBColor = RGBColor(0x44, 0x44, 0x44);
pub(super) const GRID_MAJOR: RGBColor = RGBColor(0xDD, 0xDD, 0xDD);
pub(super) const GRID_MINOR: RGBColor = RGBColor(0xF0, 0xF0, 0xF0);
/// The Pareto front's line and rings.
pub(super) const FRONT: RGBColor = RGBColor(0xFF, 0x7F, 0x0E);
/// The cross marking a point with violations.
pub(crate) const VIOLATION: RGBColor = RGBColor(0xD6, 0x27, 0x28);
/// The equivalence band's fill (green, drawn at 35 % over the grid) and its edge.
pub(super) const BAND: RGBColor = RGBColor(0x9C, 0xD8, 0x90);
pub(super) const BAND_EDGE: RGBColor = RGBColor(0x2C, 0x8A, 0x2C);
pub(super) const LEADER: RGBColor = RGBColor(0x99, 0x99, 0x99);
pub(super) const LEGEND_BORDER: RGBColor = RGBColor(0xBB, 0xBB, 0xBB);

// Font sizes (plotters' sizes: about ascender-to-descender in pixels).
pub(super) const TITLE_SIZE: f64 = 24.0;
pub(super) const AXIS_LABEL_SIZE: f64 = 19.0;
pub(super) const TICK_SIZE: f64 = 17.0;
pub(super) const SMALL_SIZE: f64 = 15.0;
/// The points' labels: smaller than the legend's, there are many.
pub(super) const LABEL_SIZE: f64 = 13.5;
/// No text is set smaller than this; what does not fit is cut with "...".
pub(super) const MIN_SIZE: f64 = 10.0;
/// Labels longer than this are shortened with "...".
pub(super) const MAX_LABEL_CHARS: usize = 40;
/// Largest magnitude an axis reaches (smallest positive value on a log axis: its
/// inverse).
pub(super) const LIMIT: f64 = 1e150;
/// Top of the title.
pub(super) const TITLE_Y: f64 = 10.0;
/// Length of the tick marks outside the frame.
pub(super) const TICK_LEN: i32 = 5;
