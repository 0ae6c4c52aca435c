//! trial.json: what a trial was, as a typed, versioned struct (the machine-readable twin of the
//! trial's README). Every field is written; optional ones are `null` when unknown.

use serde::{Deserialize, Serialize};

pub use crate::substrate::Substrate;

/// The trial format this build writes and reads. Raise it when a field or a file changes
/// meaning; [`super::read_trial`] refuses any other version, naming the file.
pub const TRIAL_FORMAT: u32 = 1;

/// The contents of trial.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrialMeta {
    /// [`TRIAL_FORMAT`] of the writer.
    pub format_version: u32,
    /// The trial's folder name (its start time, UTC, `YYYY-MM-DD HH_MM_SS`, maybe with a suffix).
    pub folder: String,
    /// How the recording ended.
    pub outcome: Outcome,
    /// The fault that stopped the robot when `outcome` is `faulted`; `None` otherwise (and in a
    /// trial written before this field).
    #[serde(default)]
    pub fault: Option<TrialFault>,
    /// Start time, ISO 8601 UTC.
    pub started: String,
    /// The `dbot` (or Python package) version that wrote the trial.
    pub host_version: String,
    /// The full command line (program name first).
    pub command_line: Vec<String>,
    /// The port of the board (`/dev/ttyACM0`, `virtual:...`, `physics`).
    pub port: String,
    pub firmware: FirmwareMeta,
    pub settings: BoardSettings,
    /// The gait played, when this command started it or a step table was given.
    pub gait: Option<GaitMeta>,
    /// The plan the gait's step table came from, when known.
    pub plan: Option<PlanMeta>,
    /// `forward` or `backward`; `None` when this command did not start the walk.
    pub direction: Option<protocol::Direction>,
    /// Step period / planned step period; `None` when this command did not start the walk.
    pub period_scale: Option<f64>,
    /// Whole steps asked for; `None`: until stopped (or not started by this command).
    pub steps: Option<u32>,
    pub substrate: Substrate,
    /// Whether strain gauges were recorded beside the servos (their data would be `strain.csv`).
    pub strain: bool,
    /// The perturbation platform's move, if one was made.
    pub perturbation: Option<Perturbation>,
    /// Free text from `--notes`.
    pub notes: String,
    /// The recording's joints, in the order of their rows in telemetry.csv.
    pub joints: Vec<String>,
    /// Bus cycles recorded and their span, s of board time.
    pub cycles: usize,
    pub duration_s: f64,
    /// Telemetry records missing (skipped cycle numbers): lost ones, and the cycles that make
    /// none (torque switched, servos rebooted, an error read, the platform checked).
    pub missing_records: u64,
    /// Records dropped on the board or the host during the recording (`board::record::gaps`);
    /// `None`: not known (the link failed first, or a trial written before this field).
    #[serde(default)]
    pub lost_records: Option<u64>,
}

impl TrialMeta {
    /// trial.json's text (what [`super::TrialFolder::publish`] writes).
    pub fn to_json(&self) -> String {
        // Every field is a string, number, bool, list or map with string keys: this cannot fail.
        serde_json::to_string_pretty(self).expect("trial metadata serialises")
    }
}

/// How a trial's recording ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// As asked (its time passed, or the walk ended).
    Complete,
    /// Ctrl-C (or SIGTERM): the rows up to then.
    Interrupted,
    /// The link failed or the board fell silent: the rows received before.
    Failed,
    /// The board stopped the robot on a fault (servo missing, stuck, overloaded, a setpoint
    /// timeout, an emergency stop): the rows up to it ([`TrialMeta::fault`] says which).
    Faulted,
}

/// The fault that ended a trial.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TrialFault {
    /// The fault's kind as the board names it (`ServoStuck`, `ServoMissing`, `ServoError`,
    /// `SetpointTimeout`, `EmergencyStop`, `Watchdog`).
    pub kind: String,
    /// The board's words for it (`ServoStuck on joint 2: servo stuck: ...`).
    pub reason: String,
    /// The joint it concerns (index in the board's joint map), if any.
    pub joint: Option<u8>,
    /// That joint's name in the recording (e.g. `RM_FTi`), when known.
    pub joint_name: Option<String>,
    /// The bus cycle of the first telemetry record in the fault state (the board stopped the
    /// robot between the record before and this one); `None` when no record showed it.
    pub cycle: Option<u32>,
}

impl Outcome {
    /// The word a trial folder of this outcome carries after its start time (none when complete).
    pub fn suffix(self) -> Option<&'static str> {
        match self {
            Outcome::Complete => None,
            Outcome::Interrupted => Some("interrupted"),
            Outcome::Failed => Some("failed"),
            Outcome::Faulted => Some("faulted"),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Outcome::Complete => "complete",
            Outcome::Interrupted => "interrupted",
            Outcome::Failed => "failed",
            Outcome::Faulted => "faulted",
        }
    }
}

/// The firmware that ran the trial.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FirmwareMeta {
    /// `major.minor.patch`.
    pub version: String,
    pub protocol_version: u16,
    pub table_format_version: u16,
    /// The first 8 hex digits of the git commit the firmware was built from; 0: unknown.
    pub build_id: u32,
}

/// The board's settings at the start of the trial.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct BoardSettings {
    /// Bus baud rate, bit/s.
    pub bus_baud: u32,
    /// Bus cycle rate, Hz.
    pub cycle_hz: u16,
    /// Telemetry every this many bus cycles.
    pub telemetry_every: u16,
    /// Per joint of the board's joint map.
    pub joints: Vec<JointSetting>,
}

/// One joint's run-time settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct JointSetting {
    /// Stiffness of the torque bias (and the servo's P gain), mN m/rad.
    pub stiffness_mnm_per_rad: u32,
    /// Limits, 1e-4 rad.
    pub min_1e4_rad: i16,
    pub max_1e4_rad: i16,
    pub torque_enabled: bool,
}

/// The gait played.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaitMeta {
    /// The slot it was played from (`None`: only a step table was given).
    pub slot: Option<u8>,
    pub name: String,
    /// CRC-32 of the step table (the board's stored CRC).
    pub crc: u32,
    pub joints: u8,
    pub slices: u16,
    /// Planned step period, s.
    pub step_period_s: f64,
    /// Fraction of the step a leg is in stance.
    pub duty: f64,
}

/// The plan a step table was built from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanMeta {
    /// The plan directory as given.
    pub dir: String,
    /// The model's name and where the planner loaded it from.
    pub model: String,
    pub model_source: String,
    /// CRC-32 of the directory's model.toml (the planned model), hex.
    pub model_crc: String,
    /// The stepping parameters (plan.json's `parameters`).
    pub parameters: serde_json::Value,
    pub period_s: f64,
}

/// A move of the perturbation platform under one leg.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Perturbation {
    /// `LF`, `LM`, `LH`, `RF`, `RM` or `RH`.
    pub leg: String,
    /// The step at whose start the platform moved.
    pub step: u32,
    /// Platform servo goals, ticks.
    pub rest: u16,
    pub moved_to: u16,
    /// The platform servo's Dynamixel ID; `None` in a trial written before this field.
    #[serde(default)]
    pub platform_id: Option<u8>,
}
