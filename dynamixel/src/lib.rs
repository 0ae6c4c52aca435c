//! Dynamixel Protocol 2.0 for the MX-28(2.0) / MX-64(2.0) servos of Drosophibot II: packet codec,
//! async bus master and control tables (`no_std`, no alloc), and with `std` a virtual servo chain
//! on a simulated half-duplex wire.
//!
//! - [`encode`] / [`parser`]: packets with CRC and byte stuffing; a streaming, resynchronising parser.
//! - [`master`]: [`master::BusMaster`] over `embedded_io_async` + [`master::DirectionPin`] + [`master::Clock`].
//! - [`model`]: [`ServoModel`], each servo model's constants in one place.
//! - [`control_table`], [`units`]: register map and SI conversions (torque ones are estimates).
//! - [`sim`] (feature `std`): [`sim::VirtualChain`] and [`sim::SimWire`] on a simulated clock.
//!
//! A bus cycle against the virtual chain, on simulated time:
//!
//! ```
//! # #[cfg(feature = "std")] {
//! use dynamixel::master::{AutoDirection, BusMaster, Goal, MasterConfig, ReplyFault};
//! use dynamixel::sim::{SimWire, VirtualChain, WireConfig};
//!
//! let mut chain = VirtualChain::drosophibot(22, 1_000_000).unwrap();
//! chain.set_return_delay_all(0);
//! let wire = SimWire::new(chain, WireConfig { baud: 1_000_000, echo: true });
//! let mut master = BusMaster::new(wire.clone(), AutoDirection, wire.clone(), MasterConfig::new(1_000_000));
//! let goals: Vec<Goal> = (1..=22).map(|id| Goal { id, position: 2048 }).collect();
//! let mut replies = [Err(ReplyFault::Timeout); 22];
//! let stats = wire.block_on(master.cycle(&goals, &mut replies)).unwrap();
//! assert_eq!(stats.ok, 22);
//! assert_eq!(stats.duration_us(), 6_220); // 622 bytes at 10 us each
//! wire.with_chain(|c| c.set_external_torque(3, 0.5).unwrap()); // load the CTr servo
//! wire.advance_us(5_000); // physics runs on the same simulated clock
//! # }
//! ```

#![cfg_attr(not(any(feature = "std", test)), no_std)]

pub mod control_table;
pub mod crc;
pub mod encode;
pub mod instruction;
pub mod master;
pub mod model;
pub mod parser;
pub mod units;

pub use model::ServoModel;

#[cfg(feature = "std")]
pub mod sim;
