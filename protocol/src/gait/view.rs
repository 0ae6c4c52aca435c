//! [`GaitTable`]: a validated, zero-copy view of a table's bytes (e.g. in XIP flash).

use super::{
    CRC_LEN, FORMAT_VERSION, GaitHeader, HEADER_LEN, JOINT_RECORD_LEN, JointField, JointMap, MAGIC,
    MAX_SLICES, NAME_LEN, SAMPLE_LEN, SLICE_PREFIX_LEN, STANCE_MASK, ServoModel, Sign, TableError,
    le_i16, le_u16, le_u32, slice_len, table_len,
};
use crate::{MAX_JOINTS, crc32};

/// A gait table checked once by [`GaitTable::parse`]; its accessors then read the bytes in place.
///
/// Accessors return `None` for an index out of range instead of panicking.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GaitTable<'a> {
    bytes: &'a [u8],
    joints: usize,
    slices: usize,
}

#[cfg(feature = "defmt")]
impl defmt::Format for GaitTable<'_> {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "GaitTable {{ {} joints, {} slices, {} bytes, crc {=u32:#010x} }}",
            self.joints,
            self.slices,
            self.bytes.len(),
            self.crc()
        )
    }
}

/// Planned angle (1e-4 rad) and torque (mN m) of one joint in one slice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sample {
    pub angle: i16,
    pub torque: i16,
}

/// One slice of a [`GaitTable`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SliceView<'a> {
    bytes: &'a [u8],
}

impl<'a> SliceView<'a> {
    /// Stance flags: bit i set when leg i (LF, LM, LH, RF, RM, RH) is in stance.
    pub fn stance(&self) -> u8 {
        self.bytes[0]
    }

    /// Angle and torque of `joint`.
    pub fn sample(&self, joint: usize) -> Option<Sample> {
        let at = SLICE_PREFIX_LEN + joint.checked_mul(SAMPLE_LEN)?;
        let rec = self.bytes.get(at..at + SAMPLE_LEN)?;
        Some(Sample {
            angle: le_i16(rec, 0),
            torque: le_i16(rec, 2),
        })
    }
}

impl<'a> GaitTable<'a> {
    /// Validates `bytes` (magic, version, counts, length, CRC, every joint record, every slice's
    /// stance byte and every angle against its joint's limits).
    ///
    /// `bytes` may be longer than the table (a whole flash slot); the view covers the declared length.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, TableError> {
        let len = u32::try_from(bytes.len()).unwrap_or(u32::MAX);
        let min_len = (HEADER_LEN + CRC_LEN) as u32;
        if len < min_len {
            return Err(TableError::Truncated {
                len,
                needed: min_len,
            });
        }
        let found = [bytes[0], bytes[1], bytes[2], bytes[3]];
        if found != MAGIC {
            return Err(TableError::BadMagic { found });
        }
        let version = le_u16(bytes, 4);
        if version != FORMAT_VERSION {
            return Err(TableError::UnsupportedVersion {
                found: version,
                supported: FORMAT_VERSION,
            });
        }
        let header = header_of(bytes);
        let joints = usize::from(header.joint_count);
        if joints == 0 || joints > MAX_JOINTS {
            return Err(TableError::BadJointCount {
                count: header.joint_count,
            });
        }
        if bytes[7] != 0 {
            return Err(TableError::Reserved { offset: 7 });
        }
        if header.slice_count == 0 || header.slice_count > MAX_SLICES {
            return Err(TableError::BadSliceCount {
                count: header.slice_count,
            });
        }
        if header.duty == 0 || header.duty >= 10_000 {
            return Err(TableError::BadDuty { duty: header.duty });
        }
        if header.step_period_us == 0 {
            return Err(TableError::BadPeriod);
        }
        let slices = usize::from(header.slice_count);
        let computed = table_len(joints, slices) as u32;
        let declared = le_u32(bytes, 16);
        if declared != computed {
            return Err(TableError::LengthMismatch { declared, computed });
        }
        if len < computed {
            return Err(TableError::Truncated {
                len,
                needed: computed,
            });
        }
        let bytes = &bytes[..computed as usize];
        let body = &bytes[..bytes.len() - CRC_LEN];
        let stored = le_u32(bytes, body.len());
        let crc = crc32::checksum(body);
        if stored != crc {
            return Err(TableError::Crc {
                stored,
                computed: crc,
            });
        }
        let table = Self {
            bytes,
            joints,
            slices,
        };
        for j in 0..joints {
            check_joint(
                &bytes[HEADER_LEN + j * JOINT_RECORD_LEN..][..JOINT_RECORD_LEN],
                j as u8,
            )?;
            let id = bytes[HEADER_LEN + j * JOINT_RECORD_LEN];
            if (0..j).any(|k| bytes[HEADER_LEN + k * JOINT_RECORD_LEN] == id) {
                // Two joints driving one servo would fight over its goal.
                return Err(TableError::BadJoint {
                    joint: j as u8,
                    field: JointField::ServoId,
                });
            }
        }
        table.check_slices()?;
        Ok(table)
    }

    fn check_slices(&self) -> Result<(), TableError> {
        for s in 0..self.slices {
            let start = self.slices_start() + s * slice_len(self.joints);
            let (stance, reserved) = (self.bytes[start], self.bytes[start + 1]);
            if stance & !STANCE_MASK != 0 || reserved != 0 {
                let bits = if reserved != 0 { reserved } else { stance };
                return Err(TableError::BadStance {
                    slice: s as u16,
                    bits,
                });
            }
            for j in 0..self.joints {
                let Some(map) = self.joint_record(j) else {
                    // Not reached: `parse` checked every joint record first (`check_joint`).
                    return Err(TableError::BadJoint {
                        joint: j as u8,
                        field: JointField::Model,
                    });
                };
                let angle = le_i16(self.bytes, start + SLICE_PREFIX_LEN + j * SAMPLE_LEN);
                if angle < map.min || angle > map.max {
                    return Err(TableError::AngleOutOfLimits {
                        slice: s as u16,
                        joint: j as u8,
                        angle,
                    });
                }
            }
        }
        Ok(())
    }

    fn slices_start(&self) -> usize {
        HEADER_LEN + self.joints * JOINT_RECORD_LEN
    }

    /// Joint `j`'s record (`j` below the joint count). `None` only for a servo model code that
    /// [`ServoModel::from_table_code`] does not know, which `parse` refuses before any table
    /// exists (`TableError::BadJoint`, field `servo model`; protocol/tests/integration/gait_table.rs): no
    /// table stands in another servo's limits for an unknown one.
    fn joint_record(&self, j: usize) -> Option<JointMap> {
        let r = &self.bytes[HEADER_LEN + j * JOINT_RECORD_LEN..][..JOINT_RECORD_LEN];
        Some(JointMap {
            servo_id: r[0],
            model: ServoModel::from_table_code(r[1])?,
            sign: if r[2] as i8 == -1 {
                Sign::Negative
            } else {
                Sign::Positive
            },
            zero_offset: le_u16(r, 4),
            min: le_i16(r, 6),
            max: le_i16(r, 8),
            stiffness: le_u32(r, 12),
            leg: r[3].checked_sub(1),
        })
    }

    /// The header.
    pub fn header(&self) -> GaitHeader {
        header_of(self.bytes)
    }

    /// The table's bytes, CRC included (exactly the declared length).
    pub fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// The stored CRC-32.
    pub fn crc(&self) -> u32 {
        le_u32(self.bytes, self.bytes.len() - CRC_LEN)
    }

    /// Joints per slice.
    pub fn joint_count(&self) -> usize {
        self.joints
    }

    /// Slices per step.
    pub fn slice_count(&self) -> usize {
        self.slices
    }

    /// The map of `joint` (`None` past the last joint).
    pub fn joint(&self, joint: usize) -> Option<JointMap> {
        (joint < self.joints)
            .then(|| self.joint_record(joint))
            .flatten()
    }

    /// One slice.
    pub fn slice(&self, slice: usize) -> Option<SliceView<'a>> {
        if slice >= self.slices {
            return None;
        }
        let len = slice_len(self.joints);
        let start = self.slices_start() + slice * len;
        Some(SliceView {
            bytes: &self.bytes[start..start + len],
        })
    }

    /// Planned angle of `joint` in `slice`, 1e-4 rad.
    pub fn angle(&self, slice: usize, joint: usize) -> Option<i16> {
        self.slice(slice)?.sample(joint).map(|s| s.angle)
    }

    /// Planned torque of `joint` in `slice`, mN m.
    pub fn torque(&self, slice: usize, joint: usize) -> Option<i16> {
        self.slice(slice)?.sample(joint).map(|s| s.torque)
    }

    /// Stance flags of `slice` (bit i = leg i in LF, LM, LH, RF, RM, RH).
    pub fn stance(&self, slice: usize) -> Option<u8> {
        self.slice(slice).map(|s| s.stance())
    }
}

fn header_of(bytes: &[u8]) -> GaitHeader {
    let mut name = [0u8; NAME_LEN];
    name.copy_from_slice(&bytes[20..20 + NAME_LEN]);
    GaitHeader {
        joint_count: bytes[6],
        slice_count: le_u16(bytes, 8),
        duty: le_u16(bytes, 10),
        step_period_us: le_u32(bytes, 12),
        name,
    }
}

fn check_joint(r: &[u8], joint: u8) -> Result<(), TableError> {
    let bad = |field| Err(TableError::BadJoint { joint, field });
    if r[0] > 252 {
        return bad(JointField::ServoId);
    }
    let Some(model) = ServoModel::from_table_code(r[1]) else {
        return bad(JointField::Model);
    };
    if r[2] != 1 && r[2] as i8 != -1 {
        return bad(JointField::Sign);
    }
    if usize::from(r[3]) > super::LEGS {
        return bad(JointField::Leg);
    }
    if r[10] != 0 || r[11] != 0 {
        return bad(JointField::Reserved);
    }
    if le_u16(r, 4) > 4095 {
        return bad(JointField::ZeroOffset);
    }
    if le_i16(r, 6) > le_i16(r, 8) {
        return bad(JointField::Limits);
    }
    // The bias divides by it and the servo's P gain must hold it (`limits::p_gain_holds`).
    if !crate::limits::p_gain_holds(model, le_u32(r, 12)) {
        return bad(JointField::Stiffness);
    }
    Ok(())
}
