//! A register read or a ping the board does on its servo bus for the host (appended: protocol
//! version 9), so that a bring-up check (`dbot doctor`) reads every servo through the board, as it
//! does through a U2D2 on the bus. The board performs it between bus cycles when the cycle leaves
//! the time for it (never at the cost of the cycle's rate), in any state; the host asks with
//! [`crate::Request::ReadServo`] and collects the result with [`crate::Request::GetServoRead`].

/// Most bytes one read returns (a control table field is at most 4; the doctor reads one field at
/// a time).
pub const MAX_SERVO_READ: usize = 32;

/// What to read: `len` bytes at `addr` of servo `id`; `len` 0 is a Ping (model number and firmware
/// version).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ServoRead {
    pub id: u8,
    pub addr: u16,
    pub len: u8,
}

/// How a read or ping came back.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ServoReadOutcome {
    /// The bytes read, and the status packet's error byte (0: none; bit 7 the Alert).
    Data {
        error: u8,
        data: heapless::Vec<u8, MAX_SERVO_READ>,
    },
    /// The ping's reply: the servo's model number and firmware version, and the error byte.
    Ping {
        error: u8,
        model_number: u16,
        firmware: u8,
    },
    /// No reply in time.
    Timeout,
    /// A reply that failed its CRC or was not the status asked for.
    Corrupt,
}

/// A finished read: what was asked and how it came back.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ServoReadResult {
    pub request: ServoRead,
    pub outcome: ServoReadOutcome,
}
