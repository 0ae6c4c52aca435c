//! Reading a plan directory back: plan.json (version checked first), model.toml, the angles and
//! torques of joints.csv and the stance flags of feet.csv, checked row by row against the model
//! and against plan.json's own timing.

use std::path::{Path, PathBuf};

use super::columns::{
    ANGLE_RAD, FEET_CSV, JOINT, JOINTS_CSV, LEG, MODEL_TOML, PLAN_JSON, SLICE, STANCE, TORQUE_NM,
};
use super::{FORMAT_VERSION, PlanDirError, PlanJson};
use crate::model::{Leg, Model};

/// A plan directory as read: its summary, its model and the per-slice data a step table or a
/// comparison needs.
#[derive(Debug, Clone)]
pub struct PlanDir {
    /// The directory.
    pub path: PathBuf,
    pub json: PlanJson,
    /// The planned model (from the directory's model.toml).
    pub model: Model,
    /// Joint angles, rad: `angle[slice][joint]`, model joint order.
    pub angle: Vec<Vec<f64>>,
    /// Actuator torques, N m, `torque[slice][joint]`; `None` when planned without dynamics.
    pub torque: Option<Vec<Vec<f64>>>,
    /// `stance[slice][leg]`, legs in `json.legs` order.
    pub stance: Vec<Vec<bool>>,
}

impl PlanDir {
    /// The planned torques, `[slice][joint]`, or the error naming joints.csv and how a directory
    /// comes to lack them (`needed_by`: what asked, e.g. "the step table").
    pub fn torques(&self, needed_by: &'static str) -> Result<&[Vec<f64>], PlanDirError> {
        self.torque
            .as_deref()
            .ok_or_else(|| PlanDirError::NoTorques {
                file: self.path.join(JOINTS_CSV),
                needed_by,
            })
    }
}

/// Reads the plan directory `dir`.
pub fn read(dir: &Path) -> Result<PlanDir, PlanDirError> {
    let json = read_json(&dir.join(PLAN_JSON))?;
    let model_path = dir.join(MODEL_TOML);
    let model = crate::model::load(&model_path).map_err(|source| PlanDirError::Model {
        file: model_path.clone(),
        source,
    })?;
    let (angle, torque) = read_joints(&dir.join(JOINTS_CSV), &model, json.slices)?;
    let stance = read_feet(&dir.join(FEET_CSV), &json.legs, json.slices)?;
    super::consistency::check(dir, &json, &stance)?;
    Ok(PlanDir {
        path: dir.to_path_buf(),
        json,
        model,
        angle,
        torque,
        stance,
    })
}

/// plan.json: its `format_version` first, so an old or foreign file is named as such rather than
/// by the first field it lacks.
pub fn read_json(path: &Path) -> Result<PlanJson, PlanDirError> {
    let text = std::fs::read_to_string(path).map_err(|source| PlanDirError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let json_err = |source| PlanDirError::Json {
        file: path.to_path_buf(),
        source,
    };
    let value: serde_json::Value = serde_json::from_str(&text).map_err(json_err)?;
    match value.get("format_version").map(|v| v.as_u64()) {
        None => {
            return Err(PlanDirError::NoVersion {
                file: path.to_path_buf(),
                expected: FORMAT_VERSION,
            });
        }
        Some(Some(v)) if v == u64::from(FORMAT_VERSION) => {}
        Some(found) => {
            return Err(PlanDirError::Version {
                file: path.to_path_buf(),
                found: found.unwrap_or(u64::MAX),
                expected: FORMAT_VERSION,
            });
        }
    }
    serde_json::from_value(value).map_err(json_err)
}

/// A CSV file's reader and the positions of the named columns (`None` for a missing optional one).
fn open(path: &Path) -> Result<(csv::Reader<std::fs::File>, csv::StringRecord), PlanDirError> {
    let row = |e: csv::Error| PlanDirError::Row {
        file: path.to_path_buf(),
        line: e.position().map_or(0, |p| p.line() as usize),
        problem: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(|source| PlanDirError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let mut rd = csv::Reader::from_reader(file);
    let headers = rd.headers().map_err(row)?.clone();
    Ok((rd, headers))
}

/// Data record `i` of `path` with its line number in the file (the header is line 1), or the
/// error naming that line.
fn numbered(
    path: &Path,
    i: usize,
    rec: csv::Result<csv::StringRecord>,
) -> Result<(usize, csv::StringRecord), PlanDirError> {
    let line = i + 2;
    let rec = rec.map_err(|e| PlanDirError::Row {
        file: path.to_path_buf(),
        line,
        problem: e.to_string(),
    })?;
    Ok((line, rec))
}

fn column(
    path: &Path,
    headers: &csv::StringRecord,
    name: &'static str,
    hint: &'static str,
) -> Result<usize, PlanDirError> {
    headers
        .iter()
        .position(|h| h == name)
        .ok_or_else(|| PlanDirError::NoColumn {
            file: path.to_path_buf(),
            column: name,
            hint,
        })
}

fn number<T: std::str::FromStr>(
    path: &Path,
    line: usize,
    what: &str,
    text: &str,
) -> Result<T, PlanDirError> {
    text.parse().map_err(|_| PlanDirError::Row {
        file: path.to_path_buf(),
        line,
        problem: format!("{what} `{text}` is not a number"),
    })
}

/// A number that must be finite (angles, torques): NaN or infinity in a plan is refused, naming the
/// file and line, instead of turning every result computed from it into NaN.
fn finite(path: &Path, line: usize, what: &str, text: &str) -> Result<f64, PlanDirError> {
    let v: f64 = number(path, line, what, text)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(PlanDirError::Row {
            file: path.to_path_buf(),
            line,
            problem: format!("{what} `{text}` is not a finite number"),
        })
    }
}

type JointColumns = (Vec<Vec<f64>>, Option<Vec<Vec<f64>>>);

/// joints.csv: rows in model joint order per slice; angles and, if present, torques.
fn read_joints(path: &Path, model: &Model, slices: usize) -> Result<JointColumns, PlanDirError> {
    let (mut rd, h) = open(path)?;
    let sc = column(path, &h, SLICE, "")?;
    let lc = column(path, &h, LEG, "")?;
    let jc = column(path, &h, JOINT, "")?;
    let ac = column(path, &h, ANGLE_RAD, "")?;
    let tc = h.iter().position(|x| x == TORQUE_NM);
    let n = model.joints.len();
    let mut angle = vec![Vec::with_capacity(n); slices];
    let mut torque = tc.map(|_| vec![Vec::with_capacity(n); slices]);
    let mut rows = 0;
    for (i, rec) in rd.records().enumerate() {
        let (line, rec) = numbered(path, i, rec)?;
        let (s, j) = (i / n.max(1), i % n.max(1));
        let joint = model.joints.get(j).filter(|_| s < slices);
        let found: usize = number(path, line, SLICE, &rec[sc])?;
        let ok = joint.is_some_and(|jt| {
            found == s && rec[lc] == *jt.leg.name() && rec[jc] == *jt.kind.name()
        });
        if !ok {
            let expected = joint.map_or_else(
                || format!("no more rows ({slices} slices x {n} joints)"),
                |jt| format!("slice {s} joint {} (rows in model order)", jt.name),
            );
            return Err(PlanDirError::Row {
                file: path.to_path_buf(),
                line,
                problem: format!(
                    "expected {expected}, found slice {} {} {}",
                    &rec[sc], &rec[lc], &rec[jc]
                ),
            });
        }
        angle[s].push(finite(path, line, ANGLE_RAD, &rec[ac])?);
        if let (Some(t), Some(tc)) = (torque.as_mut(), tc) {
            t[s].push(finite(path, line, TORQUE_NM, &rec[tc])?);
        }
        rows += 1;
    }
    if rows != slices * n {
        return Err(PlanDirError::Shape {
            file: path.to_path_buf(),
            problem: format!("{rows} rows, expected {slices} slices x {n} joints"),
        });
    }
    Ok((angle, torque))
}

/// feet.csv: the stance flag of every leg per slice, legs in `legs` order.
fn read_feet(path: &Path, legs: &[Leg], slices: usize) -> Result<Vec<Vec<bool>>, PlanDirError> {
    let (mut rd, h) = open(path)?;
    let sc = column(path, &h, SLICE, "")?;
    let lc = column(path, &h, LEG, "")?;
    let stc = column(path, &h, STANCE, "")?;
    let mut stance = vec![vec![false; legs.len()]; slices];
    let mut seen = vec![vec![false; legs.len()]; slices];
    for (i, rec) in rd.records().enumerate() {
        let (line, rec) = numbered(path, i, rec)?;
        let bad = |problem: String| PlanDirError::Row {
            file: path.to_path_buf(),
            line,
            problem,
        };
        let s: usize = number(path, line, SLICE, &rec[sc])?;
        let li = legs
            .iter()
            .position(|l| l.name() == &rec[lc])
            .ok_or_else(|| bad(format!("leg `{}` is not one of plan.json's legs", &rec[lc])))?;
        let on = match &rec[stc] {
            "1" => true,
            "0" => false,
            other => return Err(bad(format!("stance `{other}` is neither 0 nor 1"))),
        };
        let slot = seen
            .get_mut(s)
            .ok_or_else(|| bad(format!("slice {s} beyond plan.json's {slices} slices")))?;
        if std::mem::replace(&mut slot[li], true) {
            return Err(bad(format!("slice {s} leg {} listed twice", &rec[lc])));
        }
        stance[s][li] = on;
    }
    if let Some((s, li)) = seen
        .iter()
        .enumerate()
        .find_map(|(s, row)| row.iter().position(|x| !x).map(|li| (s, li)))
    {
        return Err(PlanDirError::Shape {
            file: path.to_path_buf(),
            problem: format!("no row for slice {s} leg {}", legs[li].name()),
        });
    }
    Ok(stance)
}
