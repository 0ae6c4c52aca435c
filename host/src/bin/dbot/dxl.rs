//! `dbot dxl`: direct access to Dynamixel servos through a USB serial adapter (U2D2) for setting
//! them up: find IDs, read and write registers, change ID, baud and Return Delay Time.

use anyhow::{Context as _, bail};
use dynamixel::ServoModel;
use dynamixel::control_table::{self as ct, Field};
use dynamixel::master::{BusError, MasterConfig, ReplyFault};
use host::bus::serial::{SerialMaster, block_on, open_master};
use std::path::PathBuf;

/// Talk to Dynamixel servos through a USB serial adapter (U2D2) or `dbot sim-bus`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    op: Op,
    /// Serial port of the adapter (e.g. /dev/ttyUSB0, or the link of `dbot sim-bus`)
    #[arg(long, global = true, default_value = "/dev/ttyUSB0")]
    port: PathBuf,
    /// Line rate in bit/s (factory default of the servos: 57600)
    #[arg(long, global = true, default_value_t = 57_600)]
    baud: u32,
    /// Time allowed per reply beyond its wire time, in microseconds (USB adapters add latency)
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
        #[arg(long)]
        id: u8,
        #[arg(long, conflicts_with = "addr")]
        field: Option<String>,
        #[arg(long, requires = "len")]
        addr: Option<u16>,
        #[arg(long)]
        len: Option<u16>,
        /// Value to write (signed values are written as two's complement)
        #[arg(long, allow_negative_numbers = true)]
        value: i64,
    },
    /// Torque off, then set Return Delay Time, ID and baud (in that order) and check the servo answers
    Setup {
        #[arg(long)]
        id: u8,
        /// New ID (0..=252)
        #[arg(long)]
        new_id: Option<u8>,
        /// New line rate in bit/s (57600, 115200, 1000000, 2000000, 3000000, 4000000, 4500000, 9600)
        #[arg(long)]
        new_baud: Option<u32>,
        /// New Return Delay Time in microseconds (0..=508, even)
        #[arg(long)]
        return_delay_us: Option<u32>,
    },
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let port = self.port.to_string_lossy().into_owned();
        let mut m = open_master(&port, self.baud, self.reply_slack_us)
            .with_context(|| format!("cannot open the bus on {port}"))?;
        match self.op {
            Op::Scan { max_id } => scan(&mut m, max_id, &port, self.baud),
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

fn scan(m: &mut SerialMaster, max_id: u8, port: &str, baud: u32) -> anyhow::Result<()> {
    let bar = indicatif::ProgressBar::new(max_id as u64 + 1)
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
    println!("{found} servo(s) found on {port} at {baud} bit/s");
    Ok(())
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
