//! The integration tests of `hil-tests`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

mod boot;
mod bus_timing;
mod device_log;
mod emulator;
mod fault_injection;
mod faults;
mod flash_full;
mod hil_emulator;
mod link;
mod platform;
mod prerequisites;
mod safety;
mod servo_bus;
mod soak;
mod stream_latency;
mod uf2_image;
mod walk;
mod walk_sequence;
