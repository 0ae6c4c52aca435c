//! The step table for the board (format of the `protocol` crate): the planned angle and the
//! modelled torque of every servo per slice, with the servo map and the servo stiffness the
//! firmware writes to the servos' P gain and uses for the torque bias (command = angle + torque /
//! stiffness, paper section 2.5).

use protocol::{BuildError, GaitTableBuilder, JointSpec, Sign};

use crate::model::{Leg, Model};

/// Why a plan cannot become a step table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    #[error("joint {joint}: actuated but the model gives it no servo (servo map missing)")]
    NoServo { joint: String },
    #[error("joint {joint}: servo sign {sign} must be +1 or -1")]
    BadSign { joint: String, sign: i8 },
    #[error(
        "joint {joint}: zero offset {zero_offset_rad} rad puts angle 0 at tick {ticks}, outside the servo's 0..=4095"
    )]
    ZeroOffset {
        joint: String,
        zero_offset_rad: f64,
        ticks: i64,
    },
    #[error("joint {joint}: no servo stiffness (fixed joint with a servo map?)")]
    NoStiffness { joint: String },
    #[error("slice {slice}: {what} has {got} entries, expected {expected}")]
    Shape {
        slice: usize,
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error(transparent)]
    Build(#[from] BuildError),
}

/// Model joints that drive a servo, in table order (model order), and their table records.
pub fn joint_specs(model: &Model) -> Result<(Vec<usize>, Vec<JointSpec>), TableError> {
    let mut idx = Vec::new();
    let mut specs = Vec::new();
    for (j, joint) in model.joints.iter().enumerate() {
        let crate::model::Actuation::Actuated { stiffness, .. } = joint.actuation else {
            continue;
        };
        let name = joint.name.clone();
        let servo = joint.servo.ok_or_else(|| TableError::NoServo {
            joint: name.clone(),
        })?;
        let model_code = servo.model;
        if servo.sign != 1 && servo.sign != -1 {
            return Err(TableError::BadSign {
                joint: name,
                sign: servo.sign,
            });
        }
        let sign = if servo.sign > 0 {
            Sign::Positive
        } else {
            Sign::Negative
        };
        // Angle 0 sits at centre - sign zero_offset tpr / 2 pi: the one converter's answer
        // (protocol::Calibration through the model's servo map), as the board will read it.
        let ticks = servo.zero_ticks();
        if !(0..=i64::from(model_code.ticks_per_rev()) - 1).contains(&ticks) {
            return Err(TableError::ZeroOffset {
                joint: name,
                zero_offset_rad: servo.zero_offset,
                ticks,
            });
        }
        if stiffness.is_nan() || stiffness <= 0.0 {
            return Err(TableError::NoStiffness { joint: name });
        }
        specs.push(JointSpec {
            name,
            servo_id: servo.id,
            model: model_code,
            sign,
            zero_offset: ticks as u16,
            min_rad: joint.limits.0,
            max_rad: joint.limits.1,
            stiffness_nm_per_rad: stiffness,
            leg: leg_index(joint.leg).map(|i| i as u8),
        });
        idx.push(j);
    }
    Ok((idx, specs))
}

/// A leg's index in [`Leg::ALL`]: its stance bit and the table's leg number.
fn leg_index(leg: Leg) -> Option<usize> {
    Leg::ALL.iter().position(|a| *a == leg)
}

/// Stance byte: bit i set when leg i of [`Leg::ALL`] is in stance.
pub fn stance_bits(legs: &[Leg], stance: &[bool]) -> u8 {
    legs.iter()
        .zip(stance)
        .filter(|(_, s)| **s)
        .filter_map(|(l, _)| leg_index(*l))
        .fold(0u8, |b, i| b | (1 << i))
}

/// Build the table bytes. `q` and `torque` are per slice and model joint (N m: the actuator
/// torque), `stance` per slice as [`stance_bits`].
pub fn gait_table(
    model: &Model,
    name: &str,
    period_s: f64,
    duty: f64,
    q: &[Vec<f64>],
    torque: &[Vec<f64>],
    stance: &[u8],
) -> Result<Vec<u8>, TableError> {
    let (idx, specs) = joint_specs(model)?;
    let mut b = GaitTableBuilder::new(name, period_s, duty, specs);
    let n = model.joints.len();
    for (s, ((qs, ts), st)) in q.iter().zip(torque).zip(stance).enumerate() {
        for (what, v) in [("angles", qs), ("torques", ts)] {
            if v.len() != n {
                return Err(TableError::Shape {
                    slice: s,
                    what,
                    got: v.len(),
                    expected: n,
                });
            }
        }
        let a: Vec<f64> = idx.iter().map(|&j| qs[j]).collect();
        let t: Vec<f64> = idx.iter().map(|&j| ts[j]).collect();
        b.slice(*st, &a, &t);
    }
    if q.len() != torque.len() || q.len() != stance.len() {
        return Err(TableError::Shape {
            slice: q.len().min(torque.len()),
            what: "slices",
            got: torque.len(),
            expected: q.len(),
        });
    }
    Ok(b.build()?)
}
