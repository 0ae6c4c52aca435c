//! The messages: what the host sends ([`HostMessage`]), what the board sends ([`DeviceMessage`]).
//!
//! New variants go at the end of an enum (postcard encodes the variant index), and any change of
//! the encoded bytes bumps [`crate::PROTOCOL_VERSION`].

mod device;
mod error;
mod health;
mod platform;
mod request;
mod servo_read;
mod status;
mod steer;
mod stream;

pub use device::{
    Capabilities, DeviceInfo, FirmwareVersion, GaitSummary, JointIds, LossReason, LostCopy,
    SlotInfo,
};
pub use error::{Fault, FaultKind, ProtocolError, Setting};
pub use health::{
    HealthAlarm, HealthKind, HealthLevel, HealthLimitError, HealthLimits, SERVO_MAX_VOLTAGE_DV,
    SERVO_MIN_VOLTAGE_DV, SERVO_TEMPERATURE_LIMIT_C, ServoHealth,
};
pub use platform::{PlatformFeedback, PlatformMove, PlatformSetup, PlatformState, PlatformStatus};
pub use request::{
    Direction, PlayCommand, QueueCommand, Request, ServoSelect, Steps, StreamConfig,
};
pub use servo_read::{MAX_SERVO_READ, ServoRead, ServoReadOutcome, ServoReadResult};
pub use status::{
    Counters, JointSettings, PlaybackPosition, RunState, Settings, Status, UploadProgress,
};
pub use steer::{SteerCommand, SteerFamily};
pub use stream::{
    BusStats, JointFeedback, JointSetpoint, Proprioception, Setpoint, Telemetry, feedback_flags,
};

// Messages live in fixed-size buffers on a board without a heap: boxing the large variant is not
// an option, and the size is bounded by MAX_JOINTS / MAX_CHUNK_LEN.
#[allow(clippy::large_enum_variant)]
/// Everything the host sends to the board.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HostMessage {
    /// A request; the board answers with a [`DeviceMessage::Reply`] carrying the same `seq`.
    Request { seq: u16, request: Request },
    /// A streaming setpoint (only in [`RunState::Streaming`]); not answered, see
    /// [`Proprioception::setpoint_seq`].
    Setpoint(Setpoint),
}

// Messages live in fixed-size buffers on a board without a heap: boxing the large variant is not
// an option, and the size is bounded by MAX_JOINTS / MAX_CHUNK_LEN.
#[allow(clippy::large_enum_variant)]
/// Everything the board sends to the host.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DeviceMessage {
    /// The answer to the request with the same `seq`.
    Reply { seq: u16, response: Response },
    /// Telemetry of one bus cycle outside streaming (every Nth cycle, see [`Request::SetTelemetry`]).
    Telemetry(Telemetry),
    /// Feedback of one bus cycle in streaming mode (every Nth cycle, see
    /// [`crate::StreamConfig::feedback_every`]).
    Proprioception(Proprioception),
    /// A frame that could not be decoded (so its `seq` is unknown) and was dropped.
    Rejected(crate::FrameError),
    /// A streaming setpoint that was not applied (not streaming, wrong joint count, ...).
    SetpointRejected { seq: u32, error: ProtocolError },
}

// Messages live in fixed-size buffers on a board without a heap: boxing the large variant is not
// an option, and the size is bounded by MAX_JOINTS / MAX_CHUNK_LEN.
#[allow(clippy::large_enum_variant)]
/// The result of a request: a value, an acknowledgement, or the error, carried as data.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Response {
    /// Done (requests without a result value).
    Ack,
    DeviceInfo(DeviceInfo),
    Status(Status),
    Settings(Settings),
    /// Contents of every gait slot.
    Slots(heapless::Vec<SlotInfo, { crate::MAX_SLOTS }>),
    /// A chunk was stored; `received` bytes of the table have arrived in order.
    ChunkAccepted {
        received: u32,
    },
    /// The upload verified and the slot now holds the new table.
    Committed {
        slot: u8,
        crc: u32,
    },
    /// The request failed; nothing changed unless the error says otherwise.
    Error(ProtocolError),
    /// Servo IDs of a table's joints; `None` when the slot is empty or no gait is selected.
    JointMap(Option<JointIds>),
    /// The platform set up and its servo's state; `None` when none is set (appended: protocol
    /// version 7).
    Platform(Option<PlatformStatus>),
    /// Reply to `GetServoRead`: the last finished servo read, `None` while it is pending or when
    /// none was asked (appended: protocol version 9).
    ServoRead(Option<ServoReadResult>),
}

#[cfg(feature = "std")]
impl Response {
    /// The reply's kind in words ("a status", "an error: ..."), for an error that got one it did not
    /// expect.
    pub fn describe(&self) -> String {
        match self {
            Response::Ack => "an acknowledgement".into(),
            Response::DeviceInfo(_) => "the device information".into(),
            Response::Status(s) => format!("a status (state {})", s.state),
            Response::Settings(_) => "the settings".into(),
            Response::Slots(s) => format!("the list of {} gait slots", s.len()),
            Response::ChunkAccepted { received } => {
                format!("an accepted upload chunk ({received} bytes so far)")
            }
            Response::Committed { slot, crc } => {
                format!("a committed upload (slot {slot}, CRC {crc:#010x})")
            }
            Response::Error(e) => format!("an error: {e}"),
            Response::JointMap(_) => "a joint map".into(),
            Response::Platform(_) => "the perturbation platform's set-up".into(),
            Response::ServoRead(_) => "a servo read's result".into(),
        }
    }
}
