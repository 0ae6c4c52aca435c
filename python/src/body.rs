//! The physics robot's body as a Python value (`Board.body()`): a dict of NumPy arrays in SI
//! units, world frame, the feet in the model's order (`feet`: leg names). Everything comes from
//! `physics::Body`; this file only converts.

use numpy::PyArray1;
use planner::model::Leg;
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyString};

use crate::arrays::written;

/// The six legs' names as Python strings, made once (`PyString::intern` decodes and looks its
/// text up on every call).
static LEG_NAMES: PyOnceLock<[Py<PyString>; 6]> = PyOnceLock::new();

fn leg_name<'py>(py: Python<'py>, leg: Leg) -> Bound<'py, PyString> {
    let names = LEG_NAMES.get_or_init(py, || {
        Leg::ALL.map(|l| PyString::intern(py, l.name()).unbind())
    });
    let i = Leg::ALL
        .iter()
        .position(|&l| l == leg)
        .expect("Leg::ALL has every leg");
    names[i].bind(py).clone()
}

/// `body` as a dict: `time_s`, `thorax_position_m` (3), `thorax_orientation` (w, x, y, z),
/// `thorax_rpy_rad` (roll, pitch, yaw), `thorax_velocity_m_s` (3), `thorax_angular_velocity_rad_s`
/// (3), `feet` (names), `foot_force_n` (feet x 3), `foot_contact` (feet, bool), `foot_slip_m_s`
/// (feet).
///
/// `DbotEnv` builds this every step (its `info["body"]`): the arrays are made straight from
/// the values (no intermediate vectors) and the keys are interned strings, the leg names made once.
pub fn body_dict<'py>(py: Python<'py>, body: &physics::Body) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let t = &body.thorax;
    d.set_item(intern!(py, "time_s"), body.time_s)?;
    d.set_item(
        intern!(py, "thorax_position_m"),
        PyArray1::from_slice(py, &t.position_m),
    )?;
    d.set_item(
        intern!(py, "thorax_orientation"),
        PyArray1::from_slice(py, &t.orientation),
    )?;
    d.set_item(
        intern!(py, "thorax_rpy_rad"),
        PyArray1::from_slice(py, &t.roll_pitch_yaw()),
    )?;
    d.set_item(
        intern!(py, "thorax_velocity_m_s"),
        PyArray1::from_slice(py, &t.velocity_m_s),
    )?;
    d.set_item(
        intern!(py, "thorax_angular_velocity_rad_s"),
        PyArray1::from_slice(py, &t.angular_velocity_rad_s),
    )?;
    let feet = &body.feet;
    d.set_item(
        intern!(py, "feet"),
        feet.iter().map(|f| leg_name(py, f.leg)).collect::<Vec<_>>(),
    )?;
    let forces = written(py, [feet.len(), 3], |cells: &mut [f64]| {
        for (row, f) in cells.chunks_exact_mut(3).zip(feet) {
            row.copy_from_slice(&f.force_n);
        }
    });
    d.set_item(intern!(py, "foot_force_n"), forces)?;
    d.set_item(
        intern!(py, "foot_contact"),
        PyArray1::from_iter(py, feet.iter().map(|f| f.contact)),
    )?;
    d.set_item(
        intern!(py, "foot_slip_m_s"),
        PyArray1::from_iter(py, feet.iter().map(|f| f.slip_m_s)),
    )?;
    Ok(d)
}
