//! Shared constants of the on-target tests: the board's wiring and flash layout (see firmware/src/main.rs
//! and memory.x).
#![no_std]

use defmt_rtt as _;

/// Bus UART rate of the firmware (1 Mbps); the tests also run at 4 Mbps.
pub const BUS_BAUD: u32 = 1_000_000;
/// Flash size of the board (W25Q16: 2 MB).
pub const FLASH_SIZE: usize = 2 * 1024 * 1024;
/// The last 4 KB sector of the gait store: the flash tests erase and rewrite it.
pub const SCRATCH_SECTOR: u32 = FLASH_SIZE as u32 - 4096;
