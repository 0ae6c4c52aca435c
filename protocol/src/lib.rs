//! The one contract between `dbot` on the host and the Drosophibot II firmware: the messages, their
//! framing, and the step-table (gait table) format. `no_std` without alloc by default; the `std`
//! feature adds the host-side `GaitTableBuilder` and `Vec`-returning helpers.
//!
//! # Frame layout
//!
//! Every message on the USB CDC-ACM link, in both directions, is one frame:
//!
//! ```text
//! COBS( postcard(message) ++ crc32_le(postcard(message)) ) ++ 0x00
//! ```
//!
//! * `message` is a [`HostMessage`] (host to board) or a [`DeviceMessage`] (board to host),
//!   serialized with postcard 1.x (varint integers, zigzag for signed, enum variant index as a varint,
//!   `Option` as a 0/1 tag, sequences as varint length + elements).
//! * The CRC-32 is CRC-32/ISO-HDLC (the zlib / Ethernet CRC, check value `0xCBF43926`), little-endian.
//!   USB itself is reliable, but the link also runs over pseudo-terminals and the board must tell a
//!   garbage frame from a request: without the CRC a burst of noise can decode as a valid `Play`.
//! * COBS removes every zero byte, so `0x00` only ever ends a frame; a receiver resynchronises at the
//!   next zero after garbage. Empty frames (`00 00`) are ignored and may be sent to flush a receiver.
//! * A frame decodes to at most [`MAX_MESSAGE_LEN`] postcard bytes; on the wire it is at most
//!   [`MAX_FRAME_LEN`] bytes including the delimiter. [`FrameAccumulator`] takes bytes in any chunking
//!   and turns anything else into a [`FrameError`], never a panic.
//!
//! Every [`Request`] travels in [`HostMessage::Request`] with a sequence number that the board echoes in
//! [`DeviceMessage::Reply`]; the reply is a [`Response`], errors included ([`Response::Error`] carrying
//! a [`ProtocolError`]). A frame the board cannot decode is answered with
//! [`DeviceMessage::Rejected`] (its sequence number is unknown). Streaming setpoints
//! ([`HostMessage::Setpoint`]) are not requests: at up to 400 Hz a reply each would double the
//! traffic, so the board answers them with [`DeviceMessage::Proprioception`], which names the last
//! setpoint it applied.
//!
//! The board's side in a few lines (bytes arrive from USB in any chunking):
//!
//! ```
//! use protocol::*;
//!
//! fn handle(request: &Request) -> Response {
//!     match request {
//!         Request::GetStatus => Response::Error(ProtocolError::Unsupported),
//!         _ => Response::Ack,
//!     }
//! }
//!
//! let mut acc = FrameAccumulator::new();
//! let mut out = [0u8; MAX_FRAME_LEN];
//! # let mut host = Client::new();
//! # let mut buf = [0u8; MAX_FRAME_LEN];
//! # let (_, usb_bytes) = host.encode_request(&Request::Stop, &mut buf).unwrap();
//! for message in acc.messages::<HostMessage>(usb_bytes) {
//!     let reply = match message {
//!         Ok(HostMessage::Request { seq, request }) => {
//!             DeviceMessage::Reply { seq, response: handle(&request) }
//!         }
//!         Ok(HostMessage::Setpoint(_)) => continue,
//!         Err(e) => DeviceMessage::Rejected(e),
//!     };
//!     let frame = encode_frame(&reply, &mut out).unwrap();
//!     // write `frame` to the CDC-ACM endpoint
//! #   assert_eq!(frame.last(), Some(&0));
//! }
//! ```
//!
//! # Why a plain dispatcher and not postcard-rpc
//!
//! postcard-rpc's embassy server speaks over raw USB bulk endpoints (a vendor-class interface reached
//! with nusb on the host), not over CDC-ACM, and its wire header carries hashes of endpoint schemas.
//! This project needs CDC-ACM (the board shows up as a serial port, the emulator bridges it to a
//! pseudo-terminal, `dbot --port` works the same for both), a frame layout that can be derived by hand
//! for the golden tests, and no second dependency pinned to a particular embassy-usb. So the protocol is
//! two enums and a frame codec; the firmware implements [`endpoint::Handler`] (one typed method per request, reached through
//! [`endpoint::dispatch`]) and the host calls [`endpoint`]'s typed requests through [`Client`].
//!
//! # Units (fixed point on the device)
//!
//! | quantity | type | unit | range |
//! |---|---|---|---|
//! | joint angle (table, setpoints, telemetry, limits) | `i16` | 1e-4 rad ([`units::ANGLE_PER_RAD`]) | +-3.2767 rad |
//! | joint torque (table, feed-forward) | `i16` | mN m ([`units::TORQUE_PER_NM`]) | +-32.767 N m |
//! | joint velocity (feedback) | `i16` | 1e-3 rad/s ([`units::VELOCITY_PER_RAD_S`]) | +-32.767 rad/s |
//! | servo stiffness (torque bias) | `u32` | mN m / rad ([`units::STIFFNESS_PER_NM_RAD`]) | 1 .. 4.29e6 mN m/rad |
//! | servo zero offset | `u16` | servo ticks, 4096 per turn | 0 ..= 4095 |
//! | step period | `u32` | microseconds | 1 .. 4294 s |
//! | duty factor, period scale | `u16` | 1e-4 of the step, 1e-3 (1000 = as planned) | |
//! | load / current (feedback) | `i16` | raw register 126: MX-28 0.1 % of max load, MX-64 about 3.36 mA | |
//!
//! Angles are in the joint frame (the planner's angle); a servo's goal is
//! `zero_offset + sign * angle * 4096 / 2 pi` ticks, computed by [`Calibration`] (the one angle <->
//! ticks converter, shared by the table's [`JointMap::angle_to_ticks`], the firmware and the host).
//! The firmware's torque bias is `angle + torque / stiffness` (mN m over mN m/rad gives rad),
//! computed in microradians in `i64` (`firmware::bias`), turned into ticks by the same
//! [`Calibration`] and clamped to the joint's limits in ticks.
//!
//! # Versioning
//!
//! [`PROTOCOL_VERSION`] changes with any change of the encoded bytes of a message (the golden-byte tests
//! in `tests/integration/golden.rs` fail first, on purpose); [`gait::FORMAT_VERSION`] changes with the table layout.
//! New message variants are appended at the end of their enum so older variants keep their index;
//! such an addition still bumps the version when the board can send the new variant (an older host
//! cannot decode it and would fail only when it arrives: version 2 added `FaultKind::ServoStuck`,
//! which arrives exactly when the robot has stopped on a fault), so the host refuses the board up front.
//! [`DeviceInfo`] reports both versions and [`Capabilities`] so the host can refuse a board it does
//! not understand before sending anything else.

#![cfg_attr(not(feature = "std"), no_std)]

pub mod calibration;
pub mod client;
pub mod crc32;
pub mod endpoint;
pub mod frame;
pub mod gait;
pub mod limits;
pub mod message;
pub mod platform;
mod reply;
pub mod steer;
pub mod switch;
pub mod units;
pub mod upload;

pub use calibration::Calibration;
pub use client::{Client, ReplyError};
pub use endpoint::Endpoint;
pub use frame::{FrameAccumulator, FrameError, decode_message, encode_frame};
#[cfg(feature = "std")]
pub use gait::{BuildError, GaitTableBuilder, JointSpec};
pub use gait::{GaitHeader, GaitTable, JointMap, ServoModel, Sign, TableError};
pub use message::*;
pub use platform::PlatformError;
pub use steer::SteerError;
pub use switch::{SwitchError, check_switch};
pub use upload::{UploadError, UploadLimits, UploadTracker};

/// Version of the wire protocol; bumped on every change of the encoded bytes.
pub const PROTOCOL_VERSION: u16 = 9;

/// USB vendor ID of the board: pid.codes' open-source vendor ID.
pub const USB_VID: u16 = 0x1209;
/// USB product ID of the board. 0x0001 is pid.codes' test PID (not for distribution): a lab that
/// builds boards for others should register its own.
pub const USB_PID: u16 = 0x0001;
/// USB product string, also used by `dbot devices` to recognise a board.
pub const USB_PRODUCT: &str = "Drosophibot II controller";

/// Most joints a table, a setpoint or a telemetry record can carry (the robot has 22).
pub const MAX_JOINTS: usize = 32;
/// Most gait slots a board can report.
pub const MAX_SLOTS: usize = 8;
/// Most table bytes in one upload chunk.
pub const MAX_CHUNK_LEN: usize = 512;
/// Longest postcard encoding of any message (checked against the largest value of every message
/// in the tests; 631 bytes: a telemetry record of 32 joints with every servo's heat and supply,
/// protocol version 8).
pub const MAX_MESSAGE_LEN: usize = 700;
/// Bytes of the frame CRC that follows the message inside the COBS encoding.
pub const FRAME_CRC_LEN: usize = 4;
/// Longest frame on the wire: message + CRC, COBS overhead (one byte per started 254), delimiter.
pub const MAX_FRAME_LEN: usize = {
    let inner = MAX_MESSAGE_LEN + FRAME_CRC_LEN;
    inner + inner.div_ceil(254) + 1
};
