//! NumPy (or any sequence) joint targets into a wire setpoint, through the host's SI conversion
//! (which names the joint of a value out of range).

use numpy::PyReadonlyArray1;
use pyo3::prelude::*;

use crate::errors::value_error;

fn vector(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(a) = v.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(a.as_array().to_vec());
    }
    v.extract::<Vec<f64>>()
        .map_err(|_| value_error(format!("{name}: give a 1-D array or sequence of floats")))
}

/// A setpoint numbered `seq` from angles (rad) and optional torques (N m).
pub fn setpoint(
    seq: u32,
    angles_rad: &Bound<'_, PyAny>,
    torques_nm: Option<&Bound<'_, PyAny>>,
) -> PyResult<protocol::Setpoint> {
    let a = vector("angles_rad", angles_rad)?;
    let t = torques_nm.map(|t| vector("torques_nm", t)).transpose()?;
    ::board::link::setpoint_from_si(seq, &a, t.as_deref()).map_err(value_error)
}
