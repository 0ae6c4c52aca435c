//! `dbot sim-bus`: serves a virtual chain of Dynamixel servos on a pseudo-terminal until
//! interrupted, printing every request it answers; with `--physics`, the physics robot's board
//! instead (`lab::physics_serve`), and with `--strain-link` its body's gauges on a virtual strain
//! board beside it.

use anyhow::Context as _;
use board::bus::pty::{PtyServer, Served};
use dynamixel::ServoModel;
use dynamixel::instruction::Instruction;
use dynamixel::sim::VirtualChain;
use lab::physics_serve::{PhysicsServer, StrainLink};
use nix::sys::signal::{SaFlags, SigAction, SigHandler, SigSet, Signal, sigaction};
use std::io::Write as _;

use crate::common::baud::{FACTORY_BAUD, mx_rate};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: nix::libc::c_int) {
    STOP.store(true, Ordering::Relaxed);
}

/// Serve virtual Dynamixel servos on a pseudo-terminal, so that any Protocol 2.0 client can talk to them.
///
/// Servos have IDs 1..=N, each the model the robot's model file (drosophibot2.toml) puts at that
/// ID (MX-64(2.0) on the CTr joints), MX-28(2.0) past its 22. Replies are paced at wall-clock
/// wire time.
///
/// With --physics the pseudo-terminal is instead the physics robot's board (the board's link, as
/// on its USB port, simulated time paced to the wall clock), and --strain-link serves the same
/// body's simulated gauges on a virtual strain board (counts = 300 + gain x microstrain, rounded,
/// saturating at 0 and 1023; each line reads the latest sample, taken every 24 ms of simulated
/// time).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot sim-bus --link /tmp/dxl                       # 22 servos at 57600 bit/s, as from the factory
  dbot dxl scan -p /tmp/dxl --max-id 30              # (in another shell) finds them
  dbot sim-bus --link /tmp/dxl --baud 1000000 --return-delay-us 0 --quiet   # as on the robot's bus
  dbot sim-bus --physics physics --link /tmp/board --strain-link /tmp/strain
  dbot record --out trials --port /tmp/board --table walk.dbgt --play 0 --steps 3 --strain /tmp/strain")]
pub struct Args {
    /// Serve the physics robot's board on --link instead of a servo chain: `physics` (flat) or
    /// `physics:SCENE[+SUBSTRATE]`, as --port takes them
    #[arg(long, value_name = "PORT")]
    physics: Option<String>,
    /// With --physics: serve the body's simulated gauges on a virtual strain board linked here
    #[arg(long, requires = "physics", value_name = "PATH")]
    strain_link: Option<PathBuf>,
    /// With --strain-link: counts per microstrain (an invented default: the lab's gain is not
    /// published)
    #[arg(long, requires = "strain_link", default_value_t = board::strain::virtual_board::DEFAULT_GAIN)]
    strain_gain: f64,
    /// Number of servos (IDs 1..=N)
    #[arg(long, default_value_t = 22, value_parser = clap::value_parser!(u8).range(1..=252))]
    servos: u8,
    /// Line rate the servos are set to, bit/s (9600, 57600, 115200, 1000000, 2000000, 3000000,
    /// 4000000, 4500000). Default: the servos' factory rate, also the default of `dbot dxl`.
    #[arg(long, default_value_t = FACTORY_BAUD, value_parser = mx_rate)]
    baud: u32,
    /// Path of the symlink to the pseudo-terminal: what clients open as their serial port
    #[arg(long)]
    link: PathBuf,
    /// Return Delay Time of every servo, µs (0..=508, even; factory default 500)
    #[arg(long, default_value_t = 500, value_parser = parse_return_delay_us)]
    return_delay_us: u16,
    /// The same in register units of 2 µs (the old flag; kept so scripts keep working)
    #[arg(long, hide = true, conflicts_with = "return_delay_us", value_parser = clap::value_parser!(u8))]
    return_delay: Option<u8>,
    /// Print only the start-up line, not every request
    #[arg(long)]
    quiet: bool,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if let Some(spec) = &self.physics {
            return self.run_physics(spec);
        }
        // IDs 1..=n with the servo the robot's model file puts there (MX-28(2.0) past its 22).
        let robot = board::robot::robot_servos();
        let servos: Vec<(u8, ServoModel)> = (1..=self.servos)
            .map(|id| {
                let on_robot = robot.iter().find(|s| s.0 == id);
                (id, on_robot.map_or(ServoModel::Mx28, |s| s.1))
            })
            .collect();
        let mut chain = VirtualChain::new(&servos, self.baud).with_context(|| {
            format!(
                "cannot build a chain of {} servos at {} bit/s",
                self.servos, self.baud
            )
        })?;
        let rdt = self
            .return_delay
            .unwrap_or((self.return_delay_us / 2) as u8);
        chain.set_return_delay_all(rdt);
        let mut server = PtyServer::open(chain, self.baud, &self.link)
            .with_context(|| format!("cannot serve the virtual bus at {}", self.link.display()))?;
        install_stop_handler()?;
        let mx64: Vec<u8> = servos
            .iter()
            .filter(|s| s.1 == ServoModel::Mx64)
            .map(|s| s.0)
            .collect();
        println!(
            "serving {} virtual servos (IDs 1..={}, {} on {}, {} elsewhere) at {} bit/s, return delay {} us, on {} linked at {}; Ctrl-C stops",
            self.servos,
            self.servos,
            ServoModel::Mx64.name(),
            id_list(&mx64),
            ServoModel::Mx28.name(),
            self.baud,
            u32::from(rdt) * 2,
            server.slave_path(),
            self.link.display()
        );
        std::io::stdout().flush().ok();
        let quiet = self.quiet;
        server
            .serve(&STOP, |s| {
                if !quiet {
                    println!("{}", describe(s));
                }
            })
            .context("serving the virtual bus failed")?;
        println!("stopped");
        Ok(())
    }
}

impl Args {
    /// `--physics`: the physics robot's board on `--link`, its gauges on `--strain-link`.
    fn run_physics(&self, spec: &str) -> anyhow::Result<()> {
        let strain = self.strain_link.as_ref().map(|link| StrainLink {
            link: link.clone(),
            gain: self.strain_gain,
        });
        let server = PhysicsServer::open(spec, &self.link, strain)
            .with_context(|| format!("--physics {spec}"))?;
        install_stop_handler()?;
        println!("{}; Ctrl-C stops", server.describe());
        std::io::stdout().flush().ok();
        let served = server.serve(&STOP)?;
        if let Some(e) = served.strain_error {
            eprintln!("{e}");
        }
        println!("stopped");
        Ok(())
    }
}

/// Ctrl-C and SIGTERM set [`STOP`].
fn install_stop_handler() -> anyhow::Result<()> {
    let handler = SigAction::new(
        SigHandler::Handler(on_signal),
        SaFlags::empty(),
        SigSet::empty(),
    );
    for sig in [Signal::SIGINT, Signal::SIGTERM] {
        // SAFETY: the handler only stores to an atomic, which is async-signal-safe.
        unsafe { sigaction(sig, &handler) }.context("cannot install the interrupt handler")?;
    }
    Ok(())
}

/// `--return-delay-us`: even and at most 508 µs (the register holds units of 2 µs, up to 254).
fn parse_return_delay_us(s: &str) -> Result<u16, String> {
    let us: u16 = s
        .parse()
        .map_err(|_| format!("`{s}` is not a whole number of µs"))?;
    if us > 508 || !us.is_multiple_of(2) {
        return Err(format!(
            "{us} µs: must be even and at most 508 (register unit 2 µs, max 254)"
        ));
    }
    Ok(us)
}

fn describe(s: &Served) -> String {
    let name = Instruction::from_code(s.instruction).map_or_else(
        || format!("0x{:02X}", s.instruction),
        |i| i.name().to_string(),
    );
    let target = if s.id == dynamixel::instruction::BROADCAST_ID {
        "broadcast".to_string()
    } else {
        format!("ID {}", s.id)
    };
    let mut line = format!(
        "{:10.4} s  {name:<10} {target:<9} {:>4} B  replied: {}",
        s.at_s,
        s.request_len,
        id_list(&s.replied)
    );
    if !s.silent.is_empty() {
        line.push_str(&format!("  silent: {}", id_list(&s.silent)));
    }
    line
}

/// Servo IDs as the log shows them: "ID 1, 2, 3", or "none".
fn id_list(ids: &[u8]) -> String {
    if ids.is_empty() {
        return "none".to_owned();
    }
    let ids: Vec<String> = ids.iter().map(u8::to_string).collect();
    format!("ID {}", ids.join(", "))
}

#[cfg(test)]
mod tests {
    use super::id_list;

    #[test]
    fn servo_ids_read_as_a_list_not_debug_text() {
        assert_eq!(id_list(&[]), "none");
        assert_eq!(id_list(&[3]), "ID 3");
        assert_eq!(id_list(&[1, 2, 14]), "ID 1, 2, 14");
    }
}
