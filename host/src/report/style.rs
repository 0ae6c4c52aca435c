//! What every plot of the host shares: plotters' `ab_glyph` backend has no system fonts, so DejaVu
//! Sans (the `dejavu` crate's bytes) is registered once as "sans-serif" before any text is drawn.

use std::sync::Once;

use plotters::style::FontStyle;

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
