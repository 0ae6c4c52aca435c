//! The recording's figures: modelled torque against the torque estimated from the servos' load
//! registers, averaged per phase of the step with one standard deviation shaded (the paper's
//! figure 5), and commanded against present joint angles over time; the stance of each joint's
//! leg shaded. Each figure names what it draws in a legend strip between its title and its
//! panels, so the legend covers no data. PNG via plotters with an embedded font (no system fonts
//! needed).

use std::path::Path;

use plotters::prelude::*;

use crate::legend::{Entry, ROW_H, STANCE, Swatch, legend_row};
use crate::style::register_font;
use board::record::JointMeta;
use board::record::Row;
use board::record::{PhaseStats, phase_stats};

type PlotResult = Result<(), Box<dyn std::error::Error>>;

const COLS: usize = 4;

/// The measured torque's +-1 SD band: blue at 20 % over white (the legend's swatch is opaque).
const BAND_ALPHA: f64 = 0.2;
/// [`BAND_ALPHA`] of blue over white, as the legend shows it.
pub const BAND: RGBColor = RGBColor(204, 204, 255);

/// The legend entry of the stance shading.
fn stance_entry(what: &str) -> Entry {
    Entry::new(
        format!("stance of the joint's leg{what}"),
        Swatch::Shade(STANCE),
    )
}

/// Runs of consecutive `true` in `flags`, as index ranges.
fn runs(flags: impl IntoIterator<Item = bool>) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut start = None;
    let mut n = 0;
    for (i, f) in flags.into_iter().enumerate() {
        match (f, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push(s..i);
                start = None;
            }
            _ => {}
        }
        n = i + 1;
    }
    if let Some(s) = start {
        out.push(s..n);
    }
    out
}

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
    /// Per slice, whether the panel's leg is in stance (shaded; empty: no shading).
    pub stance: Vec<bool>,
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
            stance: meta.stance.clone(),
        })
        .collect();
    plot_phase_panels(
        path,
        [
            "Joint torque per phase of the step: modelled vs measured over the recorded steps",
            "measured = ESTIMATE from Present Load (MX-28) / Present Current (MX-64), see dynamixel::units",
        ],
        "N m",
        &panels,
    )
}

/// The layout of figure 5 for any quantity: one panel per item, the model (black) over the phase
/// of the step and the measured mean with +-1 SD shaded (blue), the leg's stance shaded grey; two
/// title lines and a legend row above.
pub fn plot_phase_panels(
    path: &Path,
    titles: [&str; 2],
    unit: &str,
    panels: &[PhasePanel],
) -> PlotResult {
    register_font();
    let (r, c) = grid(panels.len());
    let head = 60 + ROW_H;
    let root =
        crate::Bitmap::new(path, (420 * c as u32, 260 * r as u32 + head)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(head);
    let (l1, rest) = title.split_vertically(30);
    let (l2, key) = rest.split_vertically(30);
    l1.titled(titles[0], ("sans-serif", 18))?;
    l2.titled(titles[1], ("sans-serif", 16))?;
    let mut entries = vec![
        Entry::new("modelled (plan)", Swatch::Line(BLACK)),
        Entry::new("measured, mean over steps", Swatch::Line(BLUE)),
        Entry::new("measured, +-1 SD", Swatch::Shade(BAND)),
    ];
    if panels.iter().any(|p| !p.stance.is_empty()) {
        entries.push(stance_entry(""));
    }
    legend_row(&key, &entries)?;
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
        let n = panel.stance.len().max(1) as f64;
        let (y0, y1) = (lo - pad, hi + pad);
        chart.draw_series(runs(panel.stance.iter().copied()).into_iter().map(|r| {
            Rectangle::new(
                [(r.start as f64 / n, y0), (r.end as f64 / n, y1)],
                STANCE.filled(),
            )
        }))?;
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
            chart.draw_series(std::iter::once(Polygon::new(band, BLUE.mix(BAND_ALPHA))))?;
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
    let head = 40 + ROW_H;
    let root =
        crate::Bitmap::new(path, (420 * c as u32, 260 * r as u32 + head)).into_drawing_area();
    root.fill(&WHITE)?;
    let (title, body) = root.split_vertically(head);
    let (l1, key) = title.split_vertically(40);
    l1.titled(
        "Joint angles over the recording: commanded vs present",
        ("sans-serif", 18),
    )?;
    let mut entries = vec![
        Entry::new(
            "commanded goal incl. torque bias (while torque is on)",
            Swatch::Line(RED),
        ),
        Entry::new("present", Swatch::Line(BLUE)),
    ];
    if joints.iter().any(|j| !j.stance.is_empty()) {
        entries.push(stance_entry(" (while the gait plays)"));
    }
    legend_row(&key, &entries)?;
    let t_end = rows.last().map_or(1.0, |r| r.time_s.max(1e-3));
    for (panel, (j, meta)) in body
        .split_evenly((r, c))
        .iter()
        .zip(joints.iter().enumerate())
    {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.joint == j).collect();
        // A goal is only meaningful while torque is on.
        let driven = |r: &&Row| r.flags & protocol::feedback_flags::TORQUE_OFF == 0;
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for r in &mine {
            lo = lo.min(r.present_rad);
            hi = hi.max(r.present_rad);
        }
        for r in mine.iter().filter(|r| driven(r)) {
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
        let (y0, y1) = (lo - pad, hi + pad);
        for span in stance_spans(&mine, &meta.stance) {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(span.0, y0), (span.1, y1)],
                STANCE.filled(),
            )))?;
        }
        chart
            .configure_mesh()
            .x_desc("s")
            .y_desc("rad")
            .label_style(("sans-serif", 11))
            .draw()?;
        // The goal is drawn only while torque is on; a gap where it was off.
        for run in runs(mine.iter().map(driven)) {
            chart.draw_series(LineSeries::new(
                mine[run].iter().map(|r| (r.time_s, r.commanded_rad)),
                &RED,
            ))?;
        }
        chart.draw_series(LineSeries::new(
            mine.iter().map(|r| (r.time_s, r.present_rad)),
            &BLUE,
        ))?;
    }
    root.present()?;
    Ok(())
}

/// Time spans of one joint's rows (time order) in which its leg is in stance while the gait plays.
/// The rows fall into runs of one (step, slice); while the gait plays a run lasts one slice's
/// time, while the robot stands (before the ramp, after the last step) the run lasts as long as
/// it stands. So a run counts as playing when it is at most twice the median run's length: the
/// median is a slice's time when most of the recording walks. A span runs to the next row's time.
fn stance_spans(rows: &[&Row], stance: &[bool]) -> Vec<(f64, f64)> {
    let at = |i: usize| (rows[i].step, rows[i].slice);
    let mut bounds = vec![0];
    bounds.extend((1..rows.len()).filter(|&i| at(i) != at(i - 1)));
    bounds.push(rows.len());
    let mut lengths: Vec<usize> = bounds.windows(2).map(|w| w[1] - w[0]).collect();
    lengths.sort_unstable();
    let Some(&median) = lengths.get(lengths.len() / 2) else {
        return Vec::new();
    };
    let mut in_stance = vec![false; rows.len()];
    for w in bounds.windows(2) {
        let (a, b) = (w[0], w[1]);
        let leg_in_stance = stance.get(usize::from(rows[a].slice)).copied();
        if b - a <= 2 * median && leg_in_stance == Some(true) {
            in_stance[a..b].fill(true);
        }
    }
    runs(in_stance)
        .into_iter()
        .map(|r| {
            let end = rows.get(r.end).unwrap_or(&rows[r.end - 1]).time_s;
            (rows[r.start].time_s, end)
        })
        .collect()
}
