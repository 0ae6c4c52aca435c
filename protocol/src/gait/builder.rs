//! [`GaitTableBuilder`]: the host turns planned f64 SI data into table bytes, refusing every value
//! that does not fit its fixed-point field (never a silent wrap) with an error naming the joint,
//! slice and field.

use super::{
    FORMAT_VERSION, GaitHeader, HEADER_LEN, LEGS, MAGIC, MAX_SLICES, NAME_LEN, STANCE_MASK,
    ServoModel, Sign, table_len,
};
use crate::units::{ANGLE_PER_RAD, DUTY_PER_UNIT, STIFFNESS_PER_NM_RAD, TORQUE_PER_NM, to_fixed};
use crate::{MAX_JOINTS, crc32};

/// A field of the table, as named in [`BuildError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    Angle,
    Torque,
    MinAngle,
    MaxAngle,
    Stiffness,
    ZeroOffset,
    ServoId,
    Leg,
    StepPeriod,
    Duty,
}

impl core::fmt::Display for Field {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let s = match self {
            Self::Angle => "angle (rad)",
            Self::Torque => "torque (N m)",
            Self::MinAngle => "lower limit (rad)",
            Self::MaxAngle => "upper limit (rad)",
            Self::Stiffness => "stiffness (N m/rad)",
            Self::ZeroOffset => "zero offset (ticks)",
            Self::ServoId => "servo ID",
            Self::Leg => "leg (0 ..= 5 in LF, LM, LH, RF, RM, RH)",
            Self::StepPeriod => "step period (s)",
            Self::Duty => "duty factor",
        };
        f.write_str(s)
    }
}

/// Why a table cannot be built. `joint` is the joint's name from its [`JointSpec`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BuildError {
    #[error("{field} = {value} does not fit the table: allowed {min} ..= {max}")]
    Header {
        field: Field,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("gait name of {len} bytes, at most {max}")]
    NameTooLong { len: usize, max: usize },
    /// A control character (or NUL) in the name: names are shown to users as text.
    #[error("gait name holds a control character (byte {index} of the name): give printable text")]
    NameNotPrintable { index: usize },
    #[error("{count} joints, the table takes 1 ..= {max}")]
    JointCount { count: usize, max: usize },
    #[error("{count} slices, the table takes 1 ..= {max}")]
    SliceCount { count: usize, max: usize },
    #[error("joint {joint}: {field} = {value} outside {min} ..= {max}")]
    Joint {
        joint: String,
        field: Field,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("joint {joint}: servo ID {servo_id} already used by joint {other}")]
    DuplicateServo {
        joint: String,
        other: String,
        servo_id: u8,
    },
    #[error("slice {slice}: {got} {what} values for {joints} joints")]
    SampleCount {
        slice: usize,
        what: &'static str,
        got: usize,
        joints: usize,
    },
    #[error("slice {slice}, joint {joint}: {field} = {value} outside {min} ..= {max}")]
    Sample {
        slice: usize,
        joint: String,
        field: Field,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("slice {slice}: stance flags {bits:#04x} name legs beyond the six")]
    Stance { slice: usize, bits: u8 },
}

/// One joint of a table in SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// Full name, e.g. `LF_ThC1` (used in errors only).
    pub name: String,
    pub servo_id: u8,
    pub model: ServoModel,
    pub sign: Sign,
    /// Servo ticks at joint angle 0.
    pub zero_offset: u16,
    /// Joint limits, rad.
    pub min_rad: f64,
    pub max_rad: f64,
    /// Servo stiffness used for the torque bias, N m/rad.
    pub stiffness_nm_per_rad: f64,
    /// The leg the joint moves (0 ..= 5 in LF, LM, LH, RF, RM, RH), if any: the board's start
    /// ramp lifts a leg's joints together.
    pub leg: Option<u8>,
}

/// Collects a gait in SI units and writes the table bytes.
#[derive(Debug, Clone)]
pub struct GaitTableBuilder {
    name: String,
    step_period_s: f64,
    duty: f64,
    joints: Vec<JointSpec>,
    slices: Vec<(u8, Vec<f64>, Vec<f64>)>,
}

const I16: (f64, f64) = (i16::MIN as f64, i16::MAX as f64);

impl GaitTableBuilder {
    /// A table named `name` (at most 16 UTF-8 bytes) of the given step period (s) and duty (0..1).
    pub fn new(name: &str, step_period_s: f64, duty: f64, joints: Vec<JointSpec>) -> Self {
        Self {
            name: name.to_owned(),
            step_period_s,
            duty,
            joints,
            slices: Vec::new(),
        }
    }

    /// Appends a slice: stance flags (bit i = leg i in LF, LM, LH, RF, RM, RH), then per joint the
    /// planned angle (rad) and torque (N m).
    pub fn slice(&mut self, stance: u8, angles_rad: &[f64], torques_nm: &[f64]) -> &mut Self {
        self.slices
            .push((stance, angles_rad.to_vec(), torques_nm.to_vec()));
        self
    }

    /// The header the table will carry (after the checks of [`Self::build`]).
    pub fn header(&self) -> Result<GaitHeader, BuildError> {
        let mut name = [0u8; NAME_LEN];
        let raw = self.name.as_bytes();
        if raw.len() > NAME_LEN {
            return Err(BuildError::NameTooLong {
                len: raw.len(),
                max: NAME_LEN,
            });
        }
        if let Some((index, _)) = self.name.char_indices().find(|(_, c)| c.is_control()) {
            return Err(BuildError::NameNotPrintable { index });
        }
        name[..raw.len()].copy_from_slice(raw);
        let period = to_fixed(self.step_period_s, 1e6, 1, i64::from(u32::MAX)).ok_or(
            BuildError::Header {
                field: Field::StepPeriod,
                value: self.step_period_s,
                min: 1e-6,
                max: f64::from(u32::MAX) / 1e6,
            },
        )?;
        let duty = to_fixed(self.duty, DUTY_PER_UNIT, 1, 9_999).ok_or(BuildError::Header {
            field: Field::Duty,
            value: self.duty,
            min: 1e-4,
            max: 0.9999,
        })?;
        if self.joints.is_empty() || self.joints.len() > MAX_JOINTS {
            return Err(BuildError::JointCount {
                count: self.joints.len(),
                max: MAX_JOINTS,
            });
        }
        if self.slices.is_empty() || self.slices.len() > usize::from(MAX_SLICES) {
            return Err(BuildError::SliceCount {
                count: self.slices.len(),
                max: MAX_SLICES.into(),
            });
        }
        Ok(GaitHeader {
            joint_count: self.joints.len() as u8,
            slice_count: self.slices.len() as u16,
            step_period_us: period as u32,
            duty: duty as u16,
            name,
        })
    }

    /// Checks everything and writes the table.
    pub fn build(&self) -> Result<Vec<u8>, BuildError> {
        let header = self.header()?;
        let len = table_len(self.joints.len(), self.slices.len());
        let mut out = Vec::with_capacity(len);
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.push(header.joint_count);
        out.push(0);
        out.extend_from_slice(&header.slice_count.to_le_bytes());
        out.extend_from_slice(&header.duty.to_le_bytes());
        out.extend_from_slice(&header.step_period_us.to_le_bytes());
        out.extend_from_slice(&(len as u32).to_le_bytes());
        out.extend_from_slice(&header.name);
        debug_assert_eq!(out.len(), HEADER_LEN);

        let mut limits = Vec::with_capacity(self.joints.len());
        for (j, spec) in self.joints.iter().enumerate() {
            if let Some(other) = self.joints[..j]
                .iter()
                .find(|o| o.servo_id == spec.servo_id)
            {
                return Err(BuildError::DuplicateServo {
                    joint: spec.name.clone(),
                    other: other.name.clone(),
                    servo_id: spec.servo_id,
                });
            }
            let (min, max) = write_joint(&mut out, spec)?;
            limits.push((min, max));
        }

        for (s, (stance, angles, torques)) in self.slices.iter().enumerate() {
            if stance & !STANCE_MASK != 0 {
                return Err(BuildError::Stance {
                    slice: s,
                    bits: *stance,
                });
            }
            for (what, got) in [("angle", angles.len()), ("torque", torques.len())] {
                if got != self.joints.len() {
                    return Err(BuildError::SampleCount {
                        slice: s,
                        what,
                        got,
                        joints: self.joints.len(),
                    });
                }
            }
            out.push(*stance);
            out.push(0);
            for (j, spec) in self.joints.iter().enumerate() {
                let sample_err = |field, value, min: f64, max: f64| BuildError::Sample {
                    slice: s,
                    joint: spec.name.clone(),
                    field,
                    value,
                    min,
                    max,
                };
                let (min, max) = limits[j];
                let angle = to_fixed(angles[j], ANGLE_PER_RAD, i64::from(min), i64::from(max))
                    .ok_or_else(|| {
                        sample_err(Field::Angle, angles[j], spec.min_rad, spec.max_rad)
                    })?;
                let torque = to_fixed(torques[j], TORQUE_PER_NM, I16.0 as i64, I16.1 as i64)
                    .ok_or_else(|| {
                        sample_err(
                            Field::Torque,
                            torques[j],
                            I16.0 / TORQUE_PER_NM,
                            I16.1 / TORQUE_PER_NM,
                        )
                    })?;
                out.extend_from_slice(&(angle as i16).to_le_bytes());
                out.extend_from_slice(&(torque as i16).to_le_bytes());
            }
        }
        let crc = crc32::checksum(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        debug_assert_eq!(out.len(), len);
        Ok(out)
    }
}

/// Writes one joint record; returns its limits in angle units.
fn write_joint(out: &mut Vec<u8>, spec: &JointSpec) -> Result<(i16, i16), BuildError> {
    let err = |field, value: f64, min: f64, max: f64| BuildError::Joint {
        joint: spec.name.clone(),
        field,
        value,
        min,
        max,
    };
    if spec.servo_id > 252 {
        return Err(err(Field::ServoId, spec.servo_id.into(), 0.0, 252.0));
    }
    if let Some(leg) = spec.leg.filter(|&l| usize::from(l) >= LEGS) {
        return Err(err(Field::Leg, leg.into(), 0.0, (LEGS - 1) as f64));
    }
    if spec.zero_offset > 4095 {
        return Err(err(Field::ZeroOffset, spec.zero_offset.into(), 0.0, 4095.0));
    }
    let (lo, hi) = (I16.0 / ANGLE_PER_RAD, I16.1 / ANGLE_PER_RAD);
    let min = to_fixed(spec.min_rad, ANGLE_PER_RAD, I16.0 as i64, I16.1 as i64)
        .ok_or_else(|| err(Field::MinAngle, spec.min_rad, lo, hi))?;
    let max = to_fixed(spec.max_rad, ANGLE_PER_RAD, min, I16.1 as i64)
        .ok_or_else(|| err(Field::MaxAngle, spec.max_rad, spec.min_rad, hi))?;
    // What the servo's P gain register holds (`limits::p_gain_stiffness_units`), as the parse
    // and the board check it.
    let held = crate::limits::p_gain_stiffness_units(spec.model);
    let stiffness = to_fixed(
        spec.stiffness_nm_per_rad,
        STIFFNESS_PER_NM_RAD,
        i64::from(*held.start()),
        i64::from(*held.end()),
    )
    .ok_or_else(|| {
        err(
            Field::Stiffness,
            spec.stiffness_nm_per_rad,
            f64::from(*held.start()) / STIFFNESS_PER_NM_RAD,
            f64::from(*held.end()) / STIFFNESS_PER_NM_RAD,
        )
    })?;
    out.push(spec.servo_id);
    out.push(spec.model.table_code());
    out.push(spec.sign.as_i32() as i8 as u8);
    out.push(spec.leg.map_or(0, |l| l + 1));
    out.extend_from_slice(&spec.zero_offset.to_le_bytes());
    out.extend_from_slice(&(min as i16).to_le_bytes());
    out.extend_from_slice(&(max as i16).to_le_bytes());
    out.extend_from_slice(&[0, 0]);
    out.extend_from_slice(&(stiffness as u32).to_le_bytes());
    Ok((min as i16, max as i16))
}
