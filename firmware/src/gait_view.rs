//! The protocol's step table as playback reads it. `GaitTable::parse` checks everything (CRC over
//! the whole table included) and is run once when a gait is selected; per bus cycle the samples are
//! then read in place with the format's layout constants, so a cycle costs no CRC and no copy.

use protocol::gait::{
    CRC_LEN, GaitTable, HEADER_LEN, JOINT_RECORD_LEN, SAMPLE_LEN, SLICE_PREFIX_LEN, TableError,
    slice_len,
};

use crate::bias::JointCal;
use crate::playback::{Gait, MAX_JOINTS};

/// Micro-radians per protocol angle unit (1e-4 rad).
pub use protocol::calibration::URAD_PER_ANGLE_UNIT;

/// Shape of a checked table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Layout {
    pub joints: usize,
    pub slices: usize,
    pub period_us: u32,
}

/// What selecting a table yields: its layout, joint map (limits in ticks) and stiffness.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Checked {
    pub layout: Layout,
    pub joints: heapless::Vec<JointCal, MAX_JOINTS>,
    pub stiffness: [u32; MAX_JOINTS],
}

/// The CRC-32 a table carries in its last bytes (`GaitTable::crc` without the parse): what tells
/// two tables apart. Not the CRC-32 over all of `bytes`, which is the same constant (the CRC-32
/// residue, 0x2144DF1C) for every table whose own CRC is right. 0 for bytes too short to hold one.
pub fn stored_crc(bytes: &[u8]) -> u32 {
    match bytes.len().checked_sub(CRC_LEN) {
        Some(at) => u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]),
        None => 0,
    }
}

/// Validates `bytes` as a gait table and converts its joint map.
pub fn check(bytes: &[u8]) -> Result<Checked, TableError> {
    let t = GaitTable::parse(bytes)?;
    let layout = Layout {
        joints: t.joint_count(),
        slices: t.slice_count(),
        period_us: t.header().step_period_us,
    };
    let mut joints = heapless::Vec::new();
    let mut stiffness = [0; MAX_JOINTS];
    for (j, k) in stiffness.iter_mut().enumerate().take(layout.joints) {
        let Some(m) = t.joint(j) else { break };
        // A reversed servo turns the angle limits around in ticks.
        let calibration = m.calibration();
        let a = calibration.angle_to_ticks(m.min.into());
        let b = calibration.angle_to_ticks(m.max.into());
        let cal = JointCal {
            id: m.servo_id,
            model: m.model,
            calibration,
            min_ticks: a.min(b),
            max_ticks: a.max(b),
            leg: m.leg,
        };
        if joints.push(cal).is_err() {
            break;
        }
        *k = m.stiffness;
    }
    Ok(Checked {
        layout,
        joints,
        stiffness,
    })
}

/// Samples of a checked table, read in place.
#[derive(Debug, Clone, Copy)]
pub struct View<'a> {
    bytes: &'a [u8],
    layout: Layout,
}

impl<'a> View<'a> {
    /// `bytes` must be the table `layout` came from (the store hands out the same slice).
    pub fn new(bytes: &'a [u8], layout: Layout) -> Self {
        Self { bytes, layout }
    }

    /// Where slice `slice` starts in the table's bytes (its stance flags).
    fn slice_at(&self, slice: usize) -> usize {
        HEADER_LEN + self.layout.joints * JOINT_RECORD_LEN + slice * slice_len(self.layout.joints)
    }

    fn sample(&self, slice: usize, joint: usize, field: usize) -> i16 {
        let at = self.slice_at(slice) + SLICE_PREFIX_LEN + joint * SAMPLE_LEN + field;
        // Out of range only if bytes and layout do not belong together: read as 0, never panic.
        match self.bytes.get(at..at + 2) {
            Some(b) => i16::from_le_bytes([b[0], b[1]]),
            None => 0,
        }
    }
}

impl Gait for View<'_> {
    fn joints(&self) -> usize {
        self.layout.joints
    }
    fn slices(&self) -> usize {
        self.layout.slices
    }
    fn period_us(&self) -> u32 {
        self.layout.period_us
    }
    fn angle_urad(&self, slice: usize, joint: usize) -> i32 {
        i32::from(self.sample(slice, joint, 0)) * URAD_PER_ANGLE_UNIT
    }
    fn torque_mnm(&self, slice: usize, joint: usize) -> i32 {
        self.sample(slice, joint, 2).into()
    }
    fn stance(&self, slice: usize) -> u8 {
        self.bytes.get(self.slice_at(slice)).copied().unwrap_or(0)
    }
}
