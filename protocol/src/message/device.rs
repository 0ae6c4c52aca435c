//! What the board is: versions, capabilities, gait slots.

use crate::MAX_SLOTS;
use crate::gait::GaitHeader;

/// Firmware version (semantic versioning).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FirmwareVersion {
    pub major: u16,
    pub minor: u16,
    pub patch: u16,
}

/// Feature bits of a board; a host checks them before using a feature.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Capabilities(pub u32);

impl Capabilities {
    /// Gait upload, list and delete.
    pub const GAIT_STORE: Self = Self(1 << 0);
    /// Table playback (forward, backward, period scaling).
    pub const PLAYBACK: Self = Self(1 << 1);
    /// Telemetry records during playback.
    pub const TELEMETRY: Self = Self(1 << 2);
    /// Streaming mode (setpoints and proprioception).
    pub const STREAMING: Self = Self(1 << 3);
    /// Torque feed-forward in streaming setpoints.
    pub const TORQUE_FEED_FORWARD: Self = Self(1 << 4);
    /// Run-time bus baud and cycle rate changes.
    pub const BUS_SETTINGS: Self = Self(1 << 5);

    /// No capability.
    pub const fn empty() -> Self {
        Self(0)
    }

    /// Both sets of bits.
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Whether every bit of `other` is set.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
}

/// A stored table, as the board reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GaitSummary {
    pub header: GaitHeader,
    /// CRC-32 of the table's bytes (its stored CRC).
    pub crc: u32,
}

/// One gait slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SlotInfo {
    pub slot: u8,
    /// The table the slot plays; `None` when it holds no valid table.
    pub gait: Option<GaitSummary>,
    /// A copy the board found damaged at start-up and does not use: newer than `gait` (the slot
    /// fell back to the older gait), or of unknown age when its commit record is unreadable. With
    /// `gait` `None` the slot is damaged, not empty. Cleared by the next committed upload.
    pub lost: Option<LostCopy>,
}

impl SlotInfo {
    /// Whether the slot holds damaged data: it fell back, or has no readable table at all.
    pub fn is_damaged(&self) -> bool {
        self.lost.is_some()
    }
}

/// Why the board did not use a copy of a slot's table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LossReason {
    /// The commit record holds, but the table's bytes no longer have the CRC-32 it names.
    TableChecksum,
    /// The commit record is damaged (not erased, but unreadable): nothing about the copy is known
    /// from it, not even whether it was newer.
    RecordDamaged,
}

/// A copy of a slot's table the board found damaged (see [`SlotInfo::lost`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LostCopy {
    /// Commit sequence number of the copy, from its record (`None`: the record is damaged).
    pub seq: Option<u32>,
    /// The table's CRC-32 as it carries it in its last 4 bytes (the same number as
    /// [`GaitSummary::crc`] and `dbot upload` show); `None` when the record is damaged and the
    /// table's length is unknown. Read from damaged bytes: a hint, not a fact.
    pub crc: Option<u32>,
    pub reason: LossReason,
    /// The lost table's name (NUL-padded) if its first bytes still read as a table header (magic,
    /// version and counts plausible). The bytes may be damaged too: a hint, not a fact.
    pub name: Option<[u8; crate::gait::NAME_LEN]>,
}

impl LostCopy {
    /// [`LostCopy::name`] up to the first NUL; `None` if unknown or not printable text
    /// ([`crate::gait::printable_name`]).
    pub fn name_str(&self) -> Option<&str> {
        crate::gait::printable_name(self.name.as_ref()?)
    }
}

/// Answer to [`crate::Request::GetJointMap`]: the servo ID of each joint of the selected gait.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointIds {
    /// The slot whose table names the joints.
    pub slot: u8,
    /// Dynamixel ID of joint 0, 1, ... in the table's order.
    pub servo_ids: heapless::Vec<u8, { crate::MAX_JOINTS }>,
}

/// Answer to [`crate::Request::GetDeviceInfo`].
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceInfo {
    pub firmware: FirmwareVersion,
    /// [`crate::PROTOCOL_VERSION`] of the firmware.
    pub protocol_version: u16,
    /// [`crate::gait::FORMAT_VERSION`] the firmware reads.
    pub table_format_version: u16,
    /// Build identifier: the first 8 hex digits of the git commit the firmware was built from;
    /// 0 when unknown (built outside a git checkout).
    pub build_id: u32,
    pub capabilities: Capabilities,
    /// Largest table a slot holds, bytes.
    pub slot_capacity: u32,
    /// Largest upload chunk accepted, bytes.
    pub max_chunk_len: u16,
    /// Every slot and what it holds (the number of slots is the length).
    pub slots: heapless::Vec<SlotInfo, MAX_SLOTS>,
}
