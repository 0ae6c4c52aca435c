//! `dbot.identify(trials, model)`, `dbot.replay(trial, model)` and `dbot.stand_in_trials(out)`:
//! the servo dynamics fitted to recorded trials, a trial replayed on the physics robot, and the
//! stand-in robot's trials, through the very calls `dbot identify` and `dbot replay` make
//! (`lab::identify`, `lab::replay`).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;
use crate::model::Model;

fn model_or_default(model: Option<&Model>) -> PyResult<planner::model::Model> {
    match model {
        Some(m) => Ok(m.inner.clone()),
        None => planner::model::builtin("drosophibot2").map_err(value_error),
    }
}

/// Fits `model`'s servo dynamics (default: the built-in Drosophibot II) to the trial folders
/// `trials` (the suspended excitation's, recorded with the feet in the air), then the ground's
/// friction (``foot_friction``) to those that walked when their feet slip, as ``dbot identify``
/// does, and returns the fitted Model. With `out` (a .toml path) also writes the fitted model
/// there and the report beside it (``<out>-report/``: report.md, plots). ValueError naming the
/// trial, joint or file.
#[pyfunction]
#[pyo3(signature = (trials, model = None, out = None))]
pub fn identify(
    py: Python<'_>,
    trials: Vec<PathBuf>,
    model: Option<&Model>,
    out: Option<PathBuf>,
) -> PyResult<Model> {
    let m = model_or_default(model)?;
    let fitted = py
        .detach(|| {
            let id = lab::identify::identify_trials(&trials, &m, &Default::default())?;
            if let Some(out) = &out {
                lab::identify::write_outputs(&id, out)?;
            }
            Ok::<_, lab::LabError>(id.model)
        })
        .map_err(|e| value_error(e.chain_text()))?;
    Ok(Model { inner: fitted })
}

/// Replays the trial folder `trial`'s goals on the physics robot with `model`'s servo dynamics
/// (default: the built-in Drosophibot II), as ``dbot replay`` does. A dict: ``trial``,
/// ``model``, ``position_rms_rad`` (every joint) and ``joints``, one dict per joint: ``joint``,
/// ``position_rms_rad``, ``position_r2``, ``velocity_rms_rad_s``, ``load_rms_nm``, ``load_r2``
/// (None where the record does not vary) and ``load_reading`` (``"calibrated"`` or
/// ``"ESTIMATE"``).
#[pyfunction]
#[pyo3(signature = (trial, model = None))]
pub fn replay<'py>(
    py: Python<'py>,
    trial: PathBuf,
    model: Option<&Model>,
) -> PyResult<Bound<'py, PyDict>> {
    let m = model_or_default(model)?;
    let r = py
        .detach(|| lab::replay::replay_trial(&trial, &m))
        .map_err(|e| value_error(e.chain_text()))?;
    let d = PyDict::new(py);
    d.set_item("trial", &r.trial)?;
    d.set_item("model", &r.model)?;
    d.set_item("position_rms_rad", r.position_rms_rad())?;
    let mut joints = Vec::new();
    for j in &r.joints {
        let e = PyDict::new(py);
        e.set_item("joint", &j.joint)?;
        e.set_item("position_rms_rad", j.position_rms_rad)?;
        e.set_item("position_r2", j.position_r2)?;
        e.set_item("velocity_rms_rad_s", j.velocity_rms_rad_s)?;
        e.set_item("load_rms_nm", j.load_rms_nm)?;
        e.set_item("load_r2", j.load_r2)?;
        e.set_item("load_reading", j.reading.word())?;
        joints.push(e);
    }
    d.set_item("joints", joints)?;
    Ok(d)
}

/// The stand-in robot (``lab::identify::stand_in``: every servo-dynamics parameter away from
/// the default) records, as trial folders under `out`: the suspended excitation of the servo
/// joints named in `joints` (all when None; ``short``: 0.3 s holds and a 3.5 s chirp instead of
/// ``dbot excite``'s 1 s and 20 s), and a held-out step of the servo-safe walk. A dict:
/// ``suspended`` (paths), ``walk`` (path), ``model`` (the stand-in's own Model: the truth) and
/// ``start`` (the Model a lab starts from: the default with the I and D gain registers read from
/// the stand-in's servos).
#[pyfunction]
#[pyo3(signature = (out, joints = None, short = false))]
pub fn stand_in_trials<'py>(
    py: Python<'py>,
    out: PathBuf,
    joints: Option<Vec<String>>,
    short: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let default = model_or_default(None)?;
    let mut options = planner::excitation::ExcitationOptions::default();
    if short {
        options.hold_s = 0.3;
        options.chirp_s = 3.5;
        options.chirp_taper_s = 0.3;
    }
    let joints = joints.unwrap_or_default();
    let t = py
        .detach(|| lab::identify::stand_in::write_trials(&default, &options, &joints, &out))
        .map_err(|e| value_error(e.chain_text()))?;
    let d = PyDict::new(py);
    d.set_item("suspended", t.suspended)?;
    d.set_item("walk", t.walk)?;
    let truth = lab::identify::stand_in::stand_in_model(&default);
    d.set_item("model", Model { inner: truth }.into_pyobject(py)?)?;
    let start = lab::identify::stand_in::start_model(&default);
    d.set_item("start", Model { inner: start }.into_pyobject(py)?)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(replay, m)?)?;
    m.add_function(wrap_pyfunction!(stand_in_trials, m)?)
}
