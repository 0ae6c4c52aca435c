//! plan.json as a typed, versioned struct: what the plan was (model, parameters, terrain, timing),
//! the name its step table gets, and the inverse dynamics' summary when it was solved.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::dynamics::DynamicsSummary;
use crate::gait::StepParams;
use crate::model::Leg;
use crate::plan::Plan;
use crate::plan::feasibility_summary::FeasibilitySummary;
use crate::terrain::Terrain;

/// The plan directory format this build writes and reads. Raise it when a file or a column changes
/// meaning; a reader refuses any other version naming the file.
pub const FORMAT_VERSION: u32 = 1;

/// The frames and units every file of the directory uses.
pub const FRAMES: &str = "thorax frame, REP-103: x forward, y left, z up; SI units";

/// The contents of plan.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanJson {
    /// [`FORMAT_VERSION`] of the writer.
    pub format_version: u32,
    /// The model's name.
    pub model: String,
    /// Where the model came from, as given to the planner (a built-in name or a file path);
    /// informational: readers load the directory's own model.toml.
    pub model_source: String,
    /// The gait name a step table built from this directory gets (at most 16 bytes); without it,
    /// the directory's own name ([`super::PlanDir::table_name`]), so the file does not depend on
    /// where it was written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table_name: Option<String>,
    pub parameters: StepParams,
    pub terrain: Terrain,
    pub gravity_m_s2: Vector3<f64>,
    pub ball_centre_m: Option<Vector3<f64>>,
    pub period_s: f64,
    pub dt_s: f64,
    pub slices: usize,
    /// Legs in the order of `leg_phases` and of the planner's per-leg data.
    pub legs: Vec<Leg>,
    /// Start of each leg's cycle, fraction of the period.
    pub leg_phases: Vec<f64>,
    pub thorax_velocity_m_s: Vector3<f64>,
    pub thorax_angular_velocity_rad_s: Vector3<f64>,
    pub resting_posture_rad: BTreeMap<String, f64>,
    /// [`FRAMES`].
    pub frames: String,
    /// The inverse dynamics' options and summary (peaks, slips, saturations); absent when the plan
    /// was made without dynamics (joints.csv then has no torque column).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamics: Option<DynamicsSummary>,
    /// The planned joints against the servos' limits (peak speed, acceleration, torque; the
    /// violations), written with the plan (feasibility.md has the same as a table).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feasibility: Option<FeasibilitySummary>,
    /// The `--spring` options the model was planned with (model.toml holds the springs themselves).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_args: Option<SpringOptions>,
}

/// The parallel-spring options a model was planned with, as `dbot plan --spring SPEC
/// --spring-equilibrium FROM` gives them.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SpringOptions {
    /// `none`, `paper`, a preset name or a stiffness in N m/rad.
    pub spring: String,
    /// `rest`, `step-midrange` or `dead-fly`.
    pub spring_equilibrium: String,
}

impl PlanJson {
    /// The summary of `plan`, planned from the model `model_source`, whose step table is named
    /// `table_name` (cut to 16 bytes on a character boundary) or else after its directory.
    pub fn new(
        plan: &Plan,
        model_source: &str,
        table_name: Option<&str>,
        dynamics: Option<DynamicsSummary>,
    ) -> Self {
        PlanJson {
            format_version: FORMAT_VERSION,
            model: plan.model.name.clone(),
            model_source: model_source.to_string(),
            table_name: table_name.map(table_name_of),
            parameters: plan.params.clone(),
            terrain: plan.terrain,
            gravity_m_s2: plan.gravity,
            ball_centre_m: plan.ball_centre,
            period_s: plan.period_s,
            dt_s: plan.dt,
            slices: plan.slices(),
            legs: plan.legs.clone(),
            leg_phases: plan.phases.clone(),
            thorax_velocity_m_s: plan.thorax_velocity,
            thorax_angular_velocity_rad_s: plan.thorax_angular_velocity,
            resting_posture_rad: plan
                .model
                .joints
                .iter()
                .zip(&plan.posture.q)
                .map(|(j, q)| (j.name.clone(), *q))
                .collect(),
            frames: FRAMES.to_string(),
            dynamics,
            feasibility: None,
            spring_args: None,
        }
    }

    /// The file's text (pretty JSON).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a PlanJson always serialises")
    }
}

/// `name` cut to the step table's 16 bytes on a character boundary.
pub fn table_name_of(name: &str) -> String {
    let mut end = name.len().min(protocol::gait::NAME_LEN);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    name[..end].to_string()
}
