//! The integration tests of `protocol`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

// Helpers shared by several modules.
mod common;

mod client;
mod endpoint;
mod error_words;
mod gait_name_printable;
mod gait_table;
mod golden;
mod robustness;
mod roundtrip;
mod upload;
