//! Calibrated readings (docs/identification.md, "Calibrated readings"; `dbot calibrate`,
//! `dbot.calibrate`): from a standing trial, per servo joint the Present Load reading's gain and
//! offset against the predicted joint torque, and per strain gauge its gain in counts per
//! microstrain against the predicted strain, each a least-squares line with its R^2 and sample
//! count, written as the calibration file a model file names (`planner::model::calibration`).
//! The prediction ([`Against`]) is the plan's static one at the recorded goals
//! ([`predict::predict`], the default) or the trial replayed on the model's body
//! ([`predict::replayed`]: its servo dynamics, MuJoCo's contacts, the posture changes' own
//! dynamics), for a model whose servo dynamics were identified.
//!
//! The load: the recorded Present Load through the register's nominal conversion (N m, joint
//! direction) against the predicted torque: `gain x torque + offset` (`identify::load::fit`).
//! The strain: counts above the trial's baseline against predicted microstrain, a line with an
//! intercept (the baseline is often the trial's first sample, the robot already standing, not
//! zero strain): its slope is the gain. A joint or gauge is calibrated only when its fit explains
//! the recording ([`MIN_R2`]) with a gain in range; the others are listed with the reason and
//! keep their ESTIMATE.

pub mod predict;

use std::path::Path;

use planner::analysis::fit::{MIN_SAMPLES, regression_r2};
use planner::model::{CalibrationFile, GaugeCalibration, JointCalibration, Model};

use crate::bail;
use crate::error::{Context, Result};
use crate::identify::recording::Recording;
use crate::replay::recorded_nm;

/// Least R^2 of a fit kept as a calibration: below it the prediction explains too little of
/// the recording for its scale to mean a gain (a joint or gauge the standing excitation barely
/// loads, or one where the plan and the robot share the load among the feet differently).
pub const MIN_R2: f64 = 0.8;

/// Most cycles predicted (evenly spread): the static solve per cycle is the cost.
pub const MAX_PREDICTED: usize = 2000;

/// What the readings are fitted against (`dbot calibrate --against`, Python `against=`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Against {
    /// The plan's static prediction at the recorded goals ([`predict::predict`]): needs only the
    /// model's geometry and masses, and maps the readings onto what the plan predicts.
    #[default]
    Plan,
    /// The trial's goals replayed on the model's body ([`predict::replayed`]): the torque and
    /// strain its servo dynamics and contacts give, for a model whose servo dynamics were
    /// identified (`dbot identify`); maps the readings onto torque and strain themselves.
    Replay,
}

impl Against {
    /// The choice named `word`; an error in the words the CLI and Python both give.
    pub fn parse(word: &str) -> Result<Self> {
        match word {
            "plan" => Ok(Against::Plan),
            "replay" => Ok(Against::Replay),
            other => bail!(
                "against: {other:?} is neither \"plan\" (the plan's static prediction) nor \"replay\" \
                 (the trial replayed on the model's body)"
            ),
        }
    }

    /// What the prediction was, for the printout and the calibration file.
    pub fn describe(self, model: &str) -> String {
        match self {
            Against::Plan => format!("the plan's static prediction of the model {model}"),
            Against::Replay => format!("the trial replayed on the body of the model {model}"),
        }
    }
}

/// One joint's or gauge's fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The joint's or gauge's name.
    pub name: String,
    pub samples: usize,
    /// Regression R^2 of the reading against the prediction.
    pub r2: Option<f64>,
    /// Load: reading per N m of predicted torque; strain: counts per predicted microstrain.
    pub gain: Option<f64>,
    /// Load only: the offset, N m, servo direction (the model file's `load_offset_nm`).
    pub offset_nm: Option<f64>,
    /// Why it is not kept as a calibration (None: kept).
    pub not_kept: Option<String>,
}

/// What a calibration found.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibrated {
    /// The standing trial's name (the recording's).
    pub trial: String,
    /// The model's name, whose plan or body predicted the torques and strain.
    pub model: String,
    /// What the readings were fitted against.
    pub against: Against,
    /// One fit per servo joint, kept or not.
    pub joints: Vec<Fit>,
    /// One fit per strain gauge, kept or not.
    pub gauges: Vec<Fit>,
}

impl Calibrated {
    /// The calibration file of the kept fits.
    pub fn file(&self) -> CalibrationFile {
        let mut f = CalibrationFile {
            trial: self.trial.clone(),
            against: self.against.describe(&self.model),
            ..CalibrationFile::default()
        };
        for j in self.joints.iter().filter(|j| j.not_kept.is_none()) {
            f.joints.insert(
                j.name.clone(),
                JointCalibration {
                    load_gain: j.gain.unwrap_or(1.0),
                    load_offset_nm: j.offset_nm.unwrap_or(0.0),
                    r2: j.r2,
                    samples: j.samples,
                },
            );
        }
        for g in self.gauges.iter().filter(|g| g.not_kept.is_none()) {
            f.gauges.insert(
                g.name.clone(),
                GaugeCalibration {
                    counts_per_microstrain: g.gain.unwrap_or(1.0),
                    r2: g.r2,
                    samples: g.samples,
                },
            );
        }
        f
    }

    /// The fits as text, one joint or gauge a line, each saying whether it was kept.
    pub fn table(&self) -> String {
        let num = |v: Option<f64>, p: usize| v.map_or("-".to_owned(), |v| format!("{v:.p$}"));
        let kept = |f: &Fit| {
            f.not_kept
                .as_ref()
                .map_or("calibrated".to_owned(), |w| format!("ESTIMATE kept: {w}"))
        };
        let mut s = format!(
            "calibration from {} against {}:\n",
            self.trial,
            self.against.describe(&self.model)
        );
        // One row format for both: the name, the gain (width, decimals), a load's offset.
        for (heading, fits, (nw, gw, gp), load) in [
            (
                "joint      load gain  offset N m     R^2  samples  reading\n",
                &self.joints,
                (10, 9, 3),
                true,
            ),
            (
                "gauge                counts/microstrain     R^2  samples  reading\n",
                &self.gauges,
                (20, 18, 4),
                false,
            ),
        ] {
            s.push_str(heading);
            for f in fits {
                let offset = if load {
                    format!("  {:>10}", num(f.offset_nm, 4))
                } else {
                    String::new()
                };
                s.push_str(&format!(
                    "{:<nw$} {:>gw$}{offset}  {:>6}  {:>7}  {}\n",
                    f.name,
                    num(f.gain, gp),
                    num(f.r2, 3),
                    f.samples,
                    kept(f)
                ));
            }
        }
        let (nj, ng) = (
            self.joints.iter().filter(|f| f.not_kept.is_none()).count(),
            self.gauges.iter().filter(|f| f.not_kept.is_none()).count(),
        );
        s.push_str(&format!(
            "calibrated: {nj} of {} joints, {ng} of {} gauges (R^2 at least {MIN_R2})\n",
            self.joints.len(),
            self.gauges.len()
        ));
        s
    }
}

/// Why a fit of `r2` and `gain` is not kept (None: kept); `range` the gain's.
fn judge(samples: usize, r2: Option<f64>, gain: Option<f64>, range: (f64, f64)) -> Option<String> {
    match (r2, gain) {
        _ if samples < MIN_SAMPLES => Some(format!("{samples} samples")),
        (None, _) | (_, None) => Some("the prediction does not vary".into()),
        (Some(r2), _) if r2 < MIN_R2 => Some(format!("R^2 {r2:.3} below {MIN_R2}")),
        (_, Some(g)) if !(range.0..=range.1).contains(&g) => {
            Some(format!("gain {g:.4} outside {} ..= {}", range.0, range.1))
        }
        _ => None,
    }
}

/// Calibrates from the trial folder `dir` against `model`'s prediction (`against`).
pub fn calibrate_trial(dir: &Path, model: &Model, against: Against) -> Result<Calibrated> {
    calibrate_against(&Recording::read(dir, model)?, model, against)
}

/// Calibrates from the standing recording `rec` against `model`'s plan (see the header).
pub fn calibrate(rec: &Recording, model: &Model) -> Result<Calibrated> {
    calibrate_against(rec, model, Against::Plan)
}

/// Calibrates from the standing recording `rec` against `model`'s prediction `against` (see the
/// header).
pub fn calibrate_against(rec: &Recording, model: &Model, against: Against) -> Result<Calibrated> {
    if rec.suspended {
        bail!(
            "trial {}: a suspended trial (the feet in the air): calibrate needs a standing trial, \
             every foot on flat ground (`dbot excite --kind standing`)",
            rec.name
        );
    }
    let n = rec.len();
    let near = rec.strain.as_ref().map(|s| s.nearest_cycles(&rec.t));
    let cycles: Vec<usize> = match &near {
        Some(near) => {
            let mut c = near.clone();
            c.dedup();
            c
        }
        None => (0..n).collect(),
    };
    let stride = cycles.len().div_ceil(MAX_PREDICTED).max(1);
    let cycles: Vec<usize> = cycles.into_iter().step_by(stride).collect();
    let pred = match against {
        Against::Plan => predict::predict(model, rec, cycles)?,
        Against::Replay => predict::replayed(model, rec, cycles)?,
    };
    let load_range = range_of("load_gain");
    let joints = rec
        .joints
        .iter()
        .enumerate()
        .map(|(k, jt)| {
            let torque: Vec<f64> = pred.torque.iter().map(|t| t[k]).collect();
            let recorded: Vec<f64> = pred
                .cycles
                .iter()
                .map(|&c| recorded_nm(model, jt.joint, jt.load_raw[c]))
                .collect();
            let raw: Vec<i16> = pred.cycles.iter().map(|&c| jt.load_raw[c]).collect();
            let map = model.joints[jt.joint].servo.expect("a servo joint");
            let unit = f64::from(dynamixel::units::load_to_torque_nm(map.model, 1));
            let line = crate::identify::load::fit(&recorded, &torque, &raw, unit);
            let r2 = regression_r2(&torque, &recorded);
            let gain = line.map(|l| l.gain);
            Fit {
                name: jt.name.clone(),
                samples: recorded.len(),
                r2,
                gain,
                offset_nm: line.map(|l| f64::from(map.sign) * l.offset_nm),
                not_kept: judge(recorded.len(), r2, gain, load_range),
            }
        })
        .collect();
    let mut gauges = Vec::new();
    if let (Some(strain), Some(near)) = (&rec.strain, &near) {
        for (col, name) in strain.names.iter().enumerate() {
            let Some(g) = model.gauges.iter().position(|m| &m.name == name) else {
                continue;
            };
            let (mut x, mut y) = (Vec::new(), Vec::new());
            for (s, &c) in near.iter().enumerate() {
                if let Ok(k) = pred.cycles.binary_search(&c) {
                    x.push(pred.strain[k][g]);
                    y.push(strain.counts[s][col] - strain.baseline[col]);
                }
            }
            let gain = planner::analysis::fit::line(&x, &y).map(|l| l.slope);
            let r2 = regression_r2(&x, &y);
            gauges.push(Fit {
                name: name.clone(),
                samples: x.len(),
                r2,
                gain,
                offset_nm: None,
                not_kept: judge(
                    x.len(),
                    r2,
                    gain,
                    (
                        1e-6,
                        planner::model::calibration::MAX_COUNTS_PER_MICROSTRAIN,
                    ),
                ),
            });
        }
    }
    Ok(Calibrated {
        trial: rec.name.clone(),
        model: model.name.clone(),
        against,
        joints,
        gauges,
    })
}

/// The range the model file allows the servo field `name`.
fn range_of(name: &str) -> (f64, f64) {
    planner::model::SERVO_FIELDS
        .iter()
        .find(|r| r.name == name)
        .map(|r| (r.min, r.max))
        .expect("a declared servo field")
}

/// Writes `cal`'s file to `out` (atomically), checked against `model` as a model file naming it
/// would be.
pub fn write(cal: &Calibrated, model: &Model, out: &Path) -> Result<()> {
    let file = cal.file();
    file.check(&out.display().to_string(), model)?;
    board::files::write_bytes_atomically(out, file.to_toml().as_bytes())
        .with_context(|| format!("writing {}", out.display()))
}
