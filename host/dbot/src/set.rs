//! `dbot set`: run-time settings of the board: servo stiffness (torque bias), bus cycle rate and
//! baud, telemetry rate, torque, fault clearing. Flags override the setup file's values.

use anyhow::{Context, bail};
use board::link::LinkError;
use protocol::{ProtocolError, RunState, ServoSelect};

use crate::args::board::BoardArgs;
use crate::common::words::state_name;

/// Change run-time settings of the board (only while it is not walking, for the bus ones).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot set --stiffness 8.4       # N m/rad, all joints
  dbot set --rate 200 --baud 2000000   # Hz, bit/s; only while not walking
  dbot set --from-config          # stiffness, rate, baud of the setup file")]
pub struct Args {
    /// Servo stiffness for the torque bias, N m/rad (all joints, or --joint).
    #[arg(long)]
    pub stiffness: Option<f64>,
    /// Joint index for --stiffness (default: all joints).
    #[arg(long)]
    pub joint: Option<u8>,
    /// Bus cycle rate, Hz (50 to 1000).
    #[arg(long)]
    pub rate: Option<u16>,
    /// Dynamixel bus baud rate, bit/s.
    #[arg(long)]
    pub baud: Option<u32>,
    /// Telemetry every this many bus cycles (0 = off), outside streaming; a stream sets its own
    /// proprioception rate (`feedback_every`).
    #[arg(long)]
    pub telemetry_every: Option<u16>,
    /// Torque on (hold the present posture) or off.
    #[arg(long)]
    pub torque: Option<OnOff>,
    /// Leave the fault state (after an emergency stop or a servo fault).
    #[arg(long)]
    pub clear_fault: bool,
    /// Apply the setup file's stiffness, rate and baud (flags still override).
    #[arg(long)]
    pub from_config: bool,
    #[command(flatten)]
    pub board: BoardArgs,
}

/// On or off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        // Everything is checked before the board is touched, so a bad flag changes nothing.
        let setup = self.board.setup()?;
        let (k, rate, baud) = if self.from_config {
            (
                self.stiffness.or(setup.stiffness),
                self.rate.or(setup.rate),
                self.baud.or(setup.baud),
            )
        } else {
            (self.stiffness, self.rate, self.baud)
        };
        if let Some(k) = k
            && !(k.is_finite()
                && k > 0.0
                && k * protocol::units::STIFFNESS_PER_NM_RAD < f64::from(u32::MAX))
        {
            bail!("--stiffness {k}: must be a positive number of N m/rad (at most 4294)");
        }
        let nothing = !self.clear_fault
            && k.is_none()
            && rate.is_none()
            && baud.is_none()
            && self.telemetry_every.is_none()
            && self.torque.is_none();
        if nothing {
            bail!(
                "nothing to set: give --stiffness, --rate, --baud, --telemetry-every, --torque or --clear-fault"
            );
        }
        let mut s = self.board.connect()?;
        let mut did = Vec::new();
        if self.clear_fault {
            // A board that is not in a fault (the virtual robot boots afresh at every command)
            // has nothing to clear: say so instead of failing, so `estop`'s advice always works.
            match s.board.clear_fault() {
                Ok(()) => did.push("fault cleared".to_owned()),
                Err(LinkError::Device {
                    error: ProtocolError::WrongState { state },
                    ..
                }) if state != RunState::Fault => {
                    did.push(format!(
                        "no fault to clear (the board is in state {})",
                        state_name(state)
                    ));
                }
                Err(e) => return Err(anyhow::Error::new(e).context("clearing the fault")),
            }
        }
        if let Some(k) = k {
            let units = (k * protocol::units::STIFFNESS_PER_NM_RAD).round() as u32;
            let joints = s.board.settings()?.joints.len() as u8;
            let list: Vec<u8> = match self.joint {
                Some(j) => vec![j],
                None => (0..joints).collect(),
            };
            if list.is_empty() {
                bail!("the board has no joint map yet (upload and play a gait first)");
            }
            for j in list {
                s.board
                    .set_stiffness(j, units)
                    .with_context(|| format!("stiffness of joint {j}"))?;
            }
            did.push(format!("stiffness {k} N m/rad"));
        }
        if rate.is_some() || baud.is_some() {
            let cur = s.board.settings()?;
            let (b, r) = (baud.unwrap_or(cur.baud), rate.unwrap_or(cur.cycle_hz));
            s.board.set_bus(b, r).context("bus settings")?;
            did.push(format!("bus {b} bit/s at {r} Hz"));
        }
        if let Some(e) = self.telemetry_every {
            s.board.set_telemetry(e)?;
            did.push(format!("telemetry every {e} cycles"));
        }
        if let Some(t) = self.torque {
            s.board.set_torque(ServoSelect::All, t == OnOff::On)?;
            did.push(match t {
                OnOff::On => "torque on".to_owned(),
                OnOff::Off => "torque off".to_owned(),
            });
        }
        let changed =
            k.is_some() || rate.is_some() || baud.is_some() || self.telemetry_every.is_some();
        if let Some(store) = s.store.clone().filter(|_| changed) {
            crate::args::virtual_settings::save(&mut s.board, &store)?;
            did.push(format!(
                "kept in {} for later commands",
                crate::args::virtual_settings::settings_path(&store).display()
            ));
        }
        println!("{}", did.join(", "));
        s.close()
    }
}
