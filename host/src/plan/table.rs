//! A [`Plan`] as a step table for the board (`protocol::GaitTable`): the joints that have a servo,
//! in model order, with their servo map, limits and stiffness, one table slice per plan slice.

use protocol::gait::{GaitTableBuilder, JointSpec, ServoModel, Sign};

use super::Plan;
use crate::model::{Actuation, ActuatorKind, Leg, Model};

/// Why a plan cannot become a step table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    #[error("joint {joint}: servo model {kind:?} has no Dynamixel table (MX-28 or MX-64 only)")]
    NoServoModel { joint: String, kind: ActuatorKind },
    #[error("the model has no joint with a servo map; nothing to put in a step table")]
    NoServos,
    #[error("torques have {got} slices, the plan {slices}")]
    TorqueSlices { got: usize, slices: usize },
    #[error("slice {slice}: torques have {got} joints, the model {joints}")]
    TorqueJoints {
        slice: usize,
        got: usize,
        joints: usize,
    },
    #[error(transparent)]
    Build(#[from] protocol::BuildError),
}

/// Indices (model order) of the joints that have a servo: the table's joint map.
pub fn servo_joints(model: &Model) -> Vec<usize> {
    (0..model.joints.len())
        .filter(|&j| model.joints[j].servo.is_some())
        .collect()
}

/// The table's joint specs, in [`servo_joints`] order.
pub fn joint_specs(model: &Model) -> Result<Vec<JointSpec>, TableError> {
    let mut specs = Vec::new();
    for j in servo_joints(model) {
        let joint = &model.joints[j];
        let Some(servo) = joint.servo else { continue };
        let model_kind = match servo.model {
            ActuatorKind::Mx28 => ServoModel::Mx28,
            ActuatorKind::Mx64 => ServoModel::Mx64,
            kind => {
                return Err(TableError::NoServoModel {
                    joint: joint.name.clone(),
                    kind,
                });
            }
        };
        // angle = sign (ticks - 2048) 2 pi / 4096 + zero_offset, so angle 0 sits at
        // ticks = 2048 - sign zero_offset 4096 / 2 pi.
        let sign = if servo.sign < 0 { -1.0 } else { 1.0 };
        let ticks = 2048.0 - sign * servo.zero_offset * 4096.0 / std::f64::consts::TAU;
        let stiffness = match joint.actuation {
            Actuation::Actuated { stiffness, .. } => stiffness,
            Actuation::Fixed { .. } => 0.0,
        };
        specs.push(JointSpec {
            name: joint.name.clone(),
            servo_id: servo.id,
            model: model_kind,
            sign: if servo.sign < 0 {
                Sign::Negative
            } else {
                Sign::Positive
            },
            zero_offset: ticks.round().clamp(0.0, 4095.0) as u16,
            min_rad: joint.limits.0,
            max_rad: joint.limits.1,
            stiffness_nm_per_rad: stiffness,
        });
    }
    if specs.is_empty() {
        return Err(TableError::NoServos);
    }
    Ok(specs)
}

/// Stance bits of one slice: bit i set when leg [`Leg::ALL`]`[i]` is in stance.
pub fn stance_bits(legs: &[Leg], stance: &[bool]) -> u8 {
    legs.iter().zip(stance).fold(0u8, |bits, (leg, &st)| {
        let i = Leg::ALL.iter().position(|l| l == leg).unwrap_or(0);
        if st { bits | (1 << i) } else { bits }
    })
}

/// The step table of `plan`, named `name` (at most 16 bytes), with the planned torques
/// (`torques[slice][model joint]`, N m) as the bias feed-forward, or zero torques.
pub fn step_table(
    plan: &Plan,
    torques: Option<&[Vec<f64>]>,
    name: &str,
) -> Result<Vec<u8>, TableError> {
    let model = &plan.model;
    let specs = joint_specs(model)?;
    let joints = servo_joints(model);
    if let Some(t) = torques
        && t.len() != plan.slices()
    {
        return Err(TableError::TorqueSlices {
            got: t.len(),
            slices: plan.slices(),
        });
    }
    let mut b = GaitTableBuilder::new(name, plan.period_s, plan.params.duty, specs);
    for s in 0..plan.slices() {
        let angles: Vec<f64> = joints.iter().map(|&j| plan.q[s][j]).collect();
        let tau: Vec<f64> = match torques {
            Some(t) => {
                if t[s].len() != model.joints.len() {
                    return Err(TableError::TorqueJoints {
                        slice: s,
                        got: t[s].len(),
                        joints: model.joints.len(),
                    });
                }
                joints.iter().map(|&j| t[s][j]).collect()
            }
            None => vec![0.0; joints.len()],
        };
        b.slice(stance_bits(&plan.legs, &plan.stance[s]), &angles, &tau);
    }
    Ok(b.build()?)
}
