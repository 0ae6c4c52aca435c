//! The strain board's item: calibrated, and its 36 channels streaming with none stuck at a rail
//! (a channel stuck at 0 or 1023 counts fails), through `board::strain::check`.

use std::time::Duration;

use board::strain::check::check;
use board::strain::{StrainBoard, Timeouts, port};

use super::{Item, chain};

/// Checks the strain board on `strain` (`virtual` or a serial port; refused when it is the
/// servo board's `servo_port`), reading `seconds` of samples after calibration.
pub fn check_strain(strain: &str, servo_port: Option<&str>, seconds: f64) -> Item {
    let name = "strain board";
    if let Some(servo) = servo_port
        && let Err(e) = port::check_not_servo_port(strain, servo)
    {
        return Item::fail(
            name,
            chain(&e),
            "give the strain board's own port (it is another USB device than the servo board)"
                .to_owned(),
        );
    }
    match port::open(strain) {
        Ok(io) => check_strain_io(io, strain, seconds),
        Err(e) => Item::fail(
            name,
            chain(&e),
            "check its USB cable and port (dbot devices lists serial ports)".to_owned(),
        ),
    }
}

/// [`check_strain`] on a strain board already open on `io` (a test double, or a port), named
/// `strain` in the item.
pub fn check_strain_io(io: Box<dyn port::StrainIo>, strain: &str, seconds: f64) -> Item {
    let name = "strain board";
    let mut b = StrainBoard::new(io, strain, Timeouts::default());
    let report = match check(&mut b, Duration::from_secs_f64(seconds.max(0.0))) {
        Ok(r) => r,
        Err(e) => {
            return Item::fail(
                name,
                chain(&e),
                "check the gauge cable it names and the board's power; dbot strain --port \
                 PORT shows the calibration"
                    .to_owned(),
            );
        }
    };
    let mut problems: Vec<String> = report
        .calibration
        .not_calibrated
        .iter()
        .map(|n| format!("{} would not calibrate", n.channel.describe()))
        .collect();
    problems.extend(report.stuck.iter().map(|s| s.to_string()));
    if problems.is_empty() {
        Item::pass(
            name,
            format!(
                "{strain}: 36 channels calibrated, {} samples, none stuck at 0 or 1023 counts",
                report.samples
            ),
        )
    } else {
        Item::fail(
            name,
            format!("{strain}: {}", problems.join("; ")),
            "check those gauges' cables and amplifiers (a channel at 0 counts: a short or a \
             broken wire; at 1023: unplugged); dbot strain --port PORT shows each gauge"
                .to_owned(),
        )
    }
}
