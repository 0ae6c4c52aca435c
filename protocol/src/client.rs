//! The host's typed side of the link: numbers requests and checks that a reply answers them.
//! No I/O: the host's link module moves the bytes.

use crate::Setpoint;
use crate::frame::{FrameError, encode_frame};
use crate::message::{HostMessage, Request};
pub use crate::reply::{IntoResponse, Reply, ReplyError, reply};

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
