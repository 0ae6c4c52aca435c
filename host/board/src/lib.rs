//! Everything on the host that talks to a board or runs one: the link (serial port, pseudo-terminal,
//! USB device discovery, transport, upload, streaming), the host's Dynamixel bus ends, recording
//! (capture, per-step statistics, telemetry CSV), trial records and their substrates, the in-process
//! virtual robot, ports by name, the robot setup file (`dbot.toml`: port, baud, rate, stiffness, model,
//! slot), the settings a `virtual:PATH` robot keeps beside its store, and the
//! rules that protect the robot, enforced by the calls that build, upload and play a step table
//! (`rules`); the lab's strain board (driver, recorder, virtual board).

pub mod bench;
pub mod bus;
pub mod counters;
pub mod files;
pub mod health;
pub mod link;
pub mod platform;
pub mod port;
pub mod record;
pub mod robot;
pub mod rules;
pub mod saved_settings;
pub mod setup_file;
pub mod slot_health;
pub mod strain;
pub mod substrate;
pub mod trial;
