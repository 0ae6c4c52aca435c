//! What a reply carries, both ways: [`Reply`] (a [`Response`] read as a typed value, the host's
//! side), [`IntoResponse`] (a typed value sent as a [`Response`], the board's side), the two
//! upload replies that are structs of their own, and [`reply`], which checks a device message
//! answers a request. Shared by the client and the endpoint table, which import it and not each
//! other.

use core::fmt;

use crate::frame::FrameError;
use crate::message::{
    DeviceInfo, DeviceMessage, JointIds, PlatformStatus, Response, ServoReadResult, Settings,
    SlotInfo, Status,
};
use crate::{MAX_SLOTS, ProtocolError};

/// Reply to [`UploadChunk`](crate::endpoint::UploadChunk): `received` bytes of the table have arrived in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChunkAccepted {
    pub received: u32,
}

/// Reply to [`UploadCommit`](crate::endpoint::UploadCommit): the upload verified and `slot` now holds the table with `crc`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Committed {
    pub slot: u8,
    pub crc: u32,
}

/// Why a device message is not the expected reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ReplyError {
    /// The board answered with an error.
    Device(ProtocolError),
    /// The board could not decode a frame we sent.
    Rejected(FrameError),
    /// A reply to another request.
    WrongSeq { expected: u16, got: u16 },
    /// Not a reply (telemetry, proprioception): route it elsewhere and keep waiting.
    NotAReply,
    /// A reply of another kind than the request's.
    Unexpected,
}

impl fmt::Display for ReplyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Device(e) => write!(f, "board error: {e}"),
            Self::Rejected(e) => write!(f, "board rejected our frame: {e}"),
            Self::WrongSeq { expected, got } => {
                write!(f, "reply to request {got}, expected {expected}")
            }
            Self::NotAReply => write!(f, "not a reply"),
            Self::Unexpected => write!(f, "reply of another kind than the request's"),
        }
    }
}

impl core::error::Error for ReplyError {}

/// A value a [`Response`] can carry.
pub trait Reply: Sized {
    /// The value, or `None` when the response is of another kind.
    fn from_response(response: Response) -> Option<Self>;
}

impl Reply for Response {
    fn from_response(response: Response) -> Option<Self> {
        Some(response)
    }
}

/// A value the board sends back as a [`Response`] (the inverse of [`Reply`]).
pub trait IntoResponse {
    fn into_response(self) -> Response;
}

/// `Response::Ack`.
impl Reply for () {
    fn from_response(response: Response) -> Option<Self> {
        matches!(response, Response::Ack).then_some(())
    }
}

impl IntoResponse for () {
    fn into_response(self) -> Response {
        Response::Ack
    }
}

impl Reply for ChunkAccepted {
    fn from_response(response: Response) -> Option<Self> {
        match response {
            Response::ChunkAccepted { received } => Some(Self { received }),
            _ => None,
        }
    }
}

impl IntoResponse for ChunkAccepted {
    fn into_response(self) -> Response {
        Response::ChunkAccepted {
            received: self.received,
        }
    }
}

impl Reply for Committed {
    fn from_response(response: Response) -> Option<Self> {
        match response {
            Response::Committed { slot, crc } => Some(Self { slot, crc }),
            _ => None,
        }
    }
}

impl IntoResponse for Committed {
    fn into_response(self) -> Response {
        Response::Committed {
            slot: self.slot,
            crc: self.crc,
        }
    }
}

macro_rules! reply_variant {
    ($ty:ty, $variant:ident) => {
        impl Reply for $ty {
            fn from_response(response: Response) -> Option<Self> {
                match response {
                    Response::$variant(v) => Some(v),
                    _ => None,
                }
            }
        }
        impl IntoResponse for $ty {
            fn into_response(self) -> Response {
                Response::$variant(self)
            }
        }
    };
}

reply_variant!(DeviceInfo, DeviceInfo);
reply_variant!(Status, Status);
reply_variant!(Settings, Settings);
reply_variant!(heapless::Vec<SlotInfo, MAX_SLOTS>, Slots);
reply_variant!(Option<JointIds>, JointMap);
reply_variant!(Option<PlatformStatus>, Platform);
reply_variant!(Option<ServoReadResult>, ServoRead);

/// Takes `message` as the reply to request `seq` and extracts the value of type `R`.
pub fn reply<R: Reply>(seq: u16, message: DeviceMessage) -> Result<R, ReplyError> {
    match message {
        DeviceMessage::Reply { seq: got, response } => {
            if got != seq {
                return Err(ReplyError::WrongSeq { expected: seq, got });
            }
            if let Response::Error(e) = response {
                return Err(ReplyError::Device(e));
            }
            R::from_response(response).ok_or(ReplyError::Unexpected)
        }
        DeviceMessage::Rejected(e) => Err(ReplyError::Rejected(e)),
        DeviceMessage::Telemetry(_)
        | DeviceMessage::Proprioception(_)
        | DeviceMessage::SetpointRejected { .. } => Err(ReplyError::NotAReply),
    }
}
