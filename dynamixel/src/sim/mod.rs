//! The virtual servo chain (feature `std`): servos with control tables and a motor model
//! ([`VirtualServo`], [`physics`], heat and supply in [`thermal`]), a bus of them ([`VirtualChain`]), and a simulated wire on
//! simulated time for the master side ([`SimWire`]), with the usual set-up of both
//! ([`SimWire::drosophibot`], [`SimWire::master`]).

mod chain;
pub mod physics;
mod servo;
mod setup;
#[cfg(test)]
mod tests;
pub mod thermal;
#[cfg(test)]
mod thermal_tests;
mod wire;

pub use chain::{ChainError, DROSOPHIBOT_CTR_IDS, PlannedReply, VirtualChain};
pub use servo::{Faults, TABLE_SIZE, VirtualServo};
pub use setup::SimMaster;
pub use thermal::{Supply, Thermal};
pub use wire::{SimIoError, SimWire, WireConfig};
