//! A trial as the identification reads it: per bus cycle the goal sent to each joint and what
//! its servo reported (present position and velocity, the Present Load register), with the
//! joints named by the model, and the strain board's record beside it when there is one
//! ([`StrainTrace`]). Built from a trial folder ([`Recording::of_trial`]) or by the
//! stand-in robot ([`super::stand_in`]).

use board::trial::Trial;
use planner::model::Model;

use crate::error::Result;
use crate::{bail, error::Context};

/// `flags` bits of a telemetry row that make it no measurement: 1 no reply, 8 torque off
/// (telemetry.csv's README).
const NOT_MEASURED: u8 = 1 | 8;

/// The name prefix of the suspended excitation's tables (`planner::excitation::suspended`):
/// a trial that played one hung with its feet in the air.
pub const SUSPENDED_PREFIX: &str = "sus-";

/// One joint's record over a trial, one value per bus cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTrace {
    pub name: String,
    /// The joint's index in the model.
    pub joint: usize,
    /// Goal sent, rad.
    pub goal: Vec<f64>,
    /// Present position, rad, and velocity, rad/s.
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    /// Present Load register, counts (servo direction).
    pub load_raw: Vec<i16>,
}

/// A trial's goals and readings.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The trial's name (its folder, or the stand-in's table).
    pub name: String,
    /// Whether the robot hung with its feet in the air (body fixed) rather than stood.
    pub suspended: bool,
    /// Time of each bus cycle, s from the first.
    pub t: Vec<f64>,
    pub joints: Vec<JointTrace>,
    /// The strain board's record beside it, when the trial recorded strain.
    pub strain: Option<StrainTrace>,
}

/// A trial's strain record (`strain.csv` and `strain_baseline.csv`), gauges in the strain
/// board's column order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrainTrace {
    /// The gauges' names (`LF_troch_axial`, ...).
    pub names: Vec<String>,
    /// Time of each sample on the telemetry's clock, s (samples without one are left out).
    pub t: Vec<f64>,
    /// `counts[sample][gauge]`.
    pub counts: Vec<Vec<f64>>,
    /// Zero-strain counts per gauge.
    pub baseline: Vec<f64>,
    /// Whether the baseline is the trial's first sample (its strain, not zero, then) rather
    /// than the mean of samples taken with the robot held unloaded.
    pub baseline_first_sample: bool,
}

impl StrainTrace {
    /// The strain record of the trial folder `dir` (None: it recorded none).
    pub fn read(dir: &std::path::Path) -> Result<Option<Self>> {
        use board::strain::recorder::{BASELINE_CSV, STRAIN_CSV};
        let csv = dir.join(STRAIN_CSV);
        if !csv.exists() {
            return Ok(None);
        }
        let aligned = board::strain::beside::read_aligned(&csv)
            .map_err(|e| crate::LabError::invalid(e.to_string()))?;
        let path = dir.join(BASELINE_CSV);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {} (written beside strain.csv)", path.display()))?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let row: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let names = board::strain::channels::names();
        let mut baseline = Vec::with_capacity(names.len());
        for name in &names {
            let v = header
                .iter()
                .position(|h| h.trim() == name)
                .and_then(|i| row.get(i))
                .and_then(|v| v.trim().parse::<f64>().ok());
            let Some(v) = v else {
                bail!("{}: no baseline count for {name}", path.display());
            };
            baseline.push(v);
        }
        let method = header
            .iter()
            .position(|h| h.trim() == "method")
            .and_then(|i| row.get(i))
            .map_or("", |m| m.trim());
        let mut out = Self {
            names,
            baseline,
            baseline_first_sample: method
                != board::strain::baseline::BaselineMethod::MeanOfUnloaded.name(),
            ..Self::default()
        };
        for (t, c) in aligned.time_s.iter().zip(&aligned.counts) {
            if let Some(t) = t {
                out.t.push(*t);
                out.counts.push(c.to_vec());
            }
        }
        Ok(Some(out))
    }

    /// Index of the bus cycle of `t` (times in order) nearest in time to each sample.
    pub fn nearest_cycles(&self, t: &[f64]) -> Vec<usize> {
        self.t
            .iter()
            .map(|&s| {
                let i = t.partition_point(|&c| c < s);
                match (i.checked_sub(1), t.get(i)) {
                    (Some(a), Some(&b)) if s - t[a] <= b - s => a,
                    (_, Some(_)) => i,
                    (Some(a), None) => a,
                    (None, None) => 0,
                }
            })
            .collect()
    }
}

impl Recording {
    /// Number of bus cycles.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether no cycle was recorded.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// `trial` read against `model`: every cycle in which each joint answered with its torque on,
    /// suspended when the gait played is a suspended excitation table (its name starts `sus-`).
    pub fn of_trial(trial: &Trial, model: &Model) -> Result<Self> {
        let place = trial.path.display().to_string();
        let mut joints = Vec::new();
        for name in &trial.meta.joints {
            let Some(j) = model.joint_index(name) else {
                bail!(
                    "trial {place}: joint `{name}` is not a joint of the model {}",
                    model.name
                );
            };
            if model.servo_params(j).is_none() {
                bail!(
                    "trial {place}: joint `{name}` has no servo in the model {}",
                    model.name
                );
            }
            joints.push(JointTrace {
                name: name.clone(),
                joint: j,
                goal: Vec::new(),
                q: Vec::new(),
                qd: Vec::new(),
                load_raw: Vec::new(),
            });
        }
        let n = joints.len();
        let mut t = Vec::new();
        let mut rows = trial.rows.iter().peekable();
        while let Some(first) = rows.next() {
            let cycle = first.cycle;
            let mut group = vec![first];
            while let Some(r) = rows.next_if(|r| r.cycle == cycle) {
                group.push(r);
            }
            if group.len() != n || group.iter().any(|r| r.flags & NOT_MEASURED != 0) {
                continue;
            }
            for r in &group {
                let Some(jt) = joints.get_mut(r.joint) else {
                    bail!("trial {place}: a row names joint {} of {n}", r.joint);
                };
                jt.goal.push(r.commanded_rad);
                jt.q.push(r.present_rad);
                jt.qd.push(r.velocity_rad_s);
                jt.load_raw.push(r.load_raw);
            }
            t.push(first.time_s);
        }
        if t.len() < 10 || joints.iter().any(|j| j.q.len() != t.len()) {
            bail!(
                "trial {place}: {} complete bus cycles (every joint answering, torque on); at least 10 are needed",
                t.len()
            );
        }
        let suspended = trial
            .meta
            .gait
            .as_ref()
            .is_some_and(|g| g.name.starts_with(SUSPENDED_PREFIX));
        Ok(Self {
            name: trial.meta.folder.clone(),
            suspended,
            t,
            joints,
            strain: StrainTrace::read(&trial.path)?,
        })
    }

    /// Reads the trial folder `dir` against `model`.
    pub fn read(dir: &std::path::Path, model: &Model) -> Result<Self> {
        let trial = board::trial::read_trial(dir)
            .with_context(|| format!("reading the trial {}", dir.display()))?;
        Self::of_trial(&trial, model)
    }
}
