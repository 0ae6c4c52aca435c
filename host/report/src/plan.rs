//! PNG plots of a plan: joint angles per leg with stance shaded (as figure 3 of the paper),
//! the footfall pattern, and foot trajectories (top and side views).

use crate::legend::{COLUMN_W, Entry, STANCE, Swatch, legend_column};
use crate::legs::panel_index;
use crate::style::{colour, register_font};
use planner::plan::Plan;
use planner::plan_dir::ReportError;

use plotters::prelude::*;
use std::path::Path;

fn perr<E: std::fmt::Display>(e: E) -> ReportError {
    ReportError::Plot(e.to_string())
}

/// Stance intervals of leg `li` as (start, end) times.
fn stance_spans(plan: &Plan, li: usize) -> Vec<(f64, f64)> {
    let mut spans = Vec::new();
    let mut start = None;
    for s in 0..plan.slices() {
        match (plan.stance[s][li], start) {
            (true, None) => start = Some(plan.time(s)),
            (false, Some(t0)) => {
                spans.push((t0, plan.time(s)));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(t0) = start {
        spans.push((t0, plan.period_s));
    }
    spans
}

/// One panel per leg: actuated joint angles (deg) over the cycle, stance shaded grey.
pub fn plot_joint_angles(plan: &Plan, path: &Path) -> Result<(), ReportError> {
    register_font();
    let root = crate::Bitmap::new(path, (1400, 1100)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let panels = root.split_evenly((3, 2));
    for (li, leg) in plan.legs.iter().enumerate() {
        let (area, key) = panels[panel_index(*leg)].split_horizontally(700 - COLUMN_W);
        let area = &area;
        let joints: Vec<usize> = plan
            .model
            .leg_chain(*leg)
            .into_iter()
            .filter(|&j| plan.model.is_actuated(j))
            .collect();
        let deg = |s: usize, j: usize| plan.q[s][j].to_degrees();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for s in 0..plan.slices() {
            for &j in &joints {
                lo = lo.min(deg(s, j));
                hi = hi.max(deg(s, j));
            }
        }
        let pad = ((hi - lo) * 0.1).max(1.0);
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("{} joint angles (shaded: stance)", leg.name()),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..plan.period_s, (lo - pad)..(hi + pad))
            .map_err(perr)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("angle (deg)")
            .draw()
            .map_err(perr)?;
        for (t0, t1) in stance_spans(plan, li) {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0, lo - pad), (t1, hi + pad)],
                    STANCE.filled(),
                )))
                .map_err(perr)?;
        }
        for (k, &j) in joints.iter().enumerate() {
            let c = colour(k);
            chart
                .draw_series(LineSeries::new(
                    (0..plan.slices()).map(|s| (plan.time(s), deg(s, j))),
                    c.stroke_width(2),
                ))
                .map_err(perr)?;
        }
        let mut entries: Vec<Entry> = joints
            .iter()
            .enumerate()
            .map(|(k, &j)| {
                Entry::new(
                    plan.model.joints[j].kind.name().to_string(),
                    Swatch::Line(colour(k)),
                )
            })
            .collect();
        entries.push(Entry::new("stance", Swatch::Shade(STANCE)));
        legend_column(&key, &entries).map_err(ReportError::Plot)?;
    }
    root.present().map_err(perr)
}

/// Footfall pattern: a black bar per leg while its foot is down.
pub fn plot_footfall(plan: &Plan, path: &Path) -> Result<(), ReportError> {
    register_font();
    let root = crate::Bitmap::new(path, (1000, 400)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let n = plan.legs.len() as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption("Footfall pattern (black: stance)", ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..plan.period_s, 0.0..n)
        .map_err(perr)?;
    let legs = plan.legs.clone();
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_labels(legs.len() * 2 + 1)
        .y_label_formatter(&|y| {
            let i = (n - y - 0.5).round();
            if (n - y - 0.5 - i).abs() < 0.01 && i >= 0.0 && (i as usize) < legs.len() {
                legs[i as usize].name().to_string()
            } else {
                String::new()
            }
        })
        .draw()
        .map_err(perr)?;
    for li in 0..plan.legs.len() {
        let y0 = n - li as f64 - 0.85;
        for (t0, t1) in stance_spans(plan, li) {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(t0, y0), (t1, y0 + 0.7)],
                    BLACK.filled(),
                )))
                .map_err(perr)?;
        }
    }
    root.present().map_err(perr)
}

/// Foot trajectories in the thorax frame: top view (x, y) and side view (x, z).
pub fn plot_feet(plan: &Plan, path: &Path) -> Result<(), ReportError> {
    register_font();
    let root = crate::Bitmap::new(path, (1400, 650)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let (views, key) = root.split_horizontally(1400 - COLUMN_W);
    let (left, right) = views.split_horizontally(640);
    let all = plan.feet.iter().flatten();
    let (mut min, mut max) = (
        nalgebra::Vector3::repeat(f64::INFINITY),
        nalgebra::Vector3::repeat(f64::NEG_INFINITY),
    );
    for p in all {
        min = min.inf(p);
        max = max.sup(p);
    }
    let pad = (max - min).max() * 0.05 + 1e-9;
    for (area, (a, b), title) in [
        (&left, (0usize, 1usize), "top view: y (m) vs x (m)"),
        (&right, (0, 2), "side view: z (m) vs x (m)"),
    ] {
        let mut chart = ChartBuilder::on(area)
            .caption(format!("Foot trajectories, {title}"), ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d(
                (min[a] - pad)..(max[a] + pad),
                (min[b] - pad)..(max[b] + pad),
            )
            .map_err(perr)?;
        chart.configure_mesh().draw().map_err(perr)?;
        for li in 0..plan.legs.len() {
            let c = colour(li);
            let pts: Vec<(f64, f64)> = (0..=plan.slices())
                .map(|s| {
                    let p = plan.feet[s % plan.slices()][li];
                    (p[a], p[b])
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                .map_err(perr)?;
        }
    }
    let entries: Vec<Entry> = plan
        .legs
        .iter()
        .enumerate()
        .map(|(li, leg)| Entry::new(format!("{} foot", leg.name()), Swatch::Line(colour(li))))
        .collect();
    legend_column(&key, &entries).map_err(ReportError::Plot)?;
    root.present().map_err(perr)
}
