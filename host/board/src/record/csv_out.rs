//! The tidy telemetry CSV, written row by row and flushed after every bus cycle.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use protocol::units::angle_to_rad;
use protocol::{RunState, Telemetry};

use super::joints::JointMeta;

/// Column names of the CSV, in order.
pub const CSV_HEADER: [&str; 20] = [
    "time_s",
    "cycle",
    "step",
    "slice",
    "joint",
    "planned_rad",
    "commanded_rad",
    "present_rad",
    "velocity_rad_s",
    "load_raw",
    "torque_estimate_nm",
    "modelled_torque_nm",
    "servo_error",
    "flags",
    "bus_cycle_us",
    "platform_goal_ticks",
    "platform_present_ticks",
    "run_state",
    "temperature_c",
    "input_voltage_v",
];

/// Columns of the telemetry CSV written before the platform's (trials of the first format
/// version without them are read with the platform unknown).
pub const CSV_HEADER_BEFORE_PLATFORM: usize = 15;

/// Columns of the telemetry CSV written before the run state's (trials without it are read with
/// the state unknown).
pub const CSV_HEADER_BEFORE_RUN_STATE: usize = 17;
/// Columns of the telemetry CSV written before the servos' heat and supply (protocol version 8
/// has both; a CSV with the run state and without them is read with temperature and voltage
/// unknown).
pub const CSV_HEADER_BEFORE_HEALTH: usize = 18;

/// One row: one joint in one bus cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Seconds since the first record of the recording (board clock).
    pub time_s: f64,
    pub cycle: u32,
    pub step: u32,
    pub slice: u16,
    pub joint: usize,
    /// Planned angle, interpolated like the goal: the commanded goal minus the torque bias
    /// (modelled torque / stiffness) where both are known, else the table's angle at the slice.
    pub planned_rad: Option<f64>,
    /// Goal sent (planned angle plus the torque bias, clamped).
    pub commanded_rad: f64,
    pub present_rad: f64,
    pub velocity_rad_s: f64,
    pub load_raw: i16,
    /// Joint torque estimated from the load register (ESTIMATE).
    pub torque_estimate_nm: Option<f64>,
    /// Modelled torque of the plan at this slice.
    pub modelled_nm: Option<f64>,
    pub error: u8,
    pub flags: u8,
    pub bus_cycle_us: u32,
    /// The perturbation platform servo's goal this cycle, ticks (`None`: no platform set up).
    pub platform_goal_ticks: Option<u16>,
    /// The platform servo's present position, ticks (`None`: no platform set up).
    pub platform_present_ticks: Option<u16>,
    /// The board's run state in this cycle (`Walking`, ..., `Fault`); `None` in a CSV written
    /// before the column.
    pub state: Option<RunState>,
    /// The servo's last Present Temperature, degC (`None`: not read yet; the board reads one
    /// servo per bus cycle in turn, so a value can be a round of the chain old).
    pub temperature_c: Option<u8>,
    /// The servo's last Present Input Voltage, V (`None`: not read yet).
    pub input_voltage_v: Option<f64>,
}

/// What the columns of telemetry.csv mean: written as README.md beside it.
pub const TELEMETRY_README: &str = include_str!("telemetry_readme.md");

/// Writes telemetry to a CSV as it arrives and keeps the rows for the plots.
#[derive(Debug)]
pub struct Recorder {
    out: BufWriter<File>,
    joints: Vec<JointMeta>,
    t0_us: Option<u64>,
    rows: Vec<Row>,
    /// Records pushed and the latest one's time since the first, s: counted per record, not
    /// per row, so a board reporting no joints still ends a timed recording (issue #30).
    records: usize,
    latest_s: f64,
}

impl Recorder {
    /// Creates `path` and writes the header.
    pub fn create(path: &Path, joints: Vec<JointMeta>) -> std::io::Result<Self> {
        let mut out = BufWriter::new(File::create(path)?);
        writeln!(out, "{}", CSV_HEADER.join(","))?;
        out.flush()?;
        Ok(Self {
            out,
            joints,
            t0_us: None,
            rows: Vec::new(),
            records: 0,
            latest_s: 0.0,
        })
    }

    pub fn joints(&self) -> &[JointMeta] {
        &self.joints
    }

    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Bus cycles recorded.
    pub fn cycles(&self) -> usize {
        self.records
    }

    /// Seconds between the first and the latest record.
    pub fn duration_s(&self) -> f64 {
        self.latest_s
    }

    /// Appends one record (one row per joint) and flushes it to the file.
    pub fn push(&mut self, t: &Telemetry) -> std::io::Result<()> {
        let t0 = *self.t0_us.get_or_insert(t.time_us);
        let time_s = t.time_us.saturating_sub(t0) as f64 * 1e-6;
        self.records += 1;
        self.latest_s = time_s;
        for (j, f) in t.joints.iter().enumerate() {
            let meta = self.joints.get(j);
            let health = t.health.get(j).filter(|h| h.is_read());
            let commanded_rad = angle_to_rad(f.commanded);
            let modelled_nm = meta.and_then(|m| m.modelled_nm.get(usize::from(t.slice)).copied());
            // With torque off the goal is not driven (the firmware reports whatever it holds), so it
            // says nothing about the plan: fall back to the table's angle at the slice.
            let driven = f.flags & protocol::feedback_flags::TORQUE_OFF == 0;
            // Stiffness 0 switches the board's bias off: the goal is the planned angle.
            let planned_rad = match (meta.and_then(|m| m.stiffness_nm_per_rad), modelled_nm) {
                (Some(k), _) if k == 0.0 && driven => Some(commanded_rad),
                (Some(k), Some(tau)) if k > 0.0 && driven => Some(commanded_rad - tau / k),
                _ => meta.and_then(|m| m.planned_rad.get(usize::from(t.slice)).copied()),
            };
            let row = Row {
                time_s,
                cycle: t.cycle,
                step: t.step,
                slice: t.slice,
                joint: j,
                planned_rad,
                commanded_rad,
                present_rad: angle_to_rad(f.present),
                velocity_rad_s: f64::from(f.velocity) / protocol::units::VELOCITY_PER_RAD_S,
                load_raw: f.load,
                torque_estimate_nm: meta.and_then(|m| m.torque_estimate_nm(f.load)),
                modelled_nm,
                error: f.error,
                flags: f.flags,
                bus_cycle_us: t.bus.cycle_us,
                platform_goal_ticks: t.platform.map(|p| p.goal),
                platform_present_ticks: t.platform.map(|p| p.present),
                state: Some(t.state),
                temperature_c: health.map(|h| h.temperature_c),
                input_voltage_v: health.map(|h| f64::from(h.voltage_dv) / 10.0),
            };
            let name = meta.map_or_else(|| format!("J{j}"), |m| m.name.clone());
            let ticks = |v: Option<u16>| v.map_or(String::new(), |x| x.to_string());
            let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.4}"));
            writeln!(
                self.out,
                "{:.6},{},{},{},{},{},{},{:.4},{:.3},{},{},{},{},{},{},{},{},{},{},{}",
                row.time_s,
                row.cycle,
                row.step,
                row.slice,
                name,
                opt(row.planned_rad),
                // Torque off: the goal register holds no command, the cell stays empty.
                opt(driven.then_some(row.commanded_rad)),
                row.present_rad,
                row.velocity_rad_s,
                row.load_raw,
                opt(row.torque_estimate_nm),
                opt(row.modelled_nm),
                row.error,
                row.flags,
                row.bus_cycle_us,
                ticks(row.platform_goal_ticks),
                ticks(row.platform_present_ticks),
                t.state.key(),
                row.temperature_c.map_or(String::new(), |t| t.to_string()),
                row.input_voltage_v
                    .map_or(String::new(), |v| format!("{v:.1}"))
            )?;
            self.rows.push(row);
        }
        self.out.flush()
    }
}
