//! PNG plots of the dynamics and of comparisons: one panel per leg (left legs left, front at the
//! top), traces over the step cycle, stance shaded grey. Torques per DoF (paper figure 4), GRF
//! components and magnitude (figure S9), and overlays of two plans.

use std::path::Path;

use plotters::prelude::*;

use crate::legend::{COLUMN_W, Entry, STANCE, Swatch, legend_column};
use crate::style::{colour, register_font};
use planner::model::Leg;

/// The leg's panel in a 3 x 2 grid, row-major: left legs in the left column, front to hind from
/// the top.
pub(crate) fn panel_index(leg: Leg) -> usize {
    let row = match leg {
        Leg::LF | Leg::RF => 0,
        Leg::LM | Leg::RM => 1,
        Leg::LH | Leg::RH => 2,
    };
    let col = match leg {
        Leg::LF | Leg::LM | Leg::LH => 0,
        Leg::RF | Leg::RM | Leg::RH => 1,
    };
    row * 2 + col
}

/// A line of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub label: String,
    pub values: Vec<f64>,
    /// Dashed (the second plan of an overlay).
    pub dashed: bool,
    /// Colour index; traces that belong together (same DoF in two plans) share it.
    pub colour: usize,
}

/// The panel of one leg.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub leg: Leg,
    pub title: String,
    pub traces: Vec<Trace>,
    /// Stance intervals (start, end) in the same unit as the time axis.
    pub stance: Vec<(f64, f64)>,
}

/// A plot failed to render or to be written.
#[derive(Debug, thiserror::Error)]
#[error("plot {path}: {reason}")]
pub struct PlotError {
    pub path: String,
    pub reason: String,
}

/// Stance intervals of a per-slice stance flag over a cycle of `period` with slices `dt` apart.
pub fn stance_spans(stance: &[bool], dt: f64) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (s, &st) in stance.iter().enumerate() {
        match (st, start) {
            (true, None) => start = Some(s as f64 * dt),
            (false, Some(t0)) => {
                spans.push((t0, s as f64 * dt));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(t0) = start {
        spans.push((t0, stance.len() as f64 * dt));
    }
    spans
}

/// Draw six leg panels; `time[i]` is the abscissa of sample i of every trace.
pub fn plot_leg_panels(
    path: &Path,
    panels: &[Panel],
    time: &[f64],
    x_desc: &str,
    y_desc: &str,
) -> Result<(), PlotError> {
    register_font();
    let err = |e: &dyn std::fmt::Display| PlotError {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let root = crate::Bitmap::new(path, (1400, 1100)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let areas = root.split_evenly((3, 2));
    let t_end = time.last().copied().unwrap_or(1.0) + time.get(1).map_or(0.0, |t1| t1 - time[0]);
    for panel in panels {
        let (area, key) = areas[panel_index(panel.leg)].split_horizontally(700 - COLUMN_W);
        let area = &area;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in panel.traces.iter().flat_map(|t| &t.values) {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        if !lo.is_finite() {
            (lo, hi) = (-1.0, 1.0);
        }
        let pad = ((hi - lo) * 0.08)
            .max(hi.abs().max(lo.abs()) * 1e-3)
            .max(1e-12);
        let (lo, hi) = (lo - pad, hi + pad);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..t_end, lo..hi)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .draw()
            .map_err(|e| err(&e))?;
        for &(t0, t1) in &panel.stance {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0, lo), (t1, hi)],
                    STANCE.filled(),
                )))
                .map_err(|e| err(&e))?;
        }
        for tr in &panel.traces {
            let c = colour(tr.colour);
            let pts: Vec<(f64, f64)> = time
                .iter()
                .copied()
                .zip(tr.values.iter().copied())
                .collect();
            let style = c.stroke_width(2);
            if tr.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts, 6, 4, style))
                    .map_err(|e| err(&e))?;
            } else {
                chart
                    .draw_series(LineSeries::new(pts, style))
                    .map_err(|e| err(&e))?;
            }
        }
        let mut entries: Vec<Entry> = panel
            .traces
            .iter()
            .map(|tr| {
                let c = colour(tr.colour);
                let swatch = if tr.dashed {
                    Swatch::Dashed(c)
                } else {
                    Swatch::Line(c)
                };
                Entry::new(tr.label.clone(), swatch)
            })
            .collect();
        if !panel.stance.is_empty() {
            entries.push(Entry::new("stance", Swatch::Shade(STANCE)));
        }
        legend_column(&key, &entries).map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))
}

/// A unit for a torque trace: N m, mN m or uN mm (1e-9 N m), chosen by the peak.
pub fn torque_unit(peak_nm: f64) -> (&'static str, f64) {
    if peak_nm >= 0.1 {
        ("N m", 1.0)
    } else if peak_nm >= 1e-4 {
        ("mN m", 1e3)
    } else {
        ("uN mm", 1e9)
    }
}

/// A unit for a force trace: N, mN or uN, chosen by the peak.
pub fn force_unit(peak_n: f64) -> (&'static str, f64) {
    if peak_n >= 0.1 {
        ("N", 1.0)
    } else if peak_n >= 1e-4 {
        ("mN", 1e3)
    } else {
        ("uN", 1e6)
    }
}
