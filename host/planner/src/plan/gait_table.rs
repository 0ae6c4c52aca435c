//! The step table for the board (format of the `protocol` crate): the planned angle and the
//! modelled torque of every servo per slice, with the servo map and the servo stiffness the
//! firmware writes to the servos' P gain and uses for the torque bias (command = angle + torque /
//! stiffness, paper section 2.5).

use protocol::{BuildError, GaitTableBuilder, JointSpec, ServoModel, Sign};

use crate::model::{ActuatorKind, Leg, Model};

/// Why a plan cannot become a step table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    #[error("joint {joint}: actuated but the model gives it no servo (servo map missing)")]
    NoServo { joint: String },
    #[error("joint {joint}: servo model {model:?} is not a Dynamixel MX-28 or MX-64")]
    NotDynamixel { joint: String, model: ActuatorKind },
    #[error("joint {joint}: servo sign {sign} must be +1 or -1")]
    BadSign { joint: String, sign: i8 },
    #[error(
        "joint {joint}: zero offset {zero_offset_rad} rad puts angle 0 at tick {ticks}, outside 0..=4095"
    )]
    ZeroOffset {
        joint: String,
        zero_offset_rad: f64,
        ticks: f64,
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
        let model_code = match ServoModel::try_from(servo.model) {
            Ok(m) => m,
            Err(other) => {
                return Err(TableError::NotDynamixel {
                    joint: name,
                    model: other,
                });
            }
        };
        let sign = match servo.sign {
            1 => Sign::Positive,
            -1 => Sign::Negative,
            s => {
                return Err(TableError::BadSign {
                    joint: name,
                    sign: s,
                });
            }
        };
        // Model: angle = sign (ticks - centre) 2 pi / tpr + zero_offset, so angle 0 sits at
        // ticks = centre - sign zero_offset tpr / 2 pi (centre = half a turn, 2048 on an MX).
        let tpr = f64::from(model_code.ticks_per_rev());
        let ticks =
            tpr / 2.0 - f64::from(servo.sign) * servo.zero_offset * tpr / std::f64::consts::TAU;
        if !(0.0..=4095.0).contains(&ticks.round()) {
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
            zero_offset: ticks.round() as u16,
            min_rad: joint.limits.0,
            max_rad: joint.limits.1,
            stiffness_nm_per_rad: stiffness,
        });
        idx.push(j);
    }
    Ok((idx, specs))
}

/// Stance byte: bit i set when leg i of [`Leg::ALL`] is in stance.
pub fn stance_bits(legs: &[Leg], stance: &[bool]) -> u8 {
    legs.iter()
        .zip(stance)
        .filter(|(_, s)| **s)
        .filter_map(|(l, _)| Leg::ALL.iter().position(|a| a == l))
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
