//! Firmware entry point for the RP2040: the only file that touches embassy-rp.
//!
//! Wiring (Drosophibot II power board): UART0 TX = GPIO0, RX = GPIO1 to the half-duplex Dynamixel bus
//! through a tri-state buffer whose direction pin is GPIO2 (high = drive); USB CDC-ACM to the host;
//! defmt logs over RTT (read them with `probe-rs run`). On the host this file builds to a stub.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "this is the RP2040 firmware; build and flash it from firmware/ with `cargo run --release` \
         (target thumbv6m-none-eabi, probe-rs runner)"
    );
    std::process::exit(2);
}

#[cfg(target_os = "none")]
mod rp;
