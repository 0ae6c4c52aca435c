//! The virtual servo chain process of the emulator runner: `hil-bus --servos 22 --baud 1000000`
//! speaks the runner's lock-step JSON lines on stdin/stdout (see hil_tests::servo_bus) and hosts the
//! dynamixel crate's virtual chain. `{"control":..}` lines inject faults (overload, external
//! torque, return delay, silent / corrupt / stuck servos, bus noise: `ServoBus::control`). Errors go
//! to stderr; a bad line (or a bad control) does not stop the chain.

use anyhow::{Context, Result};
use dynamixel::sim::VirtualChain;
use hil_tests::servo_bus::ServoBus;
use std::io::{BufRead, Write};

fn main() -> Result<()> {
    let mut servos = 22u8;
    let mut baud = 1_000_000u32;
    // The robot's servos run with Return Delay Time 0 (the firmware's reply slack assumes it, see
    // master_config in firmware/src/rp.rs); factory default is 250 (500 us).
    let mut return_delay = 0u8;
    // A servo's processing time before it answers at Return Delay Time 0: about 50 us as the
    // firmware's notes report for the MX-64 (master_config in firmware/src/rp.rs); an estimate,
    // the e-manual does not give it.
    let mut turnaround_us = 50u64;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = args.next().with_context(|| format!("{a} needs a value"))?;
        match a.as_str() {
            "--servos" => servos = v.parse().context("--servos: a number 1..=253")?,
            "--baud" => baud = v.parse().context("--baud: bit/s")?,
            "--turnaround-us" => {
                turnaround_us = v.parse().context("--turnaround-us: microseconds")?
            }
            "--return-delay" => {
                return_delay = v
                    .parse()
                    .context("--return-delay: register code, 2 us units")?
            }
            _ => anyhow::bail!(
                "unknown option {a} (use --servos N --baud B --return-delay CODE --turnaround-us US)"
            ),
        }
    }
    // IDs 1..=n, each the servo the robot's model file puts there (MX-28(2.0) past its 22).
    let list: Vec<(u8, dynamixel::ServoModel)> = (1..=servos)
        .map(|id| {
            let model = hil_tests::gait::servo_at(id).unwrap_or(dynamixel::ServoModel::Mx28);
            (id, model)
        })
        .collect();
    let mut chain = VirtualChain::new(&list, baud)
        .with_context(|| format!("{servos} servos at {baud} baud"))?;
    chain.set_return_delay_all(return_delay);
    let mut bus =
        ServoBus::new(chain).with_turnaround(std::time::Duration::from_micros(turnaround_us));
    let stdin = std::io::stdin();
    let mut out = std::io::stdout().lock();
    for line in stdin.lock().lines() {
        let line = line.context("reading from the runner")?;
        match bus.line(&line) {
            Ok(Some(answer)) => {
                writeln!(out, "{answer}")?;
                out.flush()?;
            }
            Ok(None) => {}
            Err(e) => {
                eprintln!("hil-bus: {e:#}");
                // A burst must always be answered, or the runner waits forever.
                if line.contains("\"tx\"") {
                    writeln!(out, "{{\"segments\":[]}}")?;
                    out.flush()?;
                }
            }
        }
    }
    Ok(())
}
