//! The board's pin map: which RP2040 pins the firmware drives, in one table that `rp.rs` takes
//! its pins from (it asserts at compile time that the peripherals it names are these) and that
//! `docs/hardware.md`'s pin table is checked against (`tests/pin_map.rs`).

/// One pin the firmware uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pin {
    /// RP2040 GPIO number.
    pub gpio: u8,
    /// Its function, as the hardware page names it.
    pub function: &'static str,
    /// What it connects to.
    pub connects: &'static str,
}

/// The UART instance that drives the servo bus (UART0).
pub const BUS_UART: u8 = 0;

/// The bus UART's transmit pin (UART0 TX).
pub const BUS_TX: Pin = Pin {
    gpio: 0,
    function: "UART0 TX",
    connects: "buffer/transceiver data in (to the servos)",
};

/// The bus UART's receive pin (UART0 RX).
pub const BUS_RX: Pin = Pin {
    gpio: 1,
    function: "UART0 RX",
    connects: "buffer/transceiver data out (from the servos)",
};

/// The direction pin: high while the board drives the bus, low to listen.
pub const BUS_DIRECTION: Pin = Pin {
    gpio: 2,
    function: "bus direction",
    connects: "buffer enable / transceiver DE and /RE (high = transmit)",
};

/// Every GPIO the firmware drives, in GPIO order (USB uses the RP2040's dedicated USB pins).
pub const PINS: [Pin; 3] = [BUS_TX, BUS_RX, BUS_DIRECTION];
