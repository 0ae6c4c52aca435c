//! The physics robot's body as a Python value (`Board.body()`): a dict of NumPy arrays in SI
//! units, world frame, the feet in the model's order (`feet`: leg names). Everything comes from
//! `physics::Body`; this file only converts.

use numpy::ToPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `body` as a dict: `time_s`, `thorax_position_m` (3), `thorax_orientation` (w, x, y, z),
/// `thorax_rpy_rad` (roll, pitch, yaw), `thorax_velocity_m_s` (3), `thorax_angular_velocity_rad_s`
/// (3), `feet` (names), `foot_force_n` (feet x 3), `foot_contact` (feet, bool), `foot_slip_m_s`
/// (feet).
pub fn body_dict<'py>(py: Python<'py>, body: &physics::Body) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let t = &body.thorax;
    d.set_item("time_s", body.time_s)?;
    d.set_item(
        "thorax_position_m",
        Array1::from(t.position_m.to_vec()).to_pyarray(py),
    )?;
    d.set_item(
        "thorax_orientation",
        Array1::from(t.orientation.to_vec()).to_pyarray(py),
    )?;
    d.set_item(
        "thorax_rpy_rad",
        Array1::from(t.roll_pitch_yaw().to_vec()).to_pyarray(py),
    )?;
    d.set_item(
        "thorax_velocity_m_s",
        Array1::from(t.velocity_m_s.to_vec()).to_pyarray(py),
    )?;
    d.set_item(
        "thorax_angular_velocity_rad_s",
        Array1::from(t.angular_velocity_rad_s.to_vec()).to_pyarray(py),
    )?;
    let feet = &body.feet;
    d.set_item(
        "feet",
        feet.iter()
            .map(|f| f.leg.name().to_owned())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "foot_force_n",
        Array2::from_shape_fn((feet.len(), 3), |(i, k)| feet[i].force_n[k]).to_pyarray(py),
    )?;
    d.set_item(
        "foot_contact",
        Array1::from_iter(feet.iter().map(|f| f.contact)).to_pyarray(py),
    )?;
    d.set_item(
        "foot_slip_m_s",
        Array1::from_iter(feet.iter().map(|f| f.slip_m_s)).to_pyarray(py),
    )?;
    Ok(d)
}
