//! The integration tests of `dynamixel`, one module per topic, linked into one test binary (one link
//! instead of one per file; nextest still runs each test in its own process).

mod master_reply_slots;
mod master_sim;
mod parser_props;
mod stuffing;
mod units;
mod vectors;
