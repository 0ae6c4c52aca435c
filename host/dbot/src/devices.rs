//! `dbot devices`: the boards plugged in (USB serial ports with the board's VID/PID), or the ports
//! given with `--port`, and what each says about itself. Fails (after listing every port) when a
//! port cannot be opened, does not answer, or holds a board of another protocol version.

use std::time::Duration;

use anyhow::bail;
use board::link::list_boards;

/// List the Drosophibot II boards plugged in over USB and their firmware and protocol versions.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot devices                   # boards on USB
  dbot devices --port /dev/ttyACM0")]
pub struct Args {
    /// How long to wait for each board's answer, s.
    #[arg(long, default_value_t = 1.0)]
    pub timeout: f64,
    /// Ask these ports instead of looking for boards on USB (e.g. the emulator's pseudo-terminal);
    /// repeat for several.
    #[arg(long = "port", short = 'p')]
    pub ports: Vec<String>,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if !(self.timeout.is_finite() && self.timeout > 0.0 && self.timeout <= 3600.0) {
            bail!(
                "--timeout {}: give a number of seconds above 0 (at most 3600)",
                self.timeout
            );
        }
        let timeout = Duration::from_secs_f64(self.timeout);
        let ports: Vec<(String, String)> = if self.ports.is_empty() {
            let boards = list_boards()?;
            if boards.is_empty() {
                println!(
                    "no board found (USB {:04x}:{:04x}); `--port virtual` runs the virtual robot",
                    protocol::USB_VID,
                    protocol::USB_PID
                );
                return Ok(());
            }
            boards
                .into_iter()
                .map(|b| {
                    let about = format!(
                        "  serial {}  {}",
                        b.serial_number.as_deref().unwrap_or("-"),
                        b.product.as_deref().unwrap_or("-")
                    );
                    (b.path, about)
                })
                .collect()
        } else {
            self.ports
                .iter()
                .map(|p| (p.clone(), String::new()))
                .collect()
        };
        let mut failed = Vec::new();
        for (path, about) in &ports {
            let info = physics::open_within(path, timeout).map(|b| b.info().clone());
            match info {
                Ok(i) => println!(
                    "{path}{about}  firmware {}.{}.{}  protocol {}  table format {}  {} slots of {} KB",
                    i.firmware.major,
                    i.firmware.minor,
                    i.firmware.patch,
                    i.protocol_version,
                    i.table_format_version,
                    i.slots.len(),
                    i.slot_capacity / 1024
                ),
                Err(e) => {
                    println!("{path}{about}  (no device info)");
                    failed.push(e.to_string());
                }
            }
        }
        if !failed.is_empty() {
            bail!(
                "{} of {} ports did not identify as a board this dbot can drive:\n  {}",
                failed.len(),
                ports.len(),
                failed.join("\n  ")
            );
        }
        Ok(())
    }
}
