//! A legend drawn beside a chart instead of on it: a column of swatches and labels in its own
//! area, so it never covers a curve, and every element drawn (the stance shading too) is named.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::register_font;

/// How an entry is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Swatch {
    Line(RGBColor),
    Dashed(RGBColor),
    /// A filled box (shading such as stance).
    Shade(RGBColor),
}

/// One line of a legend.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub label: String,
    pub swatch: Swatch,
}

impl Entry {
    pub fn new(label: impl Into<String>, swatch: Swatch) -> Self {
        Self {
            label: label.into(),
            swatch,
        }
    }
}

/// Width of a legend column beside a chart, pixels.
pub const COLUMN_W: u32 = 120;

/// Draws `entries` top-down in `area` (starting below a chart caption's height).
pub fn legend_column<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(), String> {
    register_font();
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    for (k, entry) in entries.iter().enumerate() {
        let y = 48 + 20 * k as i32;
        let (x0, x1) = (4, 26);
        match entry.swatch {
            Swatch::Line(c) => area
                .draw(&PathElement::new(vec![(x0, y), (x1, y)], c.stroke_width(2)))
                .map_err(e)?,
            Swatch::Dashed(c) => {
                for s in [x0, x0 + 9, x0 + 18] {
                    area.draw(&PathElement::new(
                        vec![(s, y), ((s + 5).min(x1), y)],
                        c.stroke_width(2),
                    ))
                    .map_err(e)?;
                }
            }
            Swatch::Shade(c) => area
                .draw(&Rectangle::new([(x0, y - 6), (x1, y + 6)], c.filled()))
                .map_err(e)?,
        }
        area.draw(&Text::new(
            entry.label.clone(),
            (x1 + 6, y - 7),
            font.clone(),
        ))
        .map_err(e)?;
    }
    Ok(())
}
