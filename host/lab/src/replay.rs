//! Replay: a recorded trial's goals played on the physics robot's body with a model's servo
//! dynamics ([`crate::identify::rollout`]), and per joint how well the replay follows the
//! recording: R^2 (`planner::analysis::fit::prediction_r2`) and RMS of the position and of the
//! load, the sim-to-real figure of merit (`dbot replay`, `dbot.replay`).
//!
//! The load is compared as the servo reads it: the recorded Present Load and the replayed
//! torque through the model's Present Load reading (its gain and offset, no noise), both turned
//! into N m by the register's nominal conversion (`dynamixel::units::load_to_torque_nm`, an
//! ESTIMATE of torque). Whether the model's reading was calibrated ([`Reading`]) is said with
//! every figure. Strain is not replayed yet.

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

    /// How `model` reads joint `j`'s load: calibrated when the model file gives the joint its
    /// own load gain (as the identification writes it), else the servo model's ESTIMATE.
    pub fn of(model: &Model, j: usize) -> Self {
        let own = model
            .servo_dynamics
            .of_joint(&model.joints[j].name)
            .is_some_and(|e| e.load_gain.is_some());
        if own {
            Reading::Calibrated
        } else {
            Reading::Estimate
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

/// A recording replayed on a model.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    pub trial: String,
    pub model: String,
    pub suspended: bool,
    /// Bus cycle times, s.
    pub t: Vec<f64>,
    pub joints: Vec<JointReplay>,
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
        model: model.name.clone(),
        suspended: rec.suspended,
        t: rec.t.clone(),
        joints,
    }
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
