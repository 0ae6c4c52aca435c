//! Whether the servos can follow a plan: reported by `dbot plan` (feasibility.md, plan.json,
//! terminal; its plan.json object is `planner::plan::feasibility_summary`); the override flag of the rule that `dbot table`, `dbot upload --plan` and `dbot run
//! --period` enforce through the library (`board::rules`), and the printing of its warning.

use board::rules::{Overridden, Overrides};
use planner::plan::feasibility::{Feasibility, Violation};

/// The override of the servo-feasibility check.
#[derive(Debug, Clone, clap::Args)]
pub struct FeasibilityArgs {
    /// Build, upload or play the table even when a servo cannot follow it (speed over the no-load
    /// speed, torque over stall or over the torque-speed line, an inverse-kinematics jump; for
    /// `run --period`, at the period asked for, and so for every gait queued with --then).
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
