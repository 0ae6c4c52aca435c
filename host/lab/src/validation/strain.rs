//! The `strain` block of docs/validation.md: the physics robot's simulated gauges against the
//! planner's prediction, standing still on flat ground with the torque bias on and off (issue 26
//! item 3). Both readings come from `planner::strain::slice_readings`; the prediction with the QP's
//! foot forces at the planned posture, the simulation with MuJoCo's state and contact forces
//! after 3 s (gravity ramps in over the first second).

use std::fmt::Write;

use physics::{PhysicsRobot, Plant, SimulatedGauges};
use planner::analysis::fit::{prediction_r2, rms_difference};
use planner::dynamics::{DynamicsOptions, SliceInput, solve_slice};
use planner::model::builtin;

use crate::error::{Context, Result};

/// One standing comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct StandingStrain {
    /// 1 with the torque bias, 0 without.
    pub bias: f64,
    /// RMS of simulated less predicted, over RMS of predicted.
    pub relative_rms: f64,
    /// R^2 of the prediction for the simulated readings (over the 36 gauges).
    pub r2: Option<f64>,
    /// The gauge furthest off and by how much, microstrain.
    pub worst: (String, f64),
    /// The largest predicted |reading|, microstrain.
    pub peak: f64,
}

/// Stands Drosophibot II for 3 s with goals `q + bias tau / k` and compares its gauges.
pub fn standing(bias: f64) -> Result<StandingStrain> {
    let model = builtin("drosophibot2")?;
    let options = PhysicsRobot::options(&model, &planner::terrain::Ground::Flat)?;
    let q = options.stance_q.clone();
    let still = SliceInput::still(&model, q.clone());
    let sol = solve_slice(&model, &still, &DynamicsOptions::default(), 0)?;
    let sites = planner::strain::sites(&model).context("the model's gauges")?;
    let predicted = planner::strain::slice_readings(&model, &sites, &still, &sol.grf);
    let mut plant = Plant::new(&model, &options)?;
    for i in 0..plant.joints().len() {
        let j = plant.joints()[i].clone();
        plant.set_goal(i, q[j.joint] + bias * sol.torque[j.joint] / j.kp, true);
    }
    plant.advance_to(3.0);
    let sim = SimulatedGauges::new(&model, &plant)
        .context("the model's gauges")?
        .read(&plant);
    let pairs: Vec<(f64, f64)> = predicted
        .iter()
        .zip(&sim.readings)
        .map(|(p, s)| (p.microstrain, s.microstrain))
        .collect();
    let rms_p = planner::analysis::fit::rms(pairs.iter().map(|p| p.0)).unwrap_or(0.0);
    let mut worst = (String::new(), 0.0f64);
    for (n, (p, s)) in sim.names.iter().zip(&pairs) {
        if (s - p).abs() > worst.1 {
            worst = (n.clone(), (s - p).abs());
        }
    }
    Ok(StandingStrain {
        bias,
        relative_rms: rms_difference(&pairs).unwrap_or(0.0) / rms_p,
        r2: prediction_r2(&pairs),
        worst,
        peak: pairs.iter().map(|p| p.0.abs()).fold(0.0, f64::max),
    })
}

/// The block's table.
pub fn block() -> Result<String> {
    let mut s = String::from(
        "| torque bias | RMS of simulated - predicted | R^2 of the prediction | worst gauge | largest predicted |\n|---|---|---|---|---|\n",
    );
    for bias in [1.0, 0.0] {
        let c = standing(bias)?;
        writeln!(
            s,
            "| {} | {:.2} % | {} | {} {:.1} microstrain | {:.1} microstrain |",
            if bias > 0.0 { "on" } else { "off" },
            c.relative_rms * 100.0,
            crate::plan_comparison::r2_cell(c.r2),
            c.worst.0,
            c.worst.1,
            c.peak
        )?;
    }
    Ok(s)
}
