//! A [`Plan`] as a step table for the board (`protocol::GaitTable`): the plan's angles, stance and
//! (optionally) its solved torques fed to [`super::gait_table::gait_table`], the one place where
//! the servo map becomes the table's joint records.

use super::Plan;
use super::gait_table::{gait_table, joint_specs};
use crate::model::Model;

pub use super::gait_table::{TableError, stance_bits};

/// Indices (model order) of the joints that drive a servo: the table's joints, in table order.
pub fn servo_joints(model: &Model) -> Vec<usize> {
    joint_specs(model).map(|(idx, _)| idx).unwrap_or_default()
}

/// The step table of `plan`, named `name` (at most 16 bytes), with the planned torques
/// (`torques[slice][model joint]`, N m) as the bias feed-forward, or zero torques.
pub fn step_table(
    plan: &Plan,
    torques: Option<&[Vec<f64>]>,
    name: &str,
) -> Result<Vec<u8>, TableError> {
    let zeros;
    let torque = match torques {
        Some(t) => t,
        None => {
            zeros = vec![vec![0.0; plan.model.joints.len()]; plan.slices()];
            &zeros[..]
        }
    };
    let stance: Vec<u8> = plan
        .stance
        .iter()
        .map(|s| stance_bits(&plan.legs, s))
        .collect();
    gait_table(
        &plan.model,
        name,
        plan.period_s,
        plan.params.duty,
        &plan.q,
        torque,
        &stance,
    )
}
