//! The paper's robot figures 5 to 7 drawn from a simulated walk: per joint of one leg, over the
//! phase of the step, the torque estimated from the servo's load (mean, +-1 SD over steps shaded)
//! of each run beside the planner's torque for it (dashed, same colour), the leg's stance shaded
//! grey. `dbot paper-robot` draws one figure per leg pair and experiment set.

use std::path::Path;

use plotters::prelude::*;

use crate::legend::{Entry, Swatch, legend_column};
use crate::style::{colour, register_font};

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// One run (one curve per joint).
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub label: String,
    /// Per joint, per slice: planned torque, measured mean and SD, N m.
    pub planned: Vec<Vec<f64>>,
    pub mean: Vec<Vec<f64>>,
    pub sd: Vec<Vec<f64>>,
}

/// Draws `runs` for `joints` (one panel each) to a PNG at `path`; `stance[joint][slice]` shades
/// the stance of the first run's plan.
pub fn plot_runs(
    path: &Path,
    title: &str,
    joints: &[String],
    stance: &[Vec<bool>],
    runs: &[Run],
) -> PlotResult {
    register_font();
    let w = 380 * joints.len().max(1) as u32 + 220;
    let root = crate::Bitmap::new(path, (w, 330)).into_drawing_area();
    root.fill(&WHITE)?;
    let (head, body) = root.split_vertically(34);
    head.titled(title, ("sans-serif", 17))?;
    let (panels, legend) = body.split_horizontally(w - 220);
    let mut entries = vec![Entry::new("stance", Swatch::Shade(RGBColor(225, 225, 225)))];
    for (i, r) in runs.iter().enumerate() {
        entries.push(Entry::new(
            format!("{}: load (mean +-SD)", r.label),
            Swatch::Line(colour(i)),
        ));
        entries.push(Entry::new(
            format!("{}: planned", r.label),
            Swatch::Dashed(colour(i)),
        ));
    }
    legend_column(&legend, &entries)?;
    for (j, panel) in panels
        .split_evenly((1, joints.len().max(1)))
        .iter()
        .enumerate()
        .take(joints.len())
    {
        let (mut lo, mut hi) = (-0.1f64, 0.1f64);
        for r in runs {
            for (m, s) in r.mean[j].iter().zip(&r.sd[j]) {
                lo = lo.min(m - s);
                hi = hi.max(m + s);
            }
            for p in &r.planned[j] {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
        let pad = 0.05 * (hi - lo);
        let (lo, hi) = (lo - pad, hi + pad);
        let mut chart = ChartBuilder::on(panel)
            .caption(&joints[j], ("sans-serif", 15))
            .margin(6)
            .x_label_area_size(28)
            .y_label_area_size(48)
            .build_cartesian_2d(0.0..1.0, lo..hi)?;
        chart
            .configure_mesh()
            .x_desc("phase of the step")
            .y_desc("N m")
            .label_style(("sans-serif", 11))
            .draw()?;
        let n = stance.get(j).map_or(0, Vec::len);
        if n > 0 {
            let shade = RGBColor(225, 225, 225).filled();
            chart.draw_series(stance[j].iter().enumerate().filter(|(_, s)| **s).map(
                |(s, _)| {
                    Rectangle::new(
                        [(s as f64 / n as f64, lo), ((s + 1) as f64 / n as f64, hi)],
                        shade,
                    )
                },
            ))?;
        }
        for (i, r) in runs.iter().enumerate() {
            let c = colour(i);
            let k = r.mean[j].len().max(1) as f64;
            let x = |s: usize| s as f64 / k;
            let mut band: Vec<(f64, f64)> = (0..r.mean[j].len())
                .map(|s| (x(s), r.mean[j][s] + r.sd[j][s]))
                .collect();
            band.extend(
                (0..r.mean[j].len())
                    .rev()
                    .map(|s| (x(s), r.mean[j][s] - r.sd[j][s])),
            );
            chart.draw_series(std::iter::once(Polygon::new(band, c.mix(0.18))))?;
            chart.draw_series(LineSeries::new(
                r.mean[j].iter().enumerate().map(|(s, &m)| (x(s), m)),
                c.stroke_width(2),
            ))?;
            chart.draw_series(DashedLineSeries::new(
                r.planned[j].iter().enumerate().map(|(s, &m)| (x(s), m)),
                6,
                4,
                c.stroke_width(1),
            ))?;
        }
    }
    root.present()?;
    Ok(())
}
