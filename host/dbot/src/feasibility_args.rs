//! Whether the servos can follow a plan: reported by `dbot plan` (feasibility.csv, plan.json,
//! terminal), and enforced by `dbot table` and `dbot upload --plan` unless --allow-infeasible.

use anyhow::{Result, bail};
use planner::plan::feasibility::{Feasibility, Violation};

/// The override of the servo-feasibility check.
#[derive(Debug, Clone, clap::Args)]
pub struct FeasibilityArgs {
    /// Build the table even when a servo cannot follow the plan (speed over the no-load speed,
    /// torque over stall or over the torque-speed line, an inverse-kinematics jump).
    #[arg(long)]
    pub allow_infeasible: bool,
}

impl FeasibilityArgs {
    /// Checks a plan directory's planned angles and torques against the servos before a step
    /// table is built from it (`table --plan`, `upload --plan`).
    pub fn enforce_plan_dir(&self, plan: &planner::plan_dir::PlanDir) -> Result<()> {
        let check = planner::plan::feasibility::check(
            &plan.model,
            &plan.angle,
            plan.torque.as_deref(),
            plan.json.dt_s,
        );
        self.enforce(&check, &format!("plan {}", plan.path.display()))
    }

    /// Refuses an infeasible plan (naming every joint, slice and margin) unless overridden; with
    /// the override, warns on stderr.
    pub fn enforce(&self, f: &Feasibility, what: &str) -> Result<()> {
        if f.is_feasible() {
            return Ok(());
        }
        let list = f
            .violations
            .iter()
            .map(|v| format!("  {v}"))
            .collect::<Vec<_>>()
            .join("\n");
        if self.allow_infeasible {
            eprintln!(
                "warning: {what}: the servos cannot follow this plan (--allow-infeasible):\n{list}"
            );
            Ok(())
        } else {
            bail!(
                "{what}: the servos cannot follow this plan:\n{list}\nplan a slower step (--swing), or pass --allow-infeasible to build it anyway"
            )
        }
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
