//! The perturbation platform's effect as a picture: the perturbed leg's foot load (peak and mean
//! normal force in a window at the start of each step) step by step, the perturbed step marked.

use std::path::Path;

use plotters::prelude::*;

use crate::legs::PlotError;
use crate::style::{colour, register_font};

/// One step's load on the perturbed leg's foot, N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepBar {
    pub step: u32,
    pub peak_n: f64,
    pub mean_n: f64,
}

/// Bars of each step's peak and mean load on `leg`'s foot in the first `window_ms` of the step,
/// the `perturbed` step's drawn in the second colour.
pub fn plot_step_loads(
    path: &Path,
    leg: &str,
    window_ms: f64,
    steps: &[StepBar],
    perturbed: u32,
) -> Result<(), PlotError> {
    let fail = |e: &dyn std::fmt::Display| PlotError {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    if steps.is_empty() {
        return Err(fail(&"no steps to plot"));
    }
    register_font();
    let root = crate::Bitmap::new(path, (900, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let top = steps.iter().map(|s| s.peak_n).fold(0.0f64, f64::max) * 1.15 + 1e-9;
    let last = steps.iter().map(|s| s.step).max().unwrap_or(0);
    let mut chart = ChartBuilder::on(&root)
        .margin(12)
        .caption(
            format!(
                "{leg} foot load in the first {window_ms:.0} ms of each step (step {perturbed} perturbed)"
            ),
            ("sans-serif", 17),
        )
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(-0.5..f64::from(last) + 0.5, 0.0..top)
        .map_err(|e| fail(&e))?;
    chart
        .configure_mesh()
        .x_desc("step (from 0)")
        .y_desc("normal force (N)")
        .x_labels(steps.len() + 1)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .light_line_style(WHITE)
        .draw()
        .map_err(|e| fail(&e))?;
    let plain = colour(0);
    let hit = colour(1);
    for s in steps {
        let x = f64::from(s.step);
        let c = if s.step == perturbed { hit } else { plain };
        chart
            .draw_series([
                Rectangle::new([(x - 0.38, 0.0), (x - 0.02, s.peak_n)], c.filled()),
                Rectangle::new(
                    [(x + 0.02, 0.0), (x + 0.38, s.mean_n)],
                    c.mix(0.45).filled(),
                ),
            ])
            .map_err(|e| fail(&e))?;
    }
    chart
        .draw_series(std::iter::once(Text::new(
            "left bar: peak, right bar: mean",
            (-0.4, top * 0.95),
            ("sans-serif", 13),
        )))
        .map_err(|e| fail(&e))?;
    root.present().map_err(|e| fail(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plot_is_a_png_of_its_size_and_no_steps_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("loads.png");
        let bars: Vec<StepBar> = (0..5)
            .map(|k| StepBar {
                step: k,
                peak_n: 4.0 + f64::from(k == 3) * 2.0,
                mean_n: 3.0,
            })
            .collect();
        plot_step_loads(&p, "RF", 150.0, &bars, 3).unwrap();
        let img = png::Decoder::new(std::fs::File::open(&p).unwrap());
        let info = img.read_info().unwrap().info().clone();
        assert_eq!((info.width, info.height), (900, 520));
        let e = plot_step_loads(&p, "RF", 150.0, &[], 3).unwrap_err();
        assert!(e.to_string().contains("no steps to plot"), "{e}");
    }
}
