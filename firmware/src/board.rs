//! The whole firmware over its four seams, for running in-process: the host's virtual robot
//! (`dbot --port virtual`) and the simulated-wire tests drive this exactly as the RP2040's tasks
//! drive their parts (`rp.rs`): bus cycles on the bus master's clock, host bytes through the link.

use core::cell::RefCell;

use dynamixel::master::{BusMaster, Clock, DirectionPin, MasterConfig};
use embedded_io_async::{Read, ReadReady, Write};
use embedded_storage::nor_flash::NorFlash;

use crate::bus_loop::{BusLoop, Timing};
use crate::controller::{Config, Controller};
use crate::link::Link;
use crate::store::FlashWindow;

/// Controller, bus master, schedule and link of one board.
#[derive(Debug)]
pub struct Board<F, IO, D, C> {
    pub controller: RefCell<Controller<F>>,
    pub bus: BusMaster<IO, D, C>,
    pub schedule: BusLoop,
    pub link: Link,
}

impl<F, IO, D, C> Board<F, IO, D, C>
where
    F: NorFlash + FlashWindow,
    IO: Read + ReadReady + Write,
    D: DirectionPin,
    C: Clock,
{
    /// A board on `flash` (the gait region) with `slots` gait slots, talking to the servos over
    /// `io` + `direction` at `config.baud`, timed by `clock`. `reply_slack_us` is the time allowed
    /// per reply beyond its wire time (Return Delay Time plus servo turnaround).
    pub fn new(
        flash: F,
        slots: u8,
        config: Config,
        io: IO,
        direction: D,
        clock: C,
        reply_slack_us: u32,
    ) -> Self {
        let master = MasterConfig {
            baud: config.baud,
            reply_slack_us,
        };
        Self {
            controller: RefCell::new(Controller::new(flash, slots, config)),
            bus: BusMaster::new(io, direction, clock, master),
            schedule: BusLoop::new(),
            link: Link::new(),
        }
    }

    /// One bus cycle at its slot on the fixed-rate grid.
    pub async fn run_cycle(&mut self) {
        self.schedule
            .run_cycle(&self.controller, &mut self.bus)
            .await;
    }

    /// Bytes from the host; every answer frame goes to `send`.
    pub fn receive(&mut self, bytes: &[u8], mut send: impl FnMut(&[u8])) {
        self.link.receive(&self.controller, bytes, &mut send);
    }

    /// Queued telemetry, each record as one frame to `send`.
    pub fn drain_telemetry(&mut self, mut send: impl FnMut(&[u8])) {
        while let Some(frame) = self.link.telemetry(&self.controller) {
            send(frame);
        }
    }

    /// Timing of the bus loop since it started.
    pub fn timing(&self) -> Timing {
        self.schedule.timing
    }
}
