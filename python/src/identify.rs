//! `dbot.identify(trials, model)`, `dbot.replay(trial, model)`, `dbot.calibrate(trial, model)`,
//! `dbot.stand_in_trials(out)` and `dbot.stand_in_standing_trial(out)`: the servo dynamics
//! fitted to recorded trials, a trial replayed on the physics robot, calibrated readings from a
//! standing trial, and the stand-in robots' trials, through the very calls `dbot identify`,
//! `dbot replay` and `dbot calibrate` make (`lab::identify`, `lab::replay`, `lab::calibrate`).

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
/// there and the report beside it (``<out>-report/``: report.md, plots). `refine_replays`: as
/// ``dbot identify --refine-replays`` (after Levenberg-Marquardt, Nelder-Mead on each joint with
/// at most that many replays; 0, no refinement). ValueError naming the trial, joint or file.
#[pyfunction]
#[pyo3(signature = (trials, model = None, out = None, refine_replays = 0))]
pub fn identify(
    py: Python<'_>,
    trials: Vec<PathBuf>,
    model: Option<&Model>,
    out: Option<PathBuf>,
    refine_replays: usize,
) -> PyResult<Model> {
    let m = model_or_default(model)?;
    let options = lab::identify::IdentifyOptions {
        refine_replays_per_joint: refine_replays,
        ..Default::default()
    };
    let fitted = py
        .detach(|| {
            if let Some(out) = &out {
                lab::identify::prepare_out(out)?;
            }
            let id = lab::identify::identify_trials(&trials, &m, &options)?;
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
/// ``"ESTIMATE"``); and ``gauges`` (empty unless the trial recorded strain), one dict per
/// gauge: ``gauge``, ``samples``, ``rms_microstrain``, ``r2`` (recorded against replayed),
/// ``reading`` (``"calibrated"``: the model's calibration file's gain, else ``"ESTIMATE"``) and
/// ``counts_per_microstrain`` (the gain used).
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
    let mut gauges = Vec::new();
    for g in &r.gauges {
        let e = PyDict::new(py);
        e.set_item("gauge", &g.gauge)?;
        e.set_item("samples", g.samples)?;
        e.set_item("rms_microstrain", g.rms_microstrain)?;
        e.set_item("r2", g.r2)?;
        e.set_item("reading", g.reading.word())?;
        e.set_item("counts_per_microstrain", g.gain)?;
        gauges.push(e);
    }
    d.set_item("gauges", gauges)?;
    Ok(d)
}

/// Calibrated readings from the standing trial folder `trial` against `model`'s prediction
/// (default: the built-in Drosophibot II), as ``dbot calibrate`` does (``lab::calibrate``): per
/// servo joint the Present Load gain and offset, per strain gauge its counts per microstrain.
/// ``against``: ``"plan"`` (the plan's static prediction) or ``"replay"`` (the trial replayed on
/// the model's body, for a model ``identify`` fitted), as ``dbot calibrate --against``.
/// With `out` (a .toml path) writes the calibration file a model file names
/// (``calibration = "FILE"``). A dict: ``trial``, ``model``, ``table`` (what ``dbot calibrate``
/// prints), ``joints`` and ``gauges``: one dict each with ``name``, ``samples``, ``r2``,
/// ``gain`` (load: reading per N m; gauge: counts per microstrain), ``offset_nm`` (load, servo
/// direction; None for a gauge) and ``kept`` (None, or why the fit stays an ESTIMATE); and
/// ``against`` (what they were fitted against, as the file says). ValueError naming the trial,
/// the file or ``against``, in the CLI's words.
#[pyfunction]
#[pyo3(signature = (trial, model = None, out = None, against = "plan"))]
pub fn calibrate<'py>(
    py: Python<'py>,
    trial: PathBuf,
    model: Option<&Model>,
    out: Option<PathBuf>,
    against: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let m = model_or_default(model)?;
    let against =
        lab::calibrate::Against::parse(against).map_err(|e| value_error(e.chain_text()))?;
    let c = py
        .detach(|| {
            let c = lab::calibrate::calibrate_trial(&trial, &m, against)?;
            if let Some(out) = &out {
                lab::calibrate::write(&c, &m, out)?;
            }
            Ok::<_, lab::LabError>(c)
        })
        .map_err(|e| value_error(e.chain_text()))?;
    let d = PyDict::new(py);
    d.set_item("trial", &c.trial)?;
    d.set_item("model", &c.model)?;
    d.set_item("against", c.against.describe(&c.model))?;
    d.set_item("table", c.table())?;
    let fits = |fits: &[lab::calibrate::Fit]| -> PyResult<Vec<Bound<'py, PyDict>>> {
        fits.iter()
            .map(|f| {
                let e = PyDict::new(py);
                e.set_item("name", &f.name)?;
                e.set_item("samples", f.samples)?;
                e.set_item("r2", f.r2)?;
                e.set_item("gain", f.gain)?;
                e.set_item("offset_nm", f.offset_nm)?;
                e.set_item("kept", f.not_kept.as_deref())?;
                Ok(e)
            })
            .collect()
    };
    d.set_item("joints", fits(&c.joints)?)?;
    d.set_item("gauges", fits(&c.gauges)?)?;
    Ok(d)
}

/// A stand-in robot whose body moves as the default's but whose servos read Present Load as 0.8
/// x torque + 0.05 N m (``lab::identify::stand_in::reading_stand_in_model``) and whose strain
/// board's gain is 0.3 + 0.02 x column counts per microstrain records the standing excitation
/// (``short``: 3 s posture changes and 0.5 s holds instead of ``dbot excite``'s 8 s and 1 s)
/// as the trial folder ``out/stand``. A dict: ``trial`` (path), ``model`` (the stand-in's Model:
/// the truth) and ``gauge_gains`` (gauge name to its true counts per microstrain).
#[pyfunction]
#[pyo3(signature = (out, short = false))]
pub fn stand_in_standing_trial<'py>(
    py: Python<'py>,
    out: PathBuf,
    short: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let default = model_or_default(None)?;
    let mut options = planner::excitation::ExcitationOptions::default();
    if short {
        options.hold_s = 0.5;
        options.posture_s = 3.0;
    }
    let truth = lab::identify::stand_in::reading_stand_in_model(&default);
    let trial = py
        .detach(|| lab::identify::stand_in::write_standing_trial(&truth, &default, &options, &out))
        .map_err(|e| value_error(e.chain_text()))?;
    let d = PyDict::new(py);
    d.set_item("trial", trial)?;
    let gains = PyDict::new(py);
    for (col, name) in ::board::strain::channels::names().iter().enumerate() {
        gains.set_item(name, lab::identify::stand_in::gauge_gain(col))?;
    }
    d.set_item("gauge_gains", gains)?;
    d.set_item("model", Model { inner: truth }.into_pyobject(py)?)?;
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
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(stand_in_standing_trial, m)?)?;
    m.add_function(wrap_pyfunction!(stand_in_trials, m)?)
}
