//! The lines `dbot demo` prints about its walks: the body against the plan, the tracking error
//! per leg, the plan-versus-simulation fits and what the torque bias buys. The figures come from
//! the walk modules beside this one; this file only words them, in the library so that every
//! door (the CLI, Python) can print the same words.

use std::fmt::Write as _;

use crate::walk_bias::bias_gain;
use crate::walk_body::{distance, leg_tracking, planned_per_step_m};
use crate::walk_files::Walk;
use crate::walk_fits::{Fit, r2_text};
use board::record::Recorder;
use physics::Figures;

/// The body's figures of one walk against the plan (`lab::walk_body::distance`).
pub fn print_body(
    s: &mut String,
    w: &Walk,
    f: &Figures,
    plan: &planner::plan::Plan,
    steps: u32,
) -> std::fmt::Result {
    let label = w.label;
    let seconds = w.rec.duration_s();
    let d = distance(f, planned_per_step_m(plan), steps, w.direction);
    writeln!(
        s,
        "body {label} (physics robot, sampled every bus cycle over the walk's {seconds:.1} s)"
    )?;
    writeln!(
        s,
        "  distance {:.4} m per step, planned {:.4} m ({:+.1} %; the feet's stroke is {:.3} m); lateral {:+.4} m",
        d.per_step_m, d.planned_m, d.off_percent, plan.params.translation_m, f.lateral_m
    )?;
    writeln!(
        s,
        "  heading drift {:+.2} deg; thorax height {:.1} mm at the start, {:.1} mm lowest, {:.1} mm at the end (plan: constant); tilt up to {:.2} deg (plan: 0)",
        f.heading_rad.to_degrees(),
        f.height_start_m * 1e3,
        f.height_min_m * 1e3,
        f.height_end_m * 1e3,
        f.tilt_max_rad.to_degrees()
    )?;
    let slip: Vec<String> = f
        .slip_m
        .iter()
        .map(|(leg, x)| format!("{} {:.1}", leg.name(), x * 1e3))
        .collect();
    writeln!(s, "  slip while loaded, mm: {}", slip.join(", "))?;
    match f.verdict(0.01) {
        None => writeln!(
            s,
            "  the robot carried the gait (no sag over 10 mm, no fall)"
        ),
        Some(v) => writeln!(s, "  {v}"),
    }
}

/// RMS tracking error per leg, over the steps after the first (the first starts from the ramp).
pub fn print_tracking(s: &mut String, rec: &Recorder, names: &[String]) -> std::fmt::Result {
    let legs = leg_tracking(rec.rows(), names);
    // With one step there is no step after the ramp's to measure: say so rather than print
    // zeros over an empty window.
    if legs.is_empty() {
        writeln!(
            s,
            "  no tracking error: it is measured from the second step on (give --steps 2 or more)"
        )?;
        return Ok(());
    }
    for t in legs {
        writeln!(
            s,
            "  {}: RMS {:.4} rad ({:.2} deg), max {:.4} rad over {} joints",
            t.leg.name(),
            t.rms_rad,
            t.rms_rad.to_degrees(),
            t.max_abs_rad,
            t.joints
        )?;
    }
    Ok(())
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
    writeln!(s, "    {SIMULATED_LOAD}")?;
    Ok(())
}

/// What the physics robot's "servo load" is: not a measurement independent of the simulation.
pub const SIMULATED_LOAD: &str = "(physics robot: each load is the simulated joint torque turned into the Present Load \
register and back by the exact inverse of that conversion, so it is the simulation's own torque, not an \
independent ESTIMATE as on a real servo)";

/// Under what the bias's gain was measured.
pub const SIMULATED_SPRING: &str = "(measured on simulated servos that are exactly the spring the bias assumes: \
torque = k (goal - angle) with k the stiffness the bias divides by, plus only the motor's speed damping \
and stall limit; no friction, backlash or gain error, so a real servo gains less or differently)";

/// The summary lines of what the torque bias buys: posture error of the forward walk with the
/// bias against the one without it.
pub fn print_bias(
    s: &mut String,
    walks: &[Walk],
    planned_height_m: f64,
    steps: u32,
) -> std::fmt::Result {
    let Some((p_on, p_off)) = bias_gain(walks, planned_height_m, steps) else {
        return Ok(());
    };
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
    )?;
    writeln!(s, "  {SIMULATED_SPRING}")
}

/// The summary lines of one forward walk's simulated gauges against the predicted strain
/// (`lab::strain_walk`): the load-bearing gauges' median and lowest R^2, then each gauge's R^2
/// (RMS difference, microstrain), a leg a line.
pub fn print_strain(s: &mut String, label: &str, fits: &[Fit], steps: u32) -> std::fmt::Result {
    writeln!(
        s,
        "simulated gauges vs predicted strain (by the slice the firmware played, steps 2 to {steps}; strain_vs_plan.png)"
    )?;
    writeln!(s, "  {}", crate::strain_walk::summary_line(label, fits))?;
    for chunk in fits.chunks(6) {
        let line = chunk
            .iter()
            .map(|f| format!("{} {} ({:.1})", f.name, r2_text(f.r2), f.rms))
            .collect::<Vec<_>>()
            .join(", ");
        writeln!(s, "    {line}")?;
    }
    Ok(())
}
