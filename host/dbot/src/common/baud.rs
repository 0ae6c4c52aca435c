//! The Dynamixel line rate of `dbot dxl` and `dbot sim-bus`: the parser, the factory rate and
//! `--baud auto` live in `board::bench::rates`, shared with the Python `dbot.Bench`.

pub use board::bench::rates::{BaudChoice, FACTORY_BAUD, mx_rate};
