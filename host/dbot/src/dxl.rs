//! `dbot dxl`: direct access to Dynamixel servos through a USB serial adapter (U2D2) for setting
//! them up: find IDs, read and write registers, change ID, baud and Return Delay Time.
//! `--baud auto` tries every MX(2.0) rate until servos answer.

use anyhow::{Context as _, bail};
use board::bus::serial::{SerialMaster, block_on, open_master};
use dynamixel::ServoModel;
use dynamixel::control_table::{self as ct, Field};
use dynamixel::master::{BusError, MasterConfig, ReplyFault};
use std::path::PathBuf;

use crate::common::baud::{BaudChoice, FACTORY_BAUD, mx_rate};
use crate::common::serial_path::check_serial_path;

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
        /// Control table field, by e-manual name (spaces or underscores)
        #[arg(long, conflicts_with = "addr")]
        field: Option<String>,
        /// Address (with --len) instead of a field name
        #[arg(long, requires = "len")]
        addr: Option<u16>,
        /// Number of bytes at --addr
        #[arg(long)]
        len: Option<u16>,
    },
    /// Write a register by name or address (1, 2 or 4 bytes, little endian)
    Write {
        /// Servo ID (0..=252, 254 = broadcast)
        #[arg(long)]
        id: u8,
        /// Control table field, by e-manual name (spaces or underscores)
        #[arg(long, conflicts_with = "addr")]
        field: Option<String>,
        /// Address (with --len) instead of a field name
        #[arg(long, requires = "len")]
        addr: Option<u16>,
        /// Number of bytes at --addr (1, 2 or 4)
        #[arg(long)]
        len: Option<u16>,
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

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        check_serial_path(&self.port)?;
        let port = self.port.to_string_lossy().into_owned();
        if let Op::Scan { max_id } = self.op {
            return scan(&port, self.baud, self.reply_slack_us, max_id);
        }
        let mut m = match self.baud {
            BaudChoice::Rate(b) => open(&port, b, self.reply_slack_us)?,
            BaudChoice::Auto => find_baud(&port, self.op.id(), self.reply_slack_us)?,
        };
        match self.op {
            Op::Scan { .. } => Ok(()),
            Op::Read {
                id,
                field,
                addr,
                len,
            } => {
                let f = resolve(field.as_deref(), addr, len)?;
                let mut buf = vec![0u8; f.size as usize];
                let st = block_on(m.read(id, f.addr, &mut buf))
                    .with_context(|| format!("reading {} of ID {id}", f.name))?;
                println!(
                    "ID {id} {} (addr {}, {} B) = {}{}",
                    f.name,
                    f.addr,
                    f.size,
                    show(&buf),
                    alert(st.alert())
                );
                Ok(())
            }
            Op::Write {
                id,
                field,
                addr,
                len,
                value,
            } => {
                let f = resolve(field.as_deref(), addr, len)?;
                let bytes =
                    encode_value(value, f.size).with_context(|| format!("value for {}", f.name))?;
                let st = block_on(m.write(id, f.addr, &bytes))
                    .with_context(|| format!("writing {} of ID {id}", f.name))?;
                println!(
                    "ID {id} {} (addr {}) <- {value}{}",
                    f.name,
                    f.addr,
                    alert(st.alert())
                );
                Ok(())
            }
            Op::Setup {
                id,
                new_id,
                new_baud,
                return_delay_us,
            } => setup(
                m,
                id,
                new_id,
                new_baud,
                return_delay_us,
                self.reply_slack_us,
            ),
        }
    }
}

impl Op {
    /// The servo a read, write or setup addresses (none for a scan).
    fn id(&self) -> u8 {
        match self {
            Op::Scan { .. } => dynamixel::instruction::BROADCAST_ID,
            Op::Read { id, .. } | Op::Write { id, .. } | Op::Setup { id, .. } => *id,
        }
    }
}

fn open(port: &str, baud: u32, slack: u32) -> anyhow::Result<SerialMaster> {
    open_master(port, baud, slack).with_context(|| format!("cannot open the bus on {port}"))
}

/// `--baud auto` for read, write and setup: the first MX rate at which servo `id` answers a ping.
fn find_baud(port: &str, id: u8, slack: u32) -> anyhow::Result<SerialMaster> {
    for b in BaudChoice::Auto.candidates() {
        let mut m = open(port, b, slack)?;
        if block_on(m.ping(id)).is_ok() {
            eprintln!("ID {id} answers at {b} bit/s");
            return Ok(m);
        }
    }
    bail!(
        "no servo with ID {id} answers on {port} at any MX rate ({}); check power and wiring",
        rates(&BaudChoice::Auto.candidates())
    )
}

fn rates(list: &[u32]) -> String {
    list.iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Pings IDs 0..=max_id at each rate of `choice`; with `auto`, stops at the first rate where
/// servos answer. Nothing answering is an error that says which rates to try next.
fn scan(port: &str, choice: BaudChoice, slack: u32, max_id: u8) -> anyhow::Result<()> {
    let tried = choice.candidates();
    for &baud in &tried {
        let mut m = open(port, baud, slack)?;
        let found = scan_at(&mut m, max_id, port, baud)?;
        if found > 0 {
            return Ok(());
        }
    }
    let others: Vec<u32> = BaudChoice::Auto
        .candidates()
        .into_iter()
        .filter(|b| !tried.contains(b))
        .collect();
    if others.is_empty() {
        bail!(
            "no servo answers on {port} at any MX rate ({}): check the servos' power and wiring",
            rates(&tried)
        );
    }
    bail!(
        "no servo answers on {port} at {} bit/s: try another rate (--baud {}) or --baud auto, and check power and wiring",
        rates(&tried),
        others[0]
    )
}

/// Pings IDs 0..=max_id at one rate, printing each servo that answers; returns how many did.
fn scan_at(m: &mut SerialMaster, max_id: u8, port: &str, baud: u32) -> anyhow::Result<usize> {
    // On a terminal: a bar with the ID reached and the time left (253 IDs at 57600 bit/s take
    // about 6 s, each silent ID waiting out its reply slack).
    let bar = indicatif::ProgressBar::new(max_id as u64 + 1)
        .with_style(
            indicatif::ProgressStyle::with_template("{msg} {bar:30} ID {pos}/{len}, {eta} left")
                .expect("template is valid"),
        )
        .with_message(format!("pinging {port} at {baud} bit/s"));
    let mut found = 0;
    for id in 0..=max_id {
        bar.inc(1);
        match block_on(m.ping(id)) {
            Ok(p) => {
                found += 1;
                let name =
                    ServoModel::from_number(p.model_number).map_or("unknown model", |m| m.name());
                bar.suspend(|| {
                    println!(
                        "ID {id:3}: model {} ({name}), firmware {}{}",
                        p.model_number,
                        p.firmware,
                        alert(p.error.alert())
                    )
                });
            }
            Err(BusError::Reply {
                fault: ReplyFault::Timeout,
                ..
            }) => {}
            Err(e) => bar.suspend(|| println!("ID {id:3}: answered badly: {e}")),
        }
    }
    bar.finish_and_clear();
    if found > 0 {
        println!("{found} servo(s) found on {port} at {baud} bit/s");
    }
    Ok(found)
}

fn setup(
    mut m: SerialMaster,
    id: u8,
    new_id: Option<u8>,
    new_baud: Option<u32>,
    rdt_us: Option<u32>,
    slack: u32,
) -> anyhow::Result<()> {
    block_on(m.ping(id)).with_context(|| format!("no servo with ID {id} answers"))?;
    block_on(m.write(id, ct::TORQUE_ENABLE.addr, &[0]))
        .context("turning torque off (EEPROM is locked while it is on)")?;
    if let Some(us) = rdt_us {
        if us > 508 || us % 2 != 0 {
            bail!(
                "--return-delay-us {us}: must be even and at most 508 (register unit 2 us, max 254)"
            );
        }
        block_on(m.write(id, ct::RETURN_DELAY_TIME.addr, &[(us / 2) as u8]))
            .context("writing Return Delay Time")?;
        println!("ID {id}: Return Delay Time = {us} us");
    }
    let mut id_now = id;
    if let Some(n) = new_id {
        if n > dynamixel::instruction::MAX_ID {
            bail!("--new-id {n}: IDs go up to 252");
        }
        if n != id && block_on(m.ping(n)).is_ok() {
            bail!("--new-id {n}: a servo with that ID already answers");
        }
        block_on(m.write(id, ct::ID.addr, &[n])).context("writing ID")?;
        id_now = n;
        println!("ID {id}: ID = {n}");
    }
    if let Some(b) = new_baud {
        let code = ct::baud_code(b)
            .with_context(|| format!("--new-baud {b}: not a rate the MX(2.0) supports"))?;
        block_on(m.write(id_now, ct::BAUD_RATE.addr, &[code])).context("writing Baud Rate")?;
        let (mut io, d, c) = m.into_parts();
        io.set_baud(b)?;
        m = dynamixel::master::BusMaster::new(
            io,
            d,
            c,
            MasterConfig {
                baud: b,
                reply_slack_us: slack,
            },
        );
        println!("ID {id_now}: Baud Rate = {b} bit/s");
    }
    let p = block_on(m.ping(id_now))
        .with_context(|| format!("the servo does not answer as ID {id_now} after setup"))?;
    println!(
        "ID {id_now} answers: model {}, firmware {}",
        p.model_number, p.firmware
    );
    Ok(())
}

fn resolve(field: Option<&str>, addr: Option<u16>, len: Option<u16>) -> anyhow::Result<Field> {
    match (field, addr, len) {
        (Some(name), _, _) => ct::field_by_name(name).with_context(|| {
            let names: Vec<&str> = ct::FIELDS.iter().map(|f| f.name).collect();
            format!(
                "--field {name:?}: no such control table field; known: {}",
                names.join(", ")
            )
        }),
        (None, Some(addr), Some(len)) if (1..=147).contains(&len) => Ok(Field {
            name: "register",
            addr,
            size: len as u8,
            eeprom: addr < 64,
            writable: true,
        }),
        (None, Some(_), Some(len)) => bail!("--len {len}: must be 1..=147 bytes"),
        _ => bail!("give --field NAME or --addr ADDR --len LEN"),
    }
}

fn encode_value(v: i64, size: u8) -> anyhow::Result<Vec<u8>> {
    let (min, max) = match size {
        1 => (i8::MIN as i64, u8::MAX as i64),
        2 => (i16::MIN as i64, u16::MAX as i64),
        4 => (i32::MIN as i64, u32::MAX as i64),
        _ => bail!("can only write 1, 2 or 4 byte registers, not {size}"),
    };
    if v < min || v > max {
        bail!("{v} does not fit in {size} byte(s) ({min}..={max})");
    }
    Ok(v.to_le_bytes()[..size as usize].to_vec())
}

fn show(buf: &[u8]) -> String {
    let hex: Vec<String> = buf.iter().map(|b| format!("{b:02X}")).collect();
    match buf.len() {
        1 => format!("{} (0x{})", buf[0], hex[0]),
        2 => format!(
            "{} (signed {}, 0x{})",
            u16::from_le_bytes([buf[0], buf[1]]),
            i16::from_le_bytes([buf[0], buf[1]]),
            hex.join(" ")
        ),
        4 => {
            let b = [buf[0], buf[1], buf[2], buf[3]];
            format!(
                "{} (signed {}, 0x{})",
                u32::from_le_bytes(b),
                i32::from_le_bytes(b),
                hex.join(" ")
            )
        }
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
