//! `dbot set`: run-time settings of the board: servo stiffness (torque bias), bus cycle rate and
//! baud, telemetry rate, the servos' heat and supply limits, torque, fault clearing. Flags override the setup file's values.

use anyhow::bail;
use board::link::LinkError;
use protocol::{ProtocolError, RunState, ServoSelect};

use crate::args::board::BoardArgs;

/// Change run-time settings of the board (only while it is not walking, for the bus ones).
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot set --stiffness 8.4       # N m/rad, all joints
  dbot set --rate 150                  # Hz; only while not walking
  dbot set --baud 2000000 --rate 200   # bit/s: set the servos first (dbot dxl setup --new-baud)
  dbot set --from-config          # stiffness, rate, baud of the setup file
  dbot set --stop-temp 72 --warn-temp 65   # degC: warn, and stop a walk at the end of its step")]
pub struct Args {
    /// Servo stiffness, N m/rad (all joints, or --joint): written to the servos' Position P Gain
    /// and used by the torque bias; 0 switches the bias off and leaves the gain. 0.0173 to 235.7:
    /// what the P gain register (1 to 16383) holds on every servo model (MX-64: 0.0345 N m/rad
    /// per unit, MX-28: 0.0144; estimates), so the bias never divides by a stiffness the servo
    /// does not have.
    #[arg(long)]
    pub stiffness: Option<f64>,
    /// Joint index for --stiffness (default: all joints).
    #[arg(long)]
    pub joint: Option<u8>,
    /// Bus cycle rate, Hz (50 to 1000, and within what the wire carries at the baud: 160 Hz at
    /// 1 Mbit/s for 22 servos).
    #[arg(long)]
    pub rate: Option<u16>,
    /// Dynamixel bus baud rate, bit/s: one the MX servos support (9600, 57600, 115200, 1000000,
    /// 2000000, 3000000, 4000000, 4500000). The servos keep their own baud (EEPROM): set each
    /// first (`dbot dxl setup --new-baud B` through a U2D2); the board then checks every servo
    /// answers at B, else goes back to its old baud and refuses.
    #[arg(long)]
    pub baud: Option<u32>,
    /// Telemetry every this many bus cycles (0 = off), outside streaming; a stream sets its own
    /// proprioception rate (`feedback_every`).
    #[arg(long)]
    pub telemetry_every: Option<u16>,
    /// Warn when a servo's Present Temperature reaches this, degC (default 70).
    #[arg(long, value_name = "DEGC")]
    pub warn_temp: Option<f64>,
    /// Stop a walk at the end of its step when a servo's temperature reaches this, degC
    /// (default 75; below the servos' own 80 degC shutdown).
    #[arg(long, value_name = "DEGC")]
    pub stop_temp: Option<f64>,
    /// Warn when a servo's Present Input Voltage falls to this, V (default 10.5).
    #[arg(long, value_name = "V")]
    pub warn_low_volts: Option<f64>,
    /// Stop a walk at the end of its step when the input voltage falls to this, V (default 10.0;
    /// above the servos' own 9.5 V).
    #[arg(long, value_name = "V")]
    pub stop_low_volts: Option<f64>,
    /// Warn when the input voltage rises to this, V (default 14.8).
    #[arg(long, value_name = "V")]
    pub warn_high_volts: Option<f64>,
    /// Stop a walk at the end of its step when the input voltage rises to this, V (default 15.5;
    /// below the servos' own 16.0 V).
    #[arg(long, value_name = "V")]
    pub stop_high_volts: Option<f64>,
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
        // The limits are the hardware's (protocol::limits), the same the setup file and the
        // firmware check; the wire limit is checked for the robot's servos here and again with
        // the board's current baud or rate once connected.
        use protocol::limits::{CYCLE_HZ, LimitError, MX_BAUDS, ROBOT_SERVOS, check_bus};
        // The board's unit and what every servo's P gain register holds (`board::rules`).
        if let Some(k) = k {
            board::rules::stiffness::units(k)
                .map_err(|e| anyhow::anyhow!("--stiffness {k}: {e}"))?;
        }
        if let Some(b) = baud
            && !MX_BAUDS.contains(&b)
        {
            bail!("--baud {b}: {}", LimitError::Baud { baud: b });
        }
        if let Some(r) = rate
            && !CYCLE_HZ.contains(&r)
        {
            bail!("--rate {r}: {}", LimitError::CycleRate { hz: r });
        }
        if let (Some(b), Some(r)) = (baud, rate) {
            check_bus(b, r, ROBOT_SERVOS)
                .map_err(|e| anyhow::anyhow!("--rate {r} --baud {b}: {e}"))?;
        }
        let health = board::health::HealthLimitArgs {
            warn_temperature_c: self.warn_temp,
            stop_temperature_c: self.stop_temp,
            warn_low_v: self.warn_low_volts,
            stop_low_v: self.stop_low_volts,
            warn_high_v: self.warn_high_volts,
            stop_high_v: self.stop_high_volts,
        };
        let nothing = health.is_empty()
            && !self.clear_fault
            && k.is_none()
            && rate.is_none()
            && baud.is_none()
            && self.telemetry_every.is_none()
            && self.torque.is_none();
        if nothing {
            bail!(
                "nothing to set: give --stiffness, --rate, --baud, --telemetry-every, a heat or supply limit (--warn-temp, --stop-temp, --warn-low-volts, ...), --torque or --clear-fault"
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
                        state.name()
                    ));
                }
                Err(e) => return Err(anyhow::Error::new(e).context("clearing the fault")),
            }
        }
        if let Some(k) = k {
            board::rules::stiffness::set_stiffness(&mut s.board, self.joint, k)?;
            did.push(if k == 0.0 {
                "stiffness 0: torque bias off (the servos keep their P gain)".to_owned()
            } else {
                format!("stiffness {k} N m/rad")
            });
        }
        if rate.is_some() || baud.is_some() {
            let cur = s.board.settings()?;
            let (b, r) = (baud.unwrap_or(cur.baud), rate.unwrap_or(cur.cycle_hz));
            check_bus(b, r, cur.joints.len().max(ROBOT_SERVOS)).map_err(|e| {
                anyhow::anyhow!("--baud/--rate (with the board's current bus): {e}")
            })?;
            // A baud change is verified (every servo answers at it) or undone and refused.
            board::rules::bus::set_bus(&mut s.board, b, r)?;
            did.push(format!("bus {b} bit/s at {r} Hz"));
        }
        if let Some(e) = self.telemetry_every {
            s.board.set_telemetry(e)?;
            did.push(format!("telemetry every {e} cycles"));
        }
        if !health.is_empty() {
            let cur = s.board.settings()?.health;
            let limits = board::health::health_limits(cur, &health)?;
            s.board.set_health_limits(limits)?;
            did.push(board::health::limits_line(&limits));
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
            board::saved_settings::save(&mut s.board, &store)?;
            did.push(format!(
                "kept in {} for later commands",
                board::saved_settings::settings_path(&store).display()
            ));
        }
        println!("{}", did.join(", "));
        s.close()
    }
}
