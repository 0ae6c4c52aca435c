//! docs/validation.md's `turning` block: planned curves walked on the physics robot
//! ([`crate::walk_turn`]), the turn per step and radius measured against the plan's, and issue 28's
//! run of straight, a 90 deg left curve and backward as queued gaits ([`crate::walk_sequence`]).

use std::fmt::Write as _;

use planner::gait::{StepParams, Turn};
use planner::model::builtin;

use crate::error::{Context, Result};
use crate::walk_sequence::ninety_degree_run;
use crate::walk_turn::walk_turn;

/// Slices per step of the walked plans (coarse: the walks measure the thorax, not the joints).
const SLICES: usize = 50;
/// Steps per measured walk: the curve is measured over steps 1 to 3 (step 0 starts from standing).
const STEPS: u32 = 3;

/// The curves walked, as `dbot plan --turn DEG --radius M` takes them (the two tight right turns
/// faulted in a start ramp that did not lift the legs).
const CURVES: [(Option<f64>, Option<f64>); 9] = [
    (None, Some(0.5)),
    (Some(10.0), None),
    (Some(30.0), None),
    (None, Some(-1.0)),
    (Some(-5.0), None),
    (Some(-10.0), None),
    (None, Some(-0.5)),
    (Some(20.0), Some(0.0)),
    (Some(-20.0), Some(0.0)),
];

fn flags(turn: Option<f64>, radius: Option<f64>) -> String {
    let mut s = Vec::new();
    if let Some(t) = turn {
        s.push(format!("--turn {t}"));
    }
    if let Some(r) = radius {
        s.push(format!("--radius {r}"));
    }
    s.join(" ")
}

/// The block's markdown.
pub fn turning() -> Result<String> {
    let model = builtin("drosophibot2")?;
    let mut base = StepParams::preset("servo-safe", &model.name).expect("a built-in preset");
    base.slices = SLICES;
    let mut s = String::new();
    writeln!(
        s,
        "Drosophibot II, servo-safe preset ({SLICES} slices), flat ground, {STEPS} steps from standing, the curve measured between the ends of steps 1 and {STEPS} (the first starts the body moving; `lab::walk_turn`):\n"
    )?;
    writeln!(
        s,
        "| `dbot plan` | turn per step, planned | measured | off | radius, planned | measured | centre ahead |"
    )?;
    writeln!(s, "|---|---|---|---|---|---|---|")?;
    for (turn, radius) in CURVES {
        let mut p = base.clone();
        Turn {
            turn_deg: turn,
            radius_m: radius,
        }
        .apply(&mut p)
        .context("a curve of the turning block")?;
        let w = walk_turn(&model, &p, STEPS)?;
        let (plan, m) = (w.planned, w.measured);
        let planned_r = plan.radius_m.unwrap_or(f64::INFINITY);
        writeln!(
            s,
            "| `{}` | {:.2} deg | {:.2} deg | {:+.1} % | {:.3} m | {:.3} m | {:.1} mm |",
            flags(turn, radius),
            plan.turn_per_step_rad.to_degrees(),
            m.turn_per_step_rad.to_degrees(),
            (m.turn_per_step_rad / plan.turn_per_step_rad - 1.0) * 100.0,
            planned_r,
            m.radius_m,
            m.centre_ahead_m * 1e3,
        )?;
    }
    let (w, turn) = ninety_degree_run(&model, &base)?;
    let radius = turn.turn_radius_m().unwrap_or(f64::INFINITY);
    writeln!(
        s,
        "\nOne run of queued gaits (`lab::walk_sequence`): 2 steps straight, 15 steps of `--turn 6` (radius {radius:.3} m), 2 steps straight backward, stop: {} steps, {}; heading change {:.1} deg against the plans' {:.1} deg ({:+.1} %); the curve's 15 steps {:.1} deg, the straight parts {:.2} and {:.2} deg; thorax {:.1} mm at the lowest from {:.1} mm.",
        w.steps,
        if w.stood_between {
            "stood between gaits"
        } else {
            "no stand between gaits"
        },
        w.measured_heading_rad.to_degrees(),
        w.planned_heading_rad.to_degrees(),
        (w.measured_heading_rad / w.planned_heading_rad - 1.0) * 100.0,
        w.segments[1].measured_rad.to_degrees(),
        w.segments[0].measured_rad.to_degrees(),
        w.segments[2].measured_rad.to_degrees(),
        w.figures.height_min_m * 1e3,
        w.figures.height_start_m * 1e3,
    )?;
    Ok(s)
}
