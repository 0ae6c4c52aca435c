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
    /// `None` when empty.
    pub gait: Option<GaitSummary>,
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
    /// Build identifier (e.g. the first 4 bytes of the git commit).
    pub build_id: u32,
    pub capabilities: Capabilities,
    /// Largest table a slot holds, bytes.
    pub slot_capacity: u32,
    /// Largest upload chunk accepted, bytes.
    pub max_chunk_len: u16,
    /// Every slot and what it holds (the number of slots is the length).
    pub slots: heapless::Vec<SlotInfo, MAX_SLOTS>,
}
