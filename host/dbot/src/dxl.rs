//! `dbot dxl`: direct access to Dynamixel servos through a USB serial adapter (U2D2) for setting
//! them up: find IDs, read and write registers, change ID, baud and Return Delay Time.
//! `--baud auto` tries every MX(2.0) rate until servos answer. The logic is `board::bench`; this
//! file holds the arguments and the printing.

use board::bench::{Bench, Pinged, Reading, SetupRequest, Target};
use std::path::PathBuf;

use crate::common::baud::{BaudChoice, FACTORY_BAUD, mx_rate};

/// Talk to Dynamixel servos through a USB serial adapter (U2D2) or `dbot sim-bus`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot dxl scan -p /dev/ttyUSB0                     # every ID at the factory 57600 bit/s
  dbot dxl scan -p /dev/ttyUSB0 --baud auto         # try every MX rate until servos answer
  dbot dxl setup -p /dev/ttyUSB0 --id 1 --new-id 7 --new-baud 1000000 --return-delay-us 0")]
pub struct Args {
    #[command(subcommand)]
    op: Op,
    /// Serial port of the adapter (e.g. /dev/ttyUSB0, or the --link of `dbot sim-bus`)
    #[arg(long, short = 'p', global = true, default_value = "/dev/ttyUSB0")]
    port: PathBuf,
    /// Line rate, bit/s, or `auto` to try every MX(2.0) rate (57600 first) until servos answer.
    /// Default: the servos' factory rate, also the default of `dbot sim-bus`.
    #[arg(long, global = true, default_value_t = BaudChoice::Rate(FACTORY_BAUD))]
    baud: BaudChoice,
    /// Time allowed per reply beyond its wire time, µs (USB adapters add latency)
    #[arg(long, global = true, default_value_t = 20_000)]
    reply_slack_us: u32,
}

#[derive(Debug, clap::Subcommand)]
enum Op {
    /// Ping IDs 0..=MAX_ID and list the servos that answer
    Scan {
        /// Highest ID to ping
        #[arg(long, default_value_t = 252, value_parser = clap::value_parser!(u8).range(0..=252))]
        max_id: u8,
    },
    /// Read a register by name (e.g. "Present Position") or address
    Read {
        /// Servo ID (0..=252)
        #[arg(long)]
        id: u8,
        #[command(flatten)]
        register: Register,
    },
    /// Write a register by name or address (1, 2 or 4 bytes, little endian)
    Write {
        /// Servo ID (0..=252, 254 = broadcast)
        #[arg(long)]
        id: u8,
        #[command(flatten)]
        register: Register,
        /// Value to write (signed values are written as two's complement)
        #[arg(long, allow_negative_numbers = true)]
        value: i64,
    },
    /// Torque off, then set Return Delay Time, ID and baud (in that order) and check the servo answers
    Setup {
        /// ID the servo has now
        #[arg(long)]
        id: u8,
        /// New ID (0..=252)
        #[arg(long)]
        new_id: Option<u8>,
        /// New line rate in bit/s (57600, 115200, 1000000, 2000000, 3000000, 4000000, 4500000, 9600)
        #[arg(long, value_parser = mx_rate)]
        new_baud: Option<u32>,
        /// New Return Delay Time, µs (0..=508, even; the robot's bus wants 0)
        #[arg(long, alias = "return-delay")]
        return_delay_us: Option<u32>,
    },
}

/// The register a read or write addresses: a field by name, or an address and length.
#[derive(Debug, clap::Args)]
struct Register {
    /// Control table field, by e-manual name (spaces or underscores)
    #[arg(long, conflicts_with = "addr")]
    field: Option<String>,
    /// Address (with --len) instead of a field name
    #[arg(long, requires = "len")]
    addr: Option<u16>,
    /// Number of bytes at --addr (a write takes 1, 2 or 4)
    #[arg(long)]
    len: Option<u16>,
}

impl Register {
    fn target(&self) -> anyhow::Result<Target<'_>> {
        match (&self.field, self.addr, self.len) {
            (Some(name), _, _) => Ok(Target::Field(name)),
            (None, Some(addr), Some(len)) => Ok(Target::Addr { addr, len }),
            _ => anyhow::bail!("give --field NAME or --addr ADDR --len LEN"),
        }
    }
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let port = self.port.to_string_lossy().into_owned();
        let mut bench = Bench::new(&port, self.baud, self.reply_slack_us);
        let id = match &self.op {
            Op::Scan { max_id } => return scan(&mut bench, *max_id),
            Op::Read { id, .. } | Op::Write { id, .. } | Op::Setup { id, .. } => *id,
        };
        let b = bench.connect(id)?;
        if self.baud == BaudChoice::Auto {
            eprintln!("ID {id} answers at {b} bit/s");
        }
        match self.op {
            Op::Scan { .. } => Ok(()),
            Op::Read { id, register } => {
                let r = bench.read(id, register.target()?)?;
                let f = &r.field;
                println!(
                    "ID {id} {} (addr {}, {} B) = {}{}",
                    f.name,
                    f.addr,
                    f.size,
                    show(&r),
                    alert(r.alert)
                );
                Ok(())
            }
            Op::Write {
                id,
                register,
                value,
            } => {
                let w = bench.write(id, register.target()?, value)?;
                println!(
                    "ID {id} {} (addr {}) <- {value}{}",
                    w.field.name,
                    w.field.addr,
                    alert(w.alert)
                );
                Ok(())
            }
            Op::Setup {
                id,
                new_id,
                new_baud,
                return_delay_us,
            } => {
                let req = SetupRequest {
                    new_id,
                    new_baud,
                    return_delay_us,
                };
                let d = bench.setup(id, req)?;
                if let Some(us) = d.return_delay_us {
                    println!("ID {id}: Return Delay Time = {us} us");
                }
                if let Some(n) = d.new_id {
                    println!("ID {id}: ID = {n}");
                }
                if let Some(b) = d.new_baud {
                    println!("ID {}: Baud Rate = {b} bit/s", d.id);
                }
                println!(
                    "ID {} answers: model {}, firmware {}",
                    d.id, d.model_number, d.firmware
                );
                Ok(())
            }
        }
    }
}

/// Pings IDs 0..=max_id, printing each servo that answers, with a progress bar on a terminal.
fn scan(bench: &mut Bench, max_id: u8) -> anyhow::Result<()> {
    let port = bench.port().to_owned();
    // On a terminal: a bar with the ID reached and the time left (253 IDs at 57600 bit/s take
    // about 6 s, each silent ID waiting out its reply slack).
    let mut bar = indicatif::ProgressBar::hidden();
    let found = bench.scan(max_id, |p| match p {
        Pinged::Rate { baud, ids } => {
            bar.finish_and_clear();
            bar = indicatif::ProgressBar::new(ids.into())
                .with_style(
                    indicatif::ProgressStyle::with_template(
                        "{msg} {bar:30} ID {pos}/{len}, {eta} left",
                    )
                    .expect("template is valid"),
                )
                .with_message(format!("pinging {port} at {baud} bit/s"));
        }
        Pinged::Found(f) => {
            bar.inc(1);
            let name = f.model.map_or("unknown model", |m| m.name());
            bar.suspend(|| {
                println!(
                    "ID {:3}: model {} ({name}), firmware {}{}",
                    f.id,
                    f.model_number,
                    f.firmware,
                    alert(f.alert)
                )
            });
        }
        Pinged::Bad { id, error } => {
            bar.inc(1);
            bar.suspend(|| println!("ID {id:3}: answered badly: {error}"));
        }
        Pinged::Silent { .. } => bar.inc(1),
    });
    bar.finish_and_clear();
    let found = found?;
    println!(
        "{} servo(s) found on {port} at {} bit/s",
        found.found.len(),
        found.baud
    );
    Ok(())
}

fn show(r: &Reading) -> String {
    let buf = &r.bytes;
    let hex: Vec<String> = buf.iter().map(|b| format!("{b:02X}")).collect();
    match (r.unsigned(), r.signed()) {
        (Some(u), Some(_)) if buf.len() == 1 => format!("{u} (0x{})", hex[0]),
        (Some(u), Some(s)) => format!("{u} (signed {s}, 0x{})", hex.join(" ")),
        _ => hex.join(" "),
    }
}

fn alert(a: bool) -> &'static str {
    if a {
        "  [ALERT: hardware error latched, read Hardware Error Status]"
    } else {
        ""
    }
}
