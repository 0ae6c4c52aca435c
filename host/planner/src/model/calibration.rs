//! Calibrated readings (docs/identification.md, "Calibrated readings"): a TOML file a model file
//! names (`calibration = "cal.toml"`, relative to the model file) holding, per servo joint, the
//! Present Load reading's gain and offset and, per strain gauge, its gain in counts per
//! microstrain, each with the R^2 and sample count of the fit that gave it (`dbot calibrate`).
//!
//! ```toml
//! trial = "out/trials/stand 2026-12-06 10-00-00"   # where it was fitted from (free text)
//! against = "the plan's static prediction of the model drosophibot2"   # what it was fitted against (free text)
//! [joint.LF_CTr]
//! load_gain = 0.81         # the model file's servo_dynamics.load_gain: reading = gain x torque + offset
//! load_offset_nm = 0.049   # servo direction, as servo_dynamics.load_offset_nm
//! r2 = 0.98
//! samples = 1200
//! [gauge.LF_troch_axial]
//! counts_per_microstrain = 0.61
//! r2 = 0.99
//! samples = 500
//! ```
//!
//! A joint's entry overrides the model's `servo_dynamics` load gain and offset
//! ([`Model::servo_params`]); a gauge's gain is what its counts are divided by. Loading checks
//! every entry against the model and the servo fields' ranges; an error names the calibration
//! file, the joint or gauge and the field (TOML errors: the line).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::{ModelError, field};
use super::servo_params::SERVO_FIELDS;
use super::types::Model;

/// Largest gauge gain accepted, counts per microstrain (the 10-bit board reads 0..1023: a gain
/// above this would saturate it at a fraction of a microstrain).
pub const MAX_COUNTS_PER_MICROSTRAIN: f64 = 1_000.0;

/// One joint's Present Load reading, fitted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointCalibration {
    pub load_gain: f64,
    /// Servo direction, N m (as the model file's `servo_dynamics.load_offset_nm`).
    pub load_offset_nm: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r2: Option<f64>,
    #[serde(default)]
    pub samples: usize,
}

/// One gauge's gain, fitted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaugeCalibration {
    pub counts_per_microstrain: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r2: Option<f64>,
    #[serde(default)]
    pub samples: usize,
}

/// A calibration file's contents.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationFile {
    /// Where it was fitted from (free text).
    #[serde(default)]
    pub trial: String,
    /// What the readings were fitted against (free text; empty in files written before it).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub against: String,
    #[serde(default, rename = "joint")]
    pub joints: BTreeMap<String, JointCalibration>,
    #[serde(default, rename = "gauge")]
    pub gauges: BTreeMap<String, GaugeCalibration>,
}

/// A model's calibration: the file (absolute path) and what it holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReadingCalibration {
    pub path: PathBuf,
    pub file: CalibrationFile,
}

impl ReadingCalibration {
    /// The joint's entry.
    pub fn joint(&self, name: &str) -> Option<&JointCalibration> {
        self.file.joints.get(name)
    }

    /// The gauge's counts per microstrain.
    pub fn gauge_gain(&self, name: &str) -> Option<f64> {
        self.file.gauges.get(name).map(|g| g.counts_per_microstrain)
    }
}

impl CalibrationFile {
    /// As TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a calibration always serialises")
    }

    /// Parses `text` (named `file` in errors) and checks it against `model`.
    pub fn parse(text: &str, file: &str, model: &Model) -> Result<Self, ModelError> {
        let c: CalibrationFile = toml::from_str(text).map_err(|e| ModelError::Toml {
            file: file.to_owned(),
            message: e.to_string(),
        })?;
        c.check(file, model)?;
        Ok(c)
    }

    /// Every joint a servo joint of `model`, every gauge one of its gauges, every value in range.
    pub fn check(&self, file: &str, model: &Model) -> Result<(), ModelError> {
        let range = |name: &str| {
            SERVO_FIELDS
                .iter()
                .find(|r| r.name == name)
                .map(|r| (r.min, r.max))
                .expect("a declared servo field")
        };
        let r2_ok = |r: Option<f64>| r.is_none_or(|r| r.is_finite() && r <= 1.0 + 1e-9);
        for (name, j) in &self.joints {
            let place = format!("joint {name}");
            let Some(index) = model.joint_index(name) else {
                return Err(ModelError::Unknown {
                    file: file.to_owned(),
                    place: "calibration".into(),
                    what: "joint",
                    name: name.clone(),
                });
            };
            if model.servo_params(index).is_none() {
                return Err(field(
                    file,
                    place,
                    "load_gain",
                    "the joint has no servo: only a servo reports Present Load",
                ));
            }
            for (f, v) in [
                ("load_gain", j.load_gain),
                ("load_offset_nm", j.load_offset_nm),
            ] {
                let (lo, hi) = range(f);
                if !(v.is_finite() && (lo..=hi).contains(&v)) {
                    return Err(field(
                        file,
                        &place,
                        f,
                        format!("{v} is outside {lo} ..= {hi}"),
                    ));
                }
            }
            if !r2_ok(j.r2) {
                return Err(field(file, &place, "r2", "must be a number up to 1"));
            }
        }
        for (name, g) in &self.gauges {
            let place = format!("gauge {name}");
            if !model.gauges.iter().any(|m| &m.name == name) {
                return Err(ModelError::Unknown {
                    file: file.to_owned(),
                    place: "calibration".into(),
                    what: "gauge",
                    name: name.clone(),
                });
            }
            let v = g.counts_per_microstrain;
            if !(v.is_finite() && v > 0.0 && v <= MAX_COUNTS_PER_MICROSTRAIN) {
                return Err(field(
                    file,
                    &place,
                    "counts_per_microstrain",
                    format!(
                        "{v} is not a gain: give a positive number up to {MAX_COUNTS_PER_MICROSTRAIN}"
                    ),
                ));
            }
            if !r2_ok(g.r2) {
                return Err(field(file, &place, "r2", "must be a number up to 1"));
            }
        }
        Ok(())
    }
}

/// Reads the calibration `name` names, relative to the directory of the model file `model_file`
/// (absolute as given), and checks it against `model`.
pub(crate) fn load_named(
    name: &str,
    model_file: &str,
    model: &Model,
) -> Result<ReadingCalibration, ModelError> {
    let given = Path::new(name);
    let joined = if given.is_absolute() {
        given.to_path_buf()
    } else {
        Path::new(model_file)
            .parent()
            .unwrap_or(Path::new(""))
            .join(given)
    };
    let path = std::path::absolute(&joined).unwrap_or(joined);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        field(
            model_file,
            "model",
            "calibration",
            format!("cannot read {}: {e}", path.display()),
        )
    })?;
    let file = CalibrationFile::parse(&text, &path.display().to_string(), model)?;
    Ok(ReadingCalibration { path, file })
}
