//! The one contract between `dbot` on the host and the Drosophibot II firmware: messages and the
//! step-table format, encoded with postcard. `no_std` without alloc by default; `std` for the host.

#![cfg_attr(not(feature = "std"), no_std)]

/// Version of the wire protocol; bumped on every change of the encoded bytes.
pub const PROTOCOL_VERSION: u16 = 1;

/// USB vendor ID of the board: pid.codes' open-source vendor ID.
pub const USB_VID: u16 = 0x1209;
/// USB product ID of the board. 0x0001 is pid.codes' test PID (not for distribution): a lab that
/// builds boards for others should register its own.
pub const USB_PID: u16 = 0x0001;
/// USB product string, also used by `dbot devices` to recognise a board.
pub const USB_PRODUCT: &str = "Drosophibot II controller";
