//! Replay: a recorded trial's goals played on the physics robot's body with a model's servo
//! dynamics ([`crate::identify::rollout`]), and per joint how well the replay follows the
//! recording: R^2 (`planner::analysis::fit::prediction_r2`) and RMS of the position and of the
//! load, the sim-to-real figure of merit (`dbot replay`, `dbot.replay`).
//!
//! The load is compared as the servo reads it: the recorded Present Load and the replayed
//! torque through the model's Present Load reading (its gain and offset, no noise), both turned
//! into N m by the register's nominal conversion (`dynamixel::units::load_to_torque_nm`, an
//! ESTIMATE of torque). Whether the model's reading was calibrated ([`Reading`]) is said with
//! every figure. When the trial recorded strain, the physics robot's simulated gauges are
//! replayed too ([`GaugeReplay`]): per gauge R^2 and RMS (microstrain) of the recorded strain,
//! read through the model's calibration or the ESTIMATE gain (said beside each), against the
//! replayed.

use std::path::Path;

use planner::analysis::fit::{prediction_r2, rms_difference};
use planner::model::Model;

use crate::error::Result;
use crate::identify::recording::Recording;
use crate::identify::rollout::{self, Replayed};

/// Whether a model's Present Load reading of a joint was fitted (a calibration) or is the
/// default (an ESTIMATE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reading {
    Calibrated,
    Estimate,
}

impl Reading {
    /// The word printed beside a load figure.
    pub fn word(self) -> &'static str {
        match self {
            Reading::Calibrated => "calibrated",
            Reading::Estimate => "ESTIMATE",
        }
    }

    /// How `model` reads joint `j`'s load: calibrated when the model's calibration file has the
    /// joint or the model file gives the joint its own load gain (as the identification writes
    /// it), else the servo model's ESTIMATE.
    pub fn of(model: &Model, j: usize) -> Self {
        let name = &model.joints[j].name;
        let own = model
            .servo_dynamics
            .of_joint(name)
            .is_some_and(|e| e.load_gain.is_some())
            || model
                .calibration
                .as_ref()
                .is_some_and(|c| c.joint(name).is_some());
        if own {
            Reading::Calibrated
        } else {
            Reading::Estimate
        }
    }

    /// How `model` reads gauge `name`: its counts per microstrain from the model's calibration
    /// file (calibrated), else the virtual strain board's invented
    /// `board::strain::virtual_board::DEFAULT_GAIN` (an ESTIMATE: the lab's gain is not
    /// published).
    pub fn of_gauge(model: &Model, name: &str) -> (Self, f64) {
        match model.calibration.as_ref().and_then(|c| c.gauge_gain(name)) {
            Some(g) => (Reading::Calibrated, g),
            None => (
                Reading::Estimate,
                board::strain::virtual_board::DEFAULT_GAIN,
            ),
        }
    }
}

/// One joint's replay against its recording.
#[derive(Debug, Clone, PartialEq)]
pub struct JointReplay {
    pub joint: String,
    /// Position: RMS of recorded - replayed, rad, and R^2 of the replay predicting the record.
    pub position_rms_rad: f64,
    pub position_r2: Option<f64>,
    /// Velocity RMS, rad/s.
    pub velocity_rms_rad_s: f64,
    /// Load (as read, N m): RMS and R^2.
    pub load_rms_nm: f64,
    pub load_r2: Option<f64>,
    pub reading: Reading,
    /// The traces, for plots: recorded and replayed position (rad) and load (N m).
    pub q_recorded: Vec<f64>,
    pub q_replayed: Vec<f64>,
    pub load_recorded: Vec<f64>,
    pub load_replayed: Vec<f64>,
}

/// One gauge's replay against its recording: the recorded counts above the baseline through
/// the model's reading of the gauge ([`Reading::of_gauge`]) against the physics robot's
/// simulated gauge at the bus cycle nearest each sample (both relative to the trial's first
/// sample when that was the baseline).
#[derive(Debug, Clone, PartialEq)]
pub struct GaugeReplay {
    pub gauge: String,
    pub samples: usize,
    pub rms_microstrain: f64,
    pub r2: Option<f64>,
    pub reading: Reading,
    /// The reading's counts per microstrain.
    pub gain: f64,
}

/// A recording replayed on a model.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    pub trial: String,
    pub model: String,
    pub suspended: bool,
    /// Bus cycle times, s.
    pub t: Vec<f64>,
    pub joints: Vec<JointReplay>,
    /// Per gauge of the model the trial recorded (none without strain).
    pub gauges: Vec<GaugeReplay>,
}

impl Replay {
    /// RMS over every joint of the position error, rad.
    pub fn position_rms_rad(&self) -> f64 {
        let n = self.joints.len().max(1) as f64;
        (self
            .joints
            .iter()
            .map(|j| j.position_rms_rad.powi(2))
            .sum::<f64>()
            / n)
            .sqrt()
    }

    /// The figures as a text table, one joint a line.
    pub fn table(&self) -> String {
        let mut s = format!(
            "replay of {} on the model {} ({}):\njoint      pos RMS mrad  pos R^2  vel RMS rad/s  load RMS N m  load R^2  load reading\n",
            self.trial,
            self.model,
            if self.suspended {
                "suspended"
            } else {
                "standing on flat ground"
            }
        );
        let r2 = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.3}"));
        for j in &self.joints {
            s.push_str(&format!(
                "{:<10} {:>12.2}  {:>7}  {:>13.3}  {:>12.3}  {:>8}  {}\n",
                j.joint,
                j.position_rms_rad * 1e3,
                r2(j.position_r2),
                j.velocity_rms_rad_s,
                j.load_rms_nm,
                r2(j.load_r2),
                j.reading.word()
            ));
        }
        s.push_str(&format!(
            "all joints: position RMS {:.2} mrad\n",
            self.position_rms_rad() * 1e3
        ));
        if !self.gauges.is_empty() {
            s.push_str("gauge                RMS microstrain  R^2     samples  reading\n");
        }
        for g in &self.gauges {
            s.push_str(&format!(
                "{:<20} {:>15.2}  {:>6}  {:>7}  {} ({:.4} counts per microstrain)\n",
                g.gauge,
                g.rms_microstrain,
                r2(g.r2),
                g.samples,
                g.reading.word(),
                g.gain
            ));
        }
        s
    }
}

/// The load a servo of joint `j` of `model` reads for joint torque `tau` (joint direction), as
/// N m through the register's nominal conversion (no noise).
pub fn reading_nm(model: &Model, j: usize, tau: f64) -> f64 {
    let map = model.joints[j].servo.expect("a servo joint");
    let mut p = model.servo_params(j).expect("a servo joint");
    p.load_noise_nm = 0.0;
    let sign = f64::from(map.sign);
    let raw = physics::servo::present_load(map.model, &p, sign * tau, 0.0);
    recorded_nm(model, j, raw)
}

/// A recorded Present Load of joint `j`, N m in the joint's direction through the register's
/// nominal conversion.
pub fn recorded_nm(model: &Model, j: usize, raw: i16) -> f64 {
    let map = model.joints[j].servo.expect("a servo joint");
    f64::from(map.sign) * f64::from(dynamixel::units::load_to_torque_nm(map.model, raw))
}

/// The figures of `out`, the replay of `rec` on `model`.
pub fn figures(model: &Model, rec: &Recording, out: &Replayed) -> Replay {
    let joints = rec
        .joints
        .iter()
        .enumerate()
        .map(|(k, jt)| {
            let load_recorded: Vec<f64> = jt
                .load_raw
                .iter()
                .map(|&r| recorded_nm(model, jt.joint, r))
                .collect();
            let load_replayed: Vec<f64> = out.torque[k]
                .iter()
                .map(|&t| reading_nm(model, jt.joint, t))
                .collect();
            let pos: Vec<(f64, f64)> = jt.q.iter().copied().zip(out.q[k].iter().copied()).collect();
            let vel: Vec<(f64, f64)> = jt
                .qd
                .iter()
                .copied()
                .zip(out.qd[k].iter().copied())
                .collect();
            let load: Vec<(f64, f64)> = load_recorded
                .iter()
                .copied()
                .zip(load_replayed.iter().copied())
                .collect();
            JointReplay {
                joint: jt.name.clone(),
                position_rms_rad: rms_difference(&pos).unwrap_or(0.0),
                position_r2: prediction_r2(&pos),
                velocity_rms_rad_s: rms_difference(&vel).unwrap_or(0.0),
                load_rms_nm: rms_difference(&load).unwrap_or(0.0),
                load_r2: prediction_r2(&load),
                reading: Reading::of(model, jt.joint),
                q_recorded: jt.q.clone(),
                q_replayed: out.q[k].clone(),
                load_recorded,
                load_replayed,
            }
        })
        .collect();
    Replay {
        trial: rec.name.clone(),
        model: match &model.calibration {
            Some(c) => format!("{} (calibration {})", model.name, c.path.display()),
            None => model.name.clone(),
        },
        suspended: rec.suspended,
        t: rec.t.clone(),
        joints,
        gauges: gauge_figures(model, rec, out),
    }
}

/// Per gauge of `model` the trial recorded, its strain against the replay's (see
/// [`GaugeReplay`]); none when either has no strain.
fn gauge_figures(model: &Model, rec: &Recording, out: &Replayed) -> Vec<GaugeReplay> {
    let Some(strain) = &rec.strain else {
        return Vec::new();
    };
    if out.strain.is_empty() || strain.t.is_empty() {
        return Vec::new();
    }
    let near = strain.nearest_cycles(&rec.t);
    let mut gauges = Vec::new();
    for (col, name) in strain.names.iter().enumerate() {
        let Some(g) = model.gauges.iter().position(|m| &m.name == name) else {
            continue;
        };
        let (reading, gain) = Reading::of_gauge(model, name);
        let zero = if strain.baseline_first_sample {
            out.strain[near[0]][g]
        } else {
            0.0
        };
        let pairs: Vec<(f64, f64)> = near
            .iter()
            .zip(&strain.counts)
            .map(|(&c, counts)| {
                (
                    (counts[col] - strain.baseline[col]) / gain,
                    out.strain[c][g] - zero,
                )
            })
            .collect();
        gauges.push(GaugeReplay {
            gauge: name.clone(),
            samples: pairs.len(),
            rms_microstrain: rms_difference(&pairs).unwrap_or(0.0),
            r2: prediction_r2(&pairs),
            reading,
            gain,
        });
    }
    gauges
}

/// Replays `rec` on `model` and measures it.
pub fn replay_recording(model: &Model, rec: &Recording) -> Result<Replay> {
    let out = rollout::replay(model, rec)?;
    Ok(figures(model, rec, &out))
}

/// Replays the trial folder `dir` on `model` and measures it.
pub fn replay_trial(dir: &Path, model: &Model) -> Result<Replay> {
    replay_recording(model, &Recording::read(dir, model)?)
}
