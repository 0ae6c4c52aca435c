//! `dbot devices`: the boards plugged in (USB serial ports with the board's VID/PID) and what each
//! says about itself.

use std::time::Duration;

use host::link::{Board, PortSpec, list_boards};

/// List the Drosophibot II boards plugged in over USB.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// How long to wait for each board's answer, s.
    #[arg(long, default_value_t = 1.0)]
    pub timeout: f64,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let boards = list_boards()?;
        if boards.is_empty() {
            println!(
                "no board found (USB {:04x}:{:04x}); `--port virtual` runs the virtual robot",
                protocol::USB_VID,
                protocol::USB_PID
            );
            return Ok(());
        }
        for b in boards {
            print!(
                "{}  serial {}  {}",
                b.path,
                b.serial_number.as_deref().unwrap_or("-"),
                b.product.as_deref().unwrap_or("-")
            );
            let info = PortSpec::parse(&b.path).open().and_then(|t| {
                let mut board = Board::connect(t)?;
                board.set_reply_timeout(Duration::from_secs_f64(self.timeout));
                Ok(board.info().clone())
            });
            match info {
                Ok(i) => println!(
                    "  firmware {}.{}.{}  protocol {}  table format {}  {} slots of {} KB",
                    i.firmware.major,
                    i.firmware.minor,
                    i.firmware.patch,
                    i.protocol_version,
                    i.table_format_version,
                    i.slots.len(),
                    i.slot_capacity / 1024
                ),
                Err(e) => println!("  (no device info: {e})"),
            }
        }
        Ok(())
    }
}
