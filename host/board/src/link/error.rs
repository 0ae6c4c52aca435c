//! What can go wrong talking to a board, each case naming the port and the request.

use protocol::{FrameError, ProtocolError};

use super::transport::TransportError;

/// A failed exchange with a board.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LinkError {
    /// The port could not be opened.
    #[error("{port}: cannot open the link: {source}")]
    Open {
        port: String,
        #[source]
        source: TransportError,
    },
    /// The link broke: the board was unplugged, reset or switched off.
    #[error("{port}: the board vanished ({source})")]
    Vanished {
        port: String,
        #[source]
        source: TransportError,
    },
    /// No reply within the timeout.
    #[error(
        "{port}: no reply to {request} within {timeout_ms} ms (is this a Drosophibot II board, is its firmware running?)"
    )]
    NoReply {
        port: String,
        request: &'static str,
        timeout_ms: u64,
    },
    /// The board speaks another protocol version.
    #[error("{port}: the board speaks protocol version {board}, this dbot speaks {host}: update {}", if board > host { "dbot" } else { "the firmware" })]
    ProtocolVersion { port: String, board: u16, host: u16 },
    /// The board reads another gait table format.
    #[error("{port}: the board reads gait table format {board}, this dbot writes {host}: update {}", if board > host { "dbot" } else { "the firmware" })]
    TableFormat { port: String, board: u16, host: u16 },
    /// The board refused the request because it is in a fault: named, with the joint it
    /// concerns, from the board's status (issue #30: "not allowed in state Fault" named neither).
    #[error("{port}: {request} refused: the board is in a fault ({}); clear it first", fault.map_or_else(|| "fault unknown: the status did not say".to_owned(), |f| f.to_string()))]
    Faulted {
        port: String,
        request: &'static str,
        fault: Option<protocol::Fault>,
    },
    /// The board refused the request and said why.
    /// A steering value that cannot be sent (`protocol::steer`), refused before sending.
    #[error("steering: {0}")]
    Steer(protocol::SteerError),
    /// The perturbation platform refused before sending (`protocol::platform`), or its servo did
    /// not answer the board's check.
    #[error("{port}: perturbation platform: {error}")]
    Platform {
        port: String,
        error: protocol::PlatformError,
    },
    #[error("{port}: {request} refused: {error}")]
    Device {
        port: String,
        request: &'static str,
        error: ProtocolError,
    },
    /// The board could not decode a frame we sent.
    #[error("{port}: the board could not decode our {request}: {error}")]
    Rejected {
        port: String,
        request: &'static str,
        error: FrameError,
    },
    /// A reply of the wrong kind.
    #[error("{port}: unexpected reply to {request}: {got}")]
    Unexpected {
        port: String,
        request: &'static str,
        got: String,
    },
    /// A request did not fit a frame (a bug, or a table chunk too large).
    #[error("cannot encode {request}: {error}")]
    Encode {
        request: &'static str,
        error: FrameError,
    },
    /// The table to upload is not a valid table.
    #[error("the table to upload is invalid: {0}")]
    Table(protocol::TableError),
    /// The caller interrupted an upload before its commit; it was aborted (best effort), so the
    /// slot keeps what it held before.
    #[error(
        "{port}: the upload into slot {slot} was interrupted after {sent} of {total} bytes and aborted: the slot keeps its previous table"
    )]
    UploadInterrupted {
        port: String,
        slot: u8,
        sent: u32,
        total: u32,
    },
    /// The upload went through but the board's report does not match the table sent.
    #[error("{port}: verification failed: {what}")]
    Verify { port: String, what: String },
}

impl LinkError {
    /// Whether the board is gone (as opposed to refusing or misunderstanding).
    pub fn is_vanished(&self) -> bool {
        matches!(self, Self::Vanished { .. })
    }
}
