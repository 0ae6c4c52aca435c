//! Whether the servos can follow a plan: reported by `dbot plan` (feasibility.csv, plan.json,
//! terminal); the override flag of the rule that `dbot table`, `dbot upload --plan` and `dbot run
//! --period` enforce through the library (`board::rules`), and the printing of its warning.

use board::rules::{Overridden, Overrides};
use planner::plan::feasibility::{Feasibility, Violation};

/// The override of the servo-feasibility check.
#[derive(Debug, Clone, clap::Args)]
pub struct FeasibilityArgs {
    /// Build, upload or play the table even when a servo cannot follow it (speed over the no-load
    /// speed, torque over stall or over the torque-speed line, an inverse-kinematics jump; for
    /// `run --period`, at the period asked for).
    #[arg(long)]
    pub allow_infeasible: bool,
}

impl FeasibilityArgs {
    /// The library's override.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            allow_infeasible: self.allow_infeasible,
        }
    }
}

/// Prints what the override let through (the library's words) on stderr.
pub fn warn(warning: Option<&Overridden>) {
    if let Some(w) = warning {
        eprintln!("warning: {w}");
    }
}

/// The `feasibility` object of plan.json.
pub fn json(f: &Feasibility) -> serde_json::Value {
    let joints: serde_json::Map<String, serde_json::Value> = f
        .joints
        .iter()
        .map(|j| {
            (
                j.joint.clone(),
                serde_json::json!({
                    "servo": j.limits.map(|l| l.name),
                    "no_load_speed_rad_s": j.limits.map(|l| l.no_load_speed),
                    "stall_torque_nm": j.limits.map(|l| l.stall_torque),
                    "peak_speed_rad_s": j.speed.value,
                    "peak_speed_slice": j.speed.slice,
                    "peak_acceleration_rad_s2": j.acceleration.value,
                    "peak_acceleration_slice": j.acceleration.slice,
                    "peak_torque_nm": j.torque.map(|p| p.value),
                    "peak_torque_slice": j.torque.map(|p| p.slice),
                    "torque_speed_margin_nm": j.torque_speed_margin.map(|p| p.value),
                    "torque_speed_margin_slice": j.torque_speed_margin.map(|p| p.slice),
                }),
            )
        })
        .collect();
    serde_json::json!({
        "limits_note": "servo limits are Dynamixel e-manual datasheet values at 12 V (no-load speed, stall torque); the torque-speed line T_stall (1 - |w|/w0) is an estimate; no acceleration limit is checked",
        "feasible": f.is_feasible(),
        "violations": f.violations.iter().map(|v| v.to_string()).collect::<Vec<_>>(),
        "joints": joints,
    })
}

/// The lines `dbot plan` prints: a count, and the first few violations.
pub fn summary(f: &Feasibility) -> String {
    if f.is_feasible() {
        return "servos can follow the plan (speed, torque, torque-speed line, no IK jumps)".into();
    }
    let first: Vec<String> = f
        .violations
        .iter()
        .take(5)
        .map(|v| format!("  {v}"))
        .collect();
    let more = f.violations.len().saturating_sub(5);
    let jumps = f
        .violations
        .iter()
        .filter(|v| matches!(v, Violation::Jump { .. }))
        .count();
    format!(
        "NOT FEASIBLE for the servos: {} problem(s) ({jumps} IK jump(s)); `dbot table` refuses it without --allow-infeasible\n{}{}",
        f.violations.len(),
        first.join("\n"),
        if more > 0 {
            format!("\n  ... and {more} more in plan.json")
        } else {
            String::new()
        }
    )
}
