//! `dbot strain`: calibrates and checks the lab's strain board, printing the broken gauge, the
//! gauges that would not calibrate and their values, stuck channels and per-gauge means.

use anyhow::bail;
use board::strain::channels::{BOARD_LEGS, GAUGES_PER_LEG, GaugeKind};
use board::strain::check::{CheckReport, check};
use board::strain::{StrainBoard, Timeouts, port};
use std::time::Duration;

/// Calibrate and check the lab's strain board (36 gauges).
///
/// Opens the port (the board resets and prints its banner), sends the start byte, follows its
/// calibration, then averages a few seconds of samples per gauge and stops the stream. Exits
/// non-zero if a gauge is broken, would not calibrate or is stuck at 0 or 1023 counts.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot strain --port /dev/ttyACM1        # the strain board (the servo board is another port)
  dbot strain --port virtual             # a virtual strain board in this process
  dbot sim-strain --link /tmp/strain &   # or one on a pseudo-terminal, with faults on demand
  dbot strain --port /tmp/strain")]
pub struct Args {
    /// The strain board's serial port, or `virtual` (a virtual strain board in this process)
    #[arg(long, short)]
    port: String,
    /// Seconds of samples to average after calibration
    #[arg(long, default_value_t = 3.0, value_parser = parse_seconds)]
    seconds: f64,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let io = port::open(&self.port)?;
        let mut b = StrainBoard::new(io, self.port.clone(), Timeouts::default());
        println!(
            "{}: waiting for the strain board's banner, then calibrating",
            self.port
        );
        let report = check(&mut b, Duration::from_secs_f64(self.seconds))?;
        print!("{}", describe(&self.port, &report));
        if !report.all_good() {
            bail!(
                "{}: not every gauge is good: would not calibrate: {}; stuck: {} (see above)",
                self.port,
                report.calibration.not_calibrated.len(),
                report.stuck.len()
            );
        }
        Ok(())
    }
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 600.0 => Ok(v),
        _ => Err(format!(
            "`{s}`: seconds must be a number above 0 and at most 600"
        )),
    }
}

/// The report as the command prints it.
fn describe(port: &str, r: &CheckReport) -> String {
    let mut out = String::new();
    if r.calibration.not_calibrated.is_empty() {
        out.push_str("calibrated: all 36 gauges trimmed into 300 +- 75 counts\n");
    }
    for n in &r.calibration.not_calibrated {
        let v = n.final_value.map_or_else(
            || "no final value printed".to_owned(),
            |v| format!("final value {v}"),
        );
        out.push_str(&format!(
            "would not calibrate: {} ({v})\n",
            n.channel.describe()
        ));
    }
    for s in &r.stuck {
        out.push_str(&format!("stuck: {s}\n"));
    }
    out.push_str(&format!(
        "mean counts over {} samples from {port}:\n{:<4}",
        r.samples, "leg"
    ));
    for k in GaugeKind::ALL {
        out.push_str(&format!(" {:>16}", k.name()));
    }
    out.push('\n');
    for (l, leg) in BOARD_LEGS.iter().enumerate() {
        out.push_str(&format!("{:<4}", leg.name()));
        for g in 0..GAUGES_PER_LEG {
            out.push_str(&format!(" {:>16.2}", r.means[l * GAUGES_PER_LEG + g]));
        }
        out.push('\n');
    }
    out
}
