//! The host's typed side of the link: numbers requests and checks that a reply answers them.
//! No I/O: the host's link module moves the bytes.

use core::fmt;

use crate::endpoint::{ChunkAccepted, Committed};
use crate::frame::{FrameError, encode_frame};
use crate::message::{
    DeviceInfo, DeviceMessage, HostMessage, JointIds, Request, Response, Settings, SlotInfo, Status,
};
use crate::{MAX_SLOTS, ProtocolError, Setpoint};

/// Numbers requests (wrapping `u16` sequence numbers) and encodes them as frames.
#[derive(Debug, Clone, Default)]
pub struct Client {
    next_seq: u16,
}

impl Client {
    /// A client whose first request has sequence number 0.
    pub const fn new() -> Self {
        Self { next_seq: 0 }
    }

    /// The sequence number of the next request.
    pub fn next_seq(&self) -> u16 {
        self.next_seq
    }

    /// Encodes `request` as a frame into `buf`; returns its sequence number and the frame.
    pub fn encode_request<'b>(
        &mut self,
        request: &Request,
        buf: &'b mut [u8],
    ) -> Result<(u16, &'b [u8]), FrameError> {
        let seq = self.next_seq;
        let frame = encode_frame(
            &HostMessage::Request {
                seq,
                request: request.clone(),
            },
            buf,
        )?;
        self.next_seq = seq.wrapping_add(1);
        Ok((seq, frame))
    }

    /// Encodes `request` as a new frame `Vec`; returns its sequence number and the frame.
    #[cfg(feature = "std")]
    pub fn request_frame(&mut self, request: &Request) -> Result<(u16, Vec<u8>), FrameError> {
        let mut buf = vec![0u8; crate::MAX_FRAME_LEN];
        let (seq, len) = {
            let (seq, frame) = self.encode_request(request, &mut buf)?;
            (seq, frame.len())
        };
        buf.truncate(len);
        Ok((seq, buf))
    }

    /// Encodes a streaming setpoint as a frame into `buf`.
    pub fn encode_setpoint<'b>(
        setpoint: &Setpoint,
        buf: &'b mut [u8],
    ) -> Result<&'b [u8], FrameError> {
        encode_frame(&HostMessage::Setpoint(setpoint.clone()), buf)
    }
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
