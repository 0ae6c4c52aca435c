//! The `feasibility` object of plan.json, typed: the planned joints against the servos' limits
//! (peak speed, acceleration, torque and the torque-speed margin, each with its slice), and the
//! violations in words.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::feasibility::Feasibility;

/// Where the limits come from and what is an estimate.
pub const LIMITS_NOTE: &str = "servo limits are Dynamixel e-manual datasheet values at 12 V (no-load speed, stall torque); the torque-speed line T_stall (1 - |w|/w0) is an estimate; no acceleration limit is checked";

/// A plan's feasibility as plan.json records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeasibilitySummary {
    /// [`LIMITS_NOTE`].
    pub limits_note: String,
    pub feasible: bool,
    /// Each violation in words (the same words `dbot plan` prints).
    pub violations: Vec<String>,
    /// Per joint (model name), its peaks and its servo's limits.
    pub joints: BTreeMap<String, JointFeasibility>,
}

/// One joint's peaks over the cycle and its servo's limits (none for a joint without a servo).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointFeasibility {
    pub servo: Option<String>,
    pub no_load_speed_rad_s: Option<f64>,
    pub stall_torque_nm: Option<f64>,
    pub peak_speed_rad_s: f64,
    pub peak_speed_slice: usize,
    pub peak_acceleration_rad_s2: f64,
    pub peak_acceleration_slice: usize,
    pub peak_torque_nm: Option<f64>,
    pub peak_torque_slice: Option<usize>,
    pub torque_speed_margin_nm: Option<f64>,
    pub torque_speed_margin_slice: Option<usize>,
}

impl FeasibilitySummary {
    /// The summary of `f`.
    pub fn new(f: &Feasibility) -> Self {
        let joints = f
            .joints
            .iter()
            .map(|j| {
                let row = JointFeasibility {
                    servo: j.limits.map(|l| l.name.to_string()),
                    no_load_speed_rad_s: j.limits.map(|l| l.no_load_speed),
                    stall_torque_nm: j.limits.map(|l| l.stall_torque),
                    peak_speed_rad_s: j.speed.value,
                    peak_speed_slice: j.speed.slice,
                    peak_acceleration_rad_s2: j.acceleration.value,
                    peak_acceleration_slice: j.acceleration.slice,
                    peak_torque_nm: j.torque.map(|p| p.value),
                    peak_torque_slice: j.torque.map(|p| p.slice),
                    torque_speed_margin_nm: j.torque_speed_margin.map(|p| p.value),
                    torque_speed_margin_slice: j.torque_speed_margin.map(|p| p.slice),
                };
                (j.joint.clone(), row)
            })
            .collect();
        FeasibilitySummary {
            limits_note: LIMITS_NOTE.to_string(),
            feasible: f.is_feasible(),
            violations: f.violations.iter().map(|v| v.to_string()).collect(),
            joints,
        }
    }
}
