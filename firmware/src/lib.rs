//! Hardware-independent logic of the Drosophibot II controller firmware.
//!
//! Everything here is `no_std` and free of embassy-rp, so it runs on the RP2040 and in host tests
//! alike: the binary (`main.rs`) only wires these pieces to the UART, the USB link, the flash and
//! the clock. Each piece of hardware is reached through one seam (a trait) with a test double.

#![cfg_attr(not(any(test, feature = "std")), no_std)]

#[cfg(any(test, feature = "std"))]
extern crate std;

pub mod bias;
pub mod bus_loop;
pub mod controller;
pub mod gait_view;
pub mod link;
pub mod memory_map;
pub mod playback;
pub mod safety;
pub mod store;
pub mod telemetry;
#[cfg(any(test, feature = "std"))]
pub mod testkit;
