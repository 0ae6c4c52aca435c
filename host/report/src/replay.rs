//! A recording against its replays, one panel per joint: the recorded trace (black) and each
//! replay's (coloured), over time. The identification's report draws position before and after
//! the fit with it (`lab::identify::report`).

use std::path::Path;

use plotters::prelude::*;

use crate::legend::{Entry, Swatch, legend_row};
use crate::style::{colour, register_font};

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// One joint's panel: its recorded trace and the replays' (label, trace), one value per time.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: String,
    pub recorded: Vec<f64>,
    pub curves: Vec<(String, Vec<f64>)>,
}

/// Draws `panels` over times `t` (s) to a PNG at `path`, at most two panels a row.
pub fn plot_panels(path: &Path, title: &str, t: &[f64], panels: &[Panel]) -> PlotResult {
    register_font();
    let cols = panels.len().clamp(1, 2);
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (1100u32, 60 + 240 * rows as u32);
    let root = crate::Bitmap::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE)?;
    let (head, body) = root.split_vertically(60);
    let (title_area, legend) = head.split_vertically(30);
    title_area.titled(title, ("sans-serif", 17))?;
    let mut entries = vec![Entry::new("recorded", Swatch::Line(BLACK))];
    if let Some(p) = panels.first() {
        for (i, (label, _)) in p.curves.iter().enumerate() {
            entries.push(Entry::new(label.clone(), Swatch::Line(colour(i))));
        }
    }
    legend_row(&legend, &entries)?;
    let t0 = t.first().copied().unwrap_or(0.0);
    let t1 = t.last().copied().unwrap_or(1.0).max(t0 + 1e-3);
    for (p, area) in panels.iter().zip(body.split_evenly((rows, cols)).iter()) {
        let all = p
            .recorded
            .iter()
            .chain(p.curves.iter().flat_map(|c| c.1.iter()));
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
        let (lo, hi) = if lo.is_finite() {
            (lo, hi.max(lo + 1e-6))
        } else {
            (-1.0, 1.0)
        };
        let pad = 0.05 * (hi - lo);
        let mut chart = ChartBuilder::on(area)
            .caption(&p.title, ("sans-serif", 14))
            .margin(6)
            .x_label_area_size(26)
            .y_label_area_size(52)
            .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("s")
            .label_style(("sans-serif", 11))
            .draw()?;
        chart.draw_series(LineSeries::new(
            t.iter().copied().zip(p.recorded.iter().copied()),
            BLACK.stroke_width(2),
        ))?;
        for (i, (_, c)) in p.curves.iter().enumerate() {
            chart.draw_series(LineSeries::new(
                t.iter().copied().zip(c.iter().copied()),
                colour(i).stroke_width(1),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}
