//! A recorded walk and the files made from it after the fact: the animation of the simulated
//! body (`walk.gif`, drawn by `report::robot`) and the model-vs-measured fits written beside each
//! recording (CSVs and the GRF plot). Every file is written atomically
//! (`board::files::write_atomically`).

use std::path::{Path, PathBuf};

use board::files::{write_atomically, write_bytes_atomically};
use board::record::Recorder;
use physics::{Figures, WalkLog};
use planner::model::{Leg, Model};
use protocol::Direction;
use report::recording::{PhasePanel, plot_phase_panels};
use report::robot::{WalkPose, animate_walk};

use crate::error::Result;
use crate::walk_fits::{Fit, grf_fits, load_fits, phase_csv, r2_text};

/// A foot counts as in stance in the animation above this vertical force, N.
const STANCE_N: f64 = 1.0;
/// The animation plays this many times faster than simulated time.
const SPEEDUP: f64 = 2.0;
/// The animation's file in the output directory.
pub const WALK_GIF: &str = "walk.gif";

/// One recorded walk.
#[derive(Debug)]
pub struct Walk {
    pub label: &'static str,
    pub direction: Direction,
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
pub fn write_walk_gif(out: &Path, model: &Model, walks: &[Walk]) -> Result<(PathBuf, usize)> {
    let poses = walk_poses(model, walks);
    let dt = poses
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .find(|d| *d > 0.0)
        .unwrap_or(0.25);
    let delay_ms = (dt / SPEEDUP * 1e3).round() as u32;
    let frames: Vec<WalkPose> = poses.into_iter().map(|p| p.1).collect();
    write_atomically(&out.join(WALK_GIF), |p| {
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
) -> Result<(Vec<Fit>, Vec<Fit>)> {
    let modelled: Vec<Vec<f64>> = w
        .rec
        .joints()
        .iter()
        .map(|m| m.modelled_nm.clone())
        .collect();
    let loads = load_fits(w.rec.rows(), names, &modelled, steps);
    let grf = grf_fits(log, legs, grf_z, steps);
    let dir = &w.dir;
    write_bytes_atomically(
        &dir.join("loads_vs_plan.csv"),
        phase_csv(&loads, "joint", "nm").as_bytes(),
    )?;
    write_bytes_atomically(
        &dir.join("grf_vs_plan.csv"),
        phase_csv(&grf, "leg", "n").as_bytes(),
    )?;
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
    write_bytes_atomically(&dir.join("fit.csv"), csv.as_bytes())?;
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
    write_atomically(&dir.join("grf_vs_plan.png"), |p| {
        Ok(plot_phase_panels(
            p,
            [
                "Vertical ground reaction force per phase of the step: plan vs simulated contact force over the recorded steps",
                "simulated = MuJoCo contact force on the foot sphere, every bus cycle of the whole steps after the first",
            ],
            "N",
            &panels,
        )
        .map_err(|e| format!("plotting GRF: {e}"))?)
    })?;
    Ok((loads, grf))
}
