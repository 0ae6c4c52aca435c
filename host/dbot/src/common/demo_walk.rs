//! The demo's walks after the fact: the animation of the simulated body (`walk.gif`, drawn by
//! `report::robot`), the model-vs-measured fits written beside each recording, and the summary
//! lines of the fits and of what the torque bias buys.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use board::record::Recorder;
use physics::{Figures, WalkLog};
use planner::model::Model;
use report::robot::{WalkPose, animate_walk};

use super::demo_bias::posture;
use planner::model::Leg;
use report::recording::{PhasePanel, plot_phase_panels};

use super::demo_fit::{Fit, grf_fits, load_fits, phase_csv, r2_text};
use super::output::replace;

/// A foot counts as in stance in the animation above this vertical force, N.
const STANCE_N: f64 = 1.0;
/// The animation plays this many times faster than simulated time.
const SPEEDUP: f64 = 2.0;
/// The animation's file in the output directory.
pub const WALK_GIF: &str = "walk.gif";

/// One recorded walk.
pub struct Walk {
    pub label: &'static str,
    /// Whether the firmware added the torque bias.
    pub bias_on: bool,
    pub dir: PathBuf,
    pub rec: Recorder,
    pub wall: std::time::Duration,
    pub figures: Option<Figures>,
    pub log: Option<WalkLog>,
}

/// The poses of the walks with the bias on, in order, as animation frames.
pub fn walk_poses(model: &Model, walks: &[Walk]) -> Vec<(f64, WalkPose)> {
    let mut poses = Vec::new();
    for w in walks.iter().filter(|w| w.bias_on) {
        let Some(log) = &w.log else { continue };
        let t0 = log.samples.first().map_or(0.0, |s| s.time_s);
        for s in &log.samples {
            let Some(q) = &s.pose else { continue };
            let stance = model
                .feet
                .iter()
                .map(|f| {
                    s.foot_forces
                        .iter()
                        .any(|(leg, force)| *leg == f.leg && force[2] > STANCE_N)
                })
                .collect();
            let step = s.playback.map_or(String::new(), |(step, slice)| {
                format!(", step {step} slice {slice}")
            });
            poses.push((
                s.time_s,
                WalkPose {
                    thorax: s.thorax,
                    q: q.clone(),
                    stance,
                    caption: format!(
                        "physics robot walking {}: t = {:.2} s{step} (filled feet carry load; {SPEEDUP}x speed)",
                        w.label,
                        s.time_s - t0
                    ),
                },
            ));
        }
    }
    poses
}

/// Writes `walk.gif` into `out`; returns its path and frame count.
pub fn write_walk_gif(
    out: &Path,
    model: &Model,
    walks: &[Walk],
) -> anyhow::Result<(PathBuf, usize)> {
    let poses = walk_poses(model, walks);
    let dt = poses
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .find(|d| *d > 0.0)
        .unwrap_or(0.25);
    let delay_ms = (dt / SPEEDUP * 1e3).round() as u32;
    let frames: Vec<WalkPose> = poses.into_iter().map(|p| p.1).collect();
    replace(out, WALK_GIF, |p| {
        animate_walk(model, &frames, p, delay_ms)?;
        Ok(())
    })?;
    Ok((out.join(WALK_GIF), frames.len()))
}

/// The load and GRF fits of a walk, written beside its recording (CSVs, GRF plot): `grf_z` is
/// the plan's vertical GRF `[slice][leg]`, legs in the order `legs`.
pub fn write_fits(
    w: &Walk,
    log: &WalkLog,
    names: &[String],
    legs: &[Leg],
    grf_z: &[Vec<f64>],
    steps: u32,
) -> anyhow::Result<(Vec<Fit>, Vec<Fit>)> {
    let modelled: Vec<Vec<f64>> = w
        .rec
        .joints()
        .iter()
        .map(|m| m.modelled_nm.clone())
        .collect();
    let loads = load_fits(w.rec.rows(), names, &modelled, steps);
    let grf = grf_fits(log, legs, grf_z, steps);
    let dir = &w.dir;
    replace(dir, "loads_vs_plan.csv", |p| {
        Ok(std::fs::write(p, phase_csv(&loads, "joint", "nm"))?)
    })?;
    replace(dir, "grf_vs_plan.csv", |p| {
        Ok(std::fs::write(p, phase_csv(&grf, "leg", "n"))?)
    })?;
    let mut csv = String::from("kind,name,r2,rms,samples\n");
    for (kind, fits) in [("load_nm", &loads), ("grf_z_n", &grf)] {
        for f in fits {
            let r2 = f.r2.map_or(String::new(), |r| format!("{r:.4}"));
            csv.push_str(&format!(
                "{kind},{},{r2},{:.4},{}\n",
                f.name, f.rms, f.samples
            ));
        }
    }
    replace(dir, "fit.csv", |p| Ok(std::fs::write(p, &csv)?))?;
    let panels: Vec<PhasePanel> = grf
        .iter()
        .map(|f| PhasePanel {
            name: format!("{} (R^2 {})", f.name, r2_text(f.r2)),
            modelled: f.modelled.clone(),
            measured: f.measured.clone(),
            // The force itself shows the stance: no shading.
            stance: Vec::new(),
        })
        .collect();
    replace(dir, "grf_vs_plan.png", |p| {
        plot_phase_panels(
            p,
            [
                "Vertical ground reaction force per phase of the step: plan vs simulated contact force over the recorded steps",
                "simulated = MuJoCo contact force on the foot sphere, every bus cycle of the whole steps after the first",
            ],
            "N",
            &panels,
        )
        .map_err(|e| anyhow::anyhow!("plotting GRF: {e}"))
    })?;
    Ok((loads, grf))
}

/// The summary lines of one walk's fits.
pub fn print_fits(
    s: &mut String,
    label: &str,
    loads: &[Fit],
    grf: &[Fit],
    steps: u32,
) -> std::fmt::Result {
    let window = if steps >= 2 {
        format!("steps 2 to {steps}")
    } else {
        "no whole step after the first: give --steps 2 or more".to_owned()
    };
    writeln!(
        s,
        "model vs simulation {label} (R^2 over every bus cycle of {window}; 1 = the plan predicts every sample, 0 = no better than the mean)"
    )?;
    let list = |fits: &[Fit], unit: &str| -> String {
        fits.iter()
            .map(|f| format!("{} {} ({:.2} {unit})", f.name, r2_text(f.r2), f.rms))
            .collect::<Vec<_>>()
            .join(", ")
    };
    writeln!(
        s,
        "  vertical contact force vs the plan's GRF per leg, R^2 (RMS difference): {}",
        list(grf, "N")
    )?;
    writeln!(
        s,
        "  servo load (ESTIMATE from Present Load) vs planned torque per joint, R^2 (RMS difference):"
    )?;
    for chunk in loads.chunks(6) {
        writeln!(s, "    {}", list(chunk, "N m"))?;
    }
    Ok(())
}

/// The summary lines of what the torque bias buys: posture error of the forward walk with the
/// bias against the one without it.
pub fn print_bias(
    s: &mut String,
    walks: &[Walk],
    planned_height_m: f64,
    steps: u32,
) -> std::fmt::Result {
    let find = |bias_on: bool| {
        walks
            .iter()
            .find(|w| w.bias_on == bias_on && w.label.starts_with("forward"))
    };
    let (Some(on), Some(off)) = (find(true), find(false)) else {
        return Ok(());
    };
    let (Some(log_on), Some(log_off)) = (&on.log, &off.log) else {
        return Ok(());
    };
    let p_on = posture(on.rec.rows(), log_on, planned_height_m, steps, true);
    let p_off = posture(off.rec.rows(), log_off, planned_height_m, steps, false);
    writeln!(
        s,
        "torque bias (forward walk with it vs without it, stiffness 0 on every joint; steps 2 to {steps})"
    )?;
    writeln!(
        s,
        "  joint angle error (present - planned, RMS over joints and cycles): bias on {:.4} rad ({:.2} deg), bias off {:.4} rad ({:.2} deg)",
        p_on.rms_rad,
        p_on.rms_rad.to_degrees(),
        p_off.rms_rad,
        p_off.rms_rad.to_degrees()
    )?;
    writeln!(
        s,
        "  thorax sag below the planned {:.1} mm: bias on {:.1} mm mean, {:.1} mm most; bias off {:.1} mm mean, {:.1} mm most",
        planned_height_m * 1e3,
        p_on.sag_mean_m * 1e3,
        p_on.sag_max_m * 1e3,
        p_off.sag_mean_m * 1e3,
        p_off.sag_max_m * 1e3
    )?;
    let verdict = if p_off.rms_rad > p_on.rms_rad && p_off.sag_mean_m > p_on.sag_mean_m {
        "the bias buys"
    } else {
        "NOT a gain on both counts: the bias buys"
    };
    writeln!(
        s,
        "  {verdict} {:.4} rad less joint error ({:.0} %) and {:.1} mm less mean sag",
        p_off.rms_rad - p_on.rms_rad,
        (1.0 - p_on.rms_rad / p_off.rms_rad.max(1e-12)) * 100.0,
        (p_off.sag_mean_m - p_on.sag_mean_m) * 1e3
    )
}
