//! A legend drawn beside a chart instead of on it: a column (or a row, above a grid of charts)
//! of swatches and labels in its own area, so it never covers a curve, and every element drawn
//! (the stance shading too) is named.

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

/// The grey that shades stance in every plot.
pub const STANCE: RGBColor = RGBColor(225, 225, 225);

/// Width of a legend column beside a chart, pixels.
pub const COLUMN_W: u32 = 120;

/// Draws `entries` top-down in `area` (starting below a chart caption's height).
pub fn legend_column<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(), String> {
    for (k, entry) in entries.iter().enumerate() {
        draw_entry(area, entry, (4, 48 + 20 * k as i32))?;
    }
    Ok(())
}

/// Height of a legend row, pixels.
pub const ROW_H: u32 = 28;

/// Draws `entries` left to right in `area` (a strip [`ROW_H`] high above the charts), each after
/// the width of the one before it.
pub fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(), String> {
    register_font();
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let mut x = 12;
    for entry in entries {
        draw_entry(area, entry, (x, ROW_H as i32 / 2))?;
        let (w, _) = area
            .estimate_text_size(&entry.label, &font)
            .map_err(|e| e.to_string())?;
        x += SWATCH_W + 6 + w as i32 + 24;
    }
    Ok(())
}

/// Length of a swatch, pixels.
const SWATCH_W: i32 = 22;

/// One swatch with its label, the swatch's left end and middle at `(x0, y)`.
fn draw_entry<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entry: &Entry,
    (x0, y): (i32, i32),
) -> Result<(), String> {
    register_font();
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let x1 = x0 + SWATCH_W;
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
    area.draw(&Text::new(entry.label.clone(), (x1 + 6, y - 7), font))
        .map_err(e)?;
    Ok(())
}
