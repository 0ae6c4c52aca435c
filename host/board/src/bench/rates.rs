//! The Dynamixel line rate of the servo bench (`dbot dxl`, `dbot.Bench`) and `dbot sim-bus`: one
//! default for both (the servos' factory rate), one parser that accepts only the rates of the MX(2.0) Baud Rate register
//! (`dynamixel::control_table::BAUD_RATES`: any other rate no servo answers at, and `0` divides
//! the byte time by zero), and `--baud auto`, which tries every one of them.

use std::str::FromStr;

/// The rate MX(2.0) servos leave the factory with, bit/s: the default of `dxl` and `sim-bus`, so
/// that `dbot dxl scan` finds the servos of a `dbot sim-bus` started without `--baud`.
pub const FACTORY_BAUD: u32 = 57_600;

/// The order `--baud auto` tries the rates in: the factory rate, the robot's bus rate
/// (1 Mbit/s), then the other rates of the MX(2.0) Baud Rate register.
pub const AUTO_ORDER: [u32; 8] = [
    57_600, 1_000_000, 115_200, 2_000_000, 3_000_000, 4_000_000, 4_500_000, 9_600,
];

/// A line rate in bit/s, or `auto` (`--baud`).
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
        mx_rate(s)
            .map(Self::Rate)
            .map_err(|e| format!("{e}, or `auto`"))
    }
}

/// Rates as text: `57600, 1000000`.
pub fn list(rates: &[u32]) -> String {
    let rates: Vec<String> = rates.iter().map(u32::to_string).collect();
    rates.join(", ")
}

/// The rates an MX(2.0) servo supports, bit/s, ascending, as text: `9600, 57600, ...`.
fn mx_rates() -> String {
    let mut rates: Vec<u32> = dynamixel::control_table::BAUD_RATES
        .iter()
        .map(|(_, b)| *b)
        .collect();
    rates.sort_unstable();
    list(&rates)
}

/// A `--baud` / `--new-baud` rate: one of the MX(2.0) rates, bit/s (clap value parser).
pub fn mx_rate(s: &str) -> Result<u32, String> {
    let rate: u32 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a rate in bit/s: give one of {}", mx_rates()))?;
    match dynamixel::control_table::baud_code(rate) {
        Some(_) => Ok(rate),
        None => Err(format!(
            "{rate} bit/s is not a rate an MX(2.0) servo supports: give one of {}",
            mx_rates()
        )),
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

    #[test]
    fn only_the_rates_of_the_mx_baud_register_are_accepted() {
        // 0 divided the byte time by zero; 1 bit/s made every reply timeout hours long.
        for bad in ["0", "1", "57601", "4294967295"] {
            let e = bad.parse::<BaudChoice>().unwrap_err();
            assert!(
                e.contains("not a rate an MX(2.0) servo supports")
                    && e.contains(
                        "9600, 57600, 115200, 1000000, 2000000, 3000000, 4000000, 4500000"
                    ),
                "{bad}: {e}"
            );
            assert!(mx_rate(bad).is_err(), "{bad}");
        }
        // The e-manual's Baud Rate (8) table, by hand.
        for good in [
            9600, 57_600, 115_200, 1_000_000, 2_000_000, 3_000_000, 4_000_000, 4_500_000,
        ] {
            assert_eq!(mx_rate(&good.to_string()), Ok(good));
        }
    }
}
