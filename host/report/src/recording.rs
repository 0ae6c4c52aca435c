//! The recording's figures: modelled torque against the torque estimated from the servos' load
//! registers, averaged per phase of the step with one standard deviation shaded (the paper's
//! figure 5), and commanded against present joint angles over time. PNG via plotters with an
//! embedded font (no system fonts needed).

use std::path::Path;

use plotters::prelude::*;

use crate::style::register_font;
use board::record::JointMeta;
use board::record::Row;
use board::record::{PhaseStats, phase_stats};

type PlotResult = Result<(), Box<dyn std::error::Error>>;

const COLS: usize = 4;

fn grid(n: usize) -> (usize, usize) {
    (n.div_ceil(COLS).max(1), COLS)
}

/// One panel of a model-vs-measured figure: the model per slice of the step and the measured
/// statistics per phase.
#[derive(Debug, Clone, PartialEq)]
pub struct PhasePanel {
    pub name: String,
    /// Modelled value per slice (slice s at phase s / len).
    pub modelled: Vec<f64>,
    pub measured: Vec<PhaseStats>,
}

/// Figure 5: per joint, modelled torque over the phase of the step and the estimated measured
/// torque (mean, +-1 standard deviation shaded) over the recorded steps.
pub fn plot_torques(path: &Path, rows: &[Row], joints: &[JointMeta], slices: usize) -> PlotResult {
    let panels: Vec<PhasePanel> = joints
        .iter()
        .enumerate()
        .map(|(j, meta)| PhasePanel {
            name: meta.name.clone(),
            modelled: meta.modelled_nm.clone(),
            measured: phase_stats(rows, j, slices),
        })
        .collect();
    plot_phase_panels(
        path,
        [
            "Joint torque per phase of the step: modelled (black) vs measured (blue: mean, shaded +-1 SD over steps)",
            "measured = ESTIMATE from Present Load (MX-28) / Present Current (MX-64), see dynamixel::units",
        ],
        "N m",
        &panels,
    )
}

/// The layout of figure 5 for any quantity: one panel per item, the model (black) over the phase
/// of the step and the measured mean with +-1 SD shaded (blue); two title lines above.
pub fn plot_phase_panels(
    path: &Path,
    titles: [&str; 2],
    unit: &str,
    panels: &[PhasePanel],
) -> PlotResult {
    register_font();
    let (r, c) = grid(panels.len());
    let root = crate::Bitmap::new(path, (420 * c as u32, 260 * r as u32 + 60)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(60);
    let (l1, l2) = title.split_vertically(30);
    l1.titled(titles[0], ("sans-serif", 18))?;
    l2.titled(titles[1], ("sans-serif", 16))?;
    for (area, panel) in body.split_evenly((r, c)).iter().zip(panels) {
        let st = &panel.measured;
        let mut lo: f64 = -0.1;
        let mut hi: f64 = 0.1;
        for s in st {
            lo = lo.min(s.mean_nm - s.sd_nm);
            hi = hi.max(s.mean_nm + s.sd_nm);
        }
        for &m in &panel.modelled {
            lo = lo.min(m);
            hi = hi.max(m);
        }
        let pad = 0.05 * (hi - lo);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.name, ("sans-serif", 16))
            .margin(6)
            .x_label_area_size(28)
            .y_label_area_size(48)
            .build_cartesian_2d(0.0..1.0, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("phase")
            .y_desc(unit)
            .label_style(("sans-serif", 11))
            .draw()?;
        if !st.is_empty() {
            let mut band: Vec<(f64, f64)> =
                st.iter().map(|s| (s.phase, s.mean_nm + s.sd_nm)).collect();
            band.extend(st.iter().rev().map(|s| (s.phase, s.mean_nm - s.sd_nm)));
            chart.draw_series(std::iter::once(Polygon::new(band, BLUE.mix(0.2))))?;
            chart.draw_series(LineSeries::new(
                st.iter().map(|s| (s.phase, s.mean_nm)),
                &BLUE,
            ))?;
        }
        let n = panel.modelled.len().max(1) as f64;
        chart.draw_series(LineSeries::new(
            panel
                .modelled
                .iter()
                .enumerate()
                .map(|(s, &m)| (s as f64 / n, m)),
            BLACK.stroke_width(2),
        ))?;
    }
    root.present()?;
    Ok(())
}

/// Per joint, commanded (goal after the torque bias) and present angle over the recording.
pub fn plot_angles(path: &Path, rows: &[Row], joints: &[JointMeta]) -> PlotResult {
    register_font();
    let (r, c) = grid(joints.len());
    let root = crate::Bitmap::new(path, (420 * c as u32, 260 * r as u32 + 40)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(40);
    title.titled(
        "Joint angles: commanded goal incl. torque bias (red, while torque is on) vs present (blue)",
        ("sans-serif", 18),
    )?;
    let t_end = rows.last().map_or(1.0, |r| r.time_s.max(1e-3));
    for (panel, (j, meta)) in body
        .split_evenly((r, c))
        .iter()
        .zip(joints.iter().enumerate())
    {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.joint == j).collect();
        // A goal is only meaningful while torque is on.
        let driven = |r: &&&Row| r.flags & protocol::feedback_flags::TORQUE_OFF == 0;
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for r in &mine {
            lo = lo.min(r.present_rad);
            hi = hi.max(r.present_rad);
        }
        for r in mine.iter().filter(driven) {
            lo = lo.min(r.commanded_rad);
            hi = hi.max(r.commanded_rad);
        }
        if lo > hi {
            (lo, hi) = (-1.0, 1.0);
        }
        let pad = 0.05 * (hi - lo).max(1e-3);
        let mut chart = ChartBuilder::on(panel)
            .caption(&meta.name, ("sans-serif", 16))
            .margin(6)
            .x_label_area_size(28)
            .y_label_area_size(48)
            .build_cartesian_2d(0.0..t_end, (lo - pad)..(hi + pad))?;
        chart
            .configure_mesh()
            .x_desc("s")
            .y_desc("rad")
            .label_style(("sans-serif", 11))
            .draw()?;
        chart.draw_series(LineSeries::new(
            mine.iter().map(|r| (r.time_s, r.commanded_rad)),
            &RED,
        ))?;
        chart.draw_series(LineSeries::new(
            mine.iter().map(|r| (r.time_s, r.present_rad)),
            &BLUE,
        ))?;
    }
    root.present()?;
    Ok(())
}
