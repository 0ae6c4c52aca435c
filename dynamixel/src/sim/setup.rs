//! The set-up most simulated buses start from: the robot's chain on a simulated wire with echo, and
//! a bus master driving that wire with automatic direction, clocked by the wire itself.

use super::{ChainError, SimWire, VirtualChain, WireConfig};
use crate::master::{AutoDirection, BusMaster, MasterConfig};

/// A bus master on a [`SimWire`], clocked by the same wire.
pub type SimMaster = BusMaster<SimWire, AutoDirection, SimWire>;

impl SimWire {
    /// The robot's first `n` servos ([`VirtualChain::drosophibot`]) at `baud`, every servo's
    /// Return Delay Time set to `return_delay_code`, on a wire with echo (TX and RX share one
    /// wire, as on the robot).
    pub fn drosophibot(n: u8, baud: u32, return_delay_code: u8) -> Result<Self, ChainError> {
        let mut chain = VirtualChain::drosophibot(n, baud)?;
        chain.set_return_delay_all(return_delay_code);
        Ok(Self::new(chain, WireConfig { baud, echo: true }))
    }

    /// A bus master with `config` that writes to and reads from this wire and keeps its time.
    pub fn master(&self, config: MasterConfig) -> SimMaster {
        BusMaster::new(self.clone(), AutoDirection, self.clone(), config)
    }
}
