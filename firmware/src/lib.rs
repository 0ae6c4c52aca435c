//! Hardware-independent logic of the Drosophibot II controller firmware.
//!
//! Everything here is `no_std` and free of embassy-rp, so it runs on the RP2040 and in host tests
//! alike: the binary (`main.rs` + `rp.rs`) only wires these pieces to the UART, the USB link, the
//! flash and the clock. Each piece of hardware is reached through one seam with a test double:
//!
//! | seam | trait | board | double |
//! |---|---|---|---|
//! | flash | `NorFlash` + [`store::FlashWindow`] | embassy-rp flash + XIP window | `store::nor_double::NorDouble` (feature `std`) |
//! | bus | `embedded_io_async::{Read, Write}` + `dynamixel::master::DirectionPin` | BufferedUart + GPIO | `dynamixel::sim::SimWire` |
//! | clock | `dynamixel::master::Clock` | embassy-time | `SimWire` (simulated time) |
//! | link | `embedded_io_async::{Read, Write}` | USB CDC-ACM | in-memory pipe |
//!
//! - [`store`]: A/B gait slots with commit records, power-loss safe.
//! - [`playback`], [`bias`], [`gait_view`]: gait clock, interpolation, torque bias in fixed point.
//! - [`safety`]: the state machine; [`controller`]: what to do each bus cycle and on each command.
//! - [`bus_loop`]: the fixed-rate loop over the bus master; [`link`]: the protocol dispatcher.
//! - [`pins`]: the RP2040 pins the firmware drives (`rp.rs` and `docs/hardware.md` follow it).
//! - [`device_log`]: every state change and fault, logged with defmt in the image.
//! - [`board`]: all of it over the four seams, for in-process use (host virtual robot, tests).
//! - [`testkit`] (feature `std`): the synthetic gait and the whole-board rig on the simulated wire,
//!   shared by the unit tests, the integration tests in `tests/` (a walk on the wire, the fault
//!   campaign, streaming) and the host's virtual-robot tests.

#![cfg_attr(not(any(test, feature = "std")), no_std)]

#[cfg(any(test, feature = "std"))]
extern crate std;

pub mod bias;
pub mod board;
pub mod build_id;
pub mod bus_loop;
pub mod controller;
pub mod device_log;
pub mod gait_view;
pub mod goal_step;
pub mod link;
pub mod memory_map;
pub mod pins;
pub mod playback;
pub mod safety;
pub mod store;
pub mod telemetry;
#[cfg(any(test, feature = "std"))]
pub mod testkit;
