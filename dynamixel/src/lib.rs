//! Dynamixel Protocol 2.0 for the MX-28(2.0) / MX-64(2.0) servos of Drosophibot II: packet codec,
//! async bus master and control tables (`no_std`, no alloc), and with `std` a virtual servo chain
//! on a simulated half-duplex wire.
//!
//! - [`encode`] / [`parser`]: packets with CRC and byte stuffing; a streaming, resynchronising parser.
//! - [`master`]: [`master::BusMaster`] over `embedded_io_async` + [`master::DirectionPin`] + [`master::Clock`].
//! - [`control_table`], [`units`]: register map and SI conversions (torque ones are estimates).
//! - [`sim`] (feature `std`): [`sim::VirtualChain`] and [`sim::SimWire`] on a simulated clock.

#![cfg_attr(not(any(feature = "std", test)), no_std)]

pub mod control_table;
pub mod crc;
pub mod encode;
pub mod instruction;
pub mod master;
pub mod parser;
pub mod units;

#[cfg(feature = "std")]
pub mod sim;
