//! NumPy (or any sequence) joint targets into a wire setpoint, through the host's SI conversion
//! (which names the joint of a value out of range), and a proprioception record into
//! `DbotEnv`'s observation (`Board.stream_step`).

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;
use crate::records;

fn vector(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(a) = v.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(a.as_array().to_vec());
    }
    v.extract::<Vec<f64>>()
        .map_err(|_| value_error(format!("{name}: give a 1-D array or sequence of floats")))
}

/// The angles (rad) and optional torques (N m) of a setpoint as vectors.
pub fn vectors(
    angles_rad: &Bound<'_, PyAny>,
    torques_nm: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Vec<f64>, Option<Vec<f64>>)> {
    let a = vector("angles_rad", angles_rad)?;
    let t = torques_nm.map(|t| vector("torques_nm", t)).transpose()?;
    Ok((a, t))
}

/// A setpoint numbered `seq` from angles (rad) and optional torques (N m).
pub fn setpoint(
    seq: u32,
    angles_rad: &Bound<'_, PyAny>,
    torques_nm: Option<&Bound<'_, PyAny>>,
) -> PyResult<protocol::Setpoint> {
    let (a, t) = vectors(angles_rad, torques_nm)?;
    ::board::link::setpoint_from_si(seq, &a, t.as_deref()).map_err(value_error)
}

/// `DbotEnv`'s observation of `rec`: the row `next_proprioception` gives, each value the same
/// double (`records::present_rad` and `velocity_rad_s`, as `next_proprioception`'s), as float arrays; with the physics
/// robot's gauges (`physics`) its strain sample kept for the record's time and the sample's age
/// (NaN without one).
pub fn observation<'py>(
    py: Python<'py>,
    rec: &protocol::Proprioception,
    physics: Option<&physics::PhysicsRobot>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let j = &rec.joints;
    let col =
        |f: &dyn Fn(&protocol::JointFeedback) -> f64| PyArray1::from_iter(py, j.iter().map(f));
    d.set_item(intern!(py, "present_rad"), col(&records::present_rad))?;
    d.set_item(intern!(py, "velocity_rad_s"), col(&records::velocity_rad_s))?;
    d.set_item(intern!(py, "load_raw"), col(&|x| f64::from(x.load)))?;
    d.set_item(
        intern!(py, "setpoint_age"),
        PyArray1::from_slice(py, &[f64::from(rec.setpoint_age)]),
    )?;
    if let Some(p) = physics {
        let t = rec.time_us as f64 * 1e-6;
        // A sample holds a reading per gauge; the names are cloned only when none is kept yet.
        let (strain, age) = match p.strain_at(t) {
            Some(s) => (s.microstrain(), records::strain_age_s(t, s.time_s)),
            None => (vec![f64::NAN; p.gauge_names().len()], f64::NAN),
        };
        d.set_item(
            intern!(py, "strain_microstrain"),
            PyArray1::from_vec(py, strain),
        )?;
        d.set_item(
            intern!(py, "strain_age_s"),
            PyArray1::from_slice(py, &[age]),
        )?;
    }
    Ok(d)
}
