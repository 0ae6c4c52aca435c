//! Writing a plan directory's own files (plan.json, model.toml, model.urdf, joints.csv, feet.csv),
//! each through a scratch file renamed over the old one when complete: a run that fails or is
//! killed leaves every file either whole from before or whole from this run.

use std::path::Path;

use super::columns::{FEET_CSV, JOINTS_CSV, MODEL_TOML, MODEL_URDF, PLAN_JSON};
use super::{ExtraColumn, PlanDirError, PlanJson, ReportError, write_feet_csv, write_joints_csv};
use crate::plan::Plan;

/// Writes `plan` into `dir` (created if missing) with the summary `json` and the extra columns of
/// joints.csv and feet.csv (the dynamics' torques and forces); returns the names of the files.
pub fn write(
    dir: &Path,
    plan: &Plan,
    json: &PlanJson,
    joint_extra: &[ExtraColumn],
    feet_extra: &[ExtraColumn],
) -> Result<[&'static str; 5], PlanDirError> {
    std::fs::create_dir_all(dir).map_err(|source| PlanDirError::Io {
        file: dir.to_path_buf(),
        source,
    })?;
    let create = |p: &Path| std::fs::File::create(p).map_err(ReportError::from);
    replace(&dir.join(JOINTS_CSV), |p| {
        write_joints_csv(create(p)?, plan, joint_extra)
    })?;
    replace(&dir.join(FEET_CSV), |p| {
        write_feet_csv(create(p)?, plan, feet_extra)
    })?;
    let notes = format!(
        "The model of this plan directory (planned from `{}`), written with the plan so the \
         directory is read without the model's source.",
        json.model_source
    );
    let toml = crate::model::to_toml_string(&plan.model, &notes, &|_| String::new());
    replace(&dir.join(MODEL_TOML), |p| Ok(std::fs::write(p, &toml)?))?;
    let urdf = crate::model::to_urdf(&plan.model);
    replace(&dir.join(MODEL_URDF), |p| Ok(std::fs::write(p, &urdf)?))?;
    // plan.json last: a directory with a plan.json of this format has all its other files.
    let text = json.to_json();
    replace(&dir.join(PLAN_JSON), |p| Ok(std::fs::write(p, &text)?))?;
    Ok([JOINTS_CSV, FEET_CSV, MODEL_TOML, MODEL_URDF, PLAN_JSON])
}

/// Writes `path` through a scratch file `.partial-NAME` beside it (same extension, so writers that
/// pick a format by extension pick the same one), renamed over `path` only once complete.
pub fn replace(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), ReportError>,
) -> Result<(), PlanDirError> {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    let scratch = path.with_file_name(format!(".partial-{name}"));
    let done = write(&scratch).and_then(|()| Ok(std::fs::rename(&scratch, path)?));
    if done.is_err() {
        let _ = std::fs::remove_file(&scratch);
    }
    done.map_err(|source| PlanDirError::Write {
        file: path.to_path_buf(),
        source,
    })
}
