//! The Dynamixel line rate of `dbot dxl` and `dbot sim-bus`: one default for both (the servos'
//! factory rate), and `--baud auto`, which tries every rate the MX(2.0) servos support.

use std::str::FromStr;

/// The rate MX(2.0) servos leave the factory with, bit/s: the default of `dxl` and `sim-bus`, so
/// that `dbot dxl scan` finds the servos of a `dbot sim-bus` started without `--baud`.
pub const FACTORY_BAUD: u32 = 57_600;

/// The order `--baud auto` tries the rates in: the factory rate, the robot's bus rate
/// (1 Mbit/s), then the other rates of the MX(2.0) Baud Rate register.
pub const AUTO_ORDER: [u32; 8] = [
    57_600, 1_000_000, 115_200, 2_000_000, 3_000_000, 4_000_000, 4_500_000, 9_600,
];

/// `--baud`: a rate in bit/s, or `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaudChoice {
    Rate(u32),
    Auto,
}

impl BaudChoice {
    /// The rates to try, in order.
    pub fn candidates(self) -> Vec<u32> {
        match self {
            Self::Rate(b) => vec![b],
            Self::Auto => AUTO_ORDER.to_vec(),
        }
    }
}

impl std::fmt::Display for BaudChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Rate(b) => write!(f, "{b}"),
            Self::Auto => f.write_str("auto"),
        }
    }
}

impl FromStr for BaudChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        if s.eq_ignore_ascii_case("auto") {
            return Ok(Self::Auto);
        }
        s.parse::<u32>()
            .map(Self::Rate)
            .map_err(|_| format!("`{s}` is neither a rate in bit/s (e.g. 57600) nor `auto`"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_tries_every_mx_rate_once_factory_rate_first() {
        let mut tried = BaudChoice::Auto.candidates();
        assert_eq!(tried[0], 57_600);
        tried.sort_unstable();
        let mut mx: Vec<u32> = dynamixel::control_table::BAUD_RATES
            .iter()
            .map(|(_, b)| *b)
            .collect();
        mx.sort_unstable();
        assert_eq!(tried, mx);
    }

    #[test]
    fn parses_rates_and_auto_and_names_bad_input() {
        assert_eq!("1000000".parse(), Ok(BaudChoice::Rate(1_000_000)));
        assert_eq!("AUTO".parse(), Ok(BaudChoice::Auto));
        let e = "fast".parse::<BaudChoice>().unwrap_err();
        assert!(e.contains("`fast`"), "{e}");
    }
}
