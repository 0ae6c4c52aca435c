//! What every plot of the host shares: plotters' `ab_glyph` backend has no system fonts, so DejaVu
//! Sans (the `dejavu` crate's bytes) is registered once as "sans-serif" before any text is drawn;
//! and one palette for the series of every plot.

use std::sync::Once;

use plotters::style::{FontStyle, RGBColor};

/// Registers the embedded font; cheap after the first call.
pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Can only fail if the bytes are not a font; dejavu's are.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Matplotlib's "tab10" order (the colours researchers know from their Python plots), then black.
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(0, 0, 0),
];

/// The colour of series `i` (the palette repeats).
pub fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}
