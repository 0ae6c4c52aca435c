//! `dbot.excitation(kind, model)`: the excitation trials a lab plays on the robot to identify it
//! (`planner::excitation`), each with its step table built under the board's rules, as
//! `dbot excite` writes them (`board::rules::build::excitation_table`, the same call).

use numpy::ToPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::errors::value_error;
use crate::model::Model;

/// The excitation trials of `kind` (``"suspended"``: feet in the air, per-joint steps and chirps;
/// ``"standing"``: slow posture changes under the body's weight) for `model` (default: the
/// built-in Drosophibot II), as ``dbot excite --kind KIND`` writes them. A list of dicts, one per
/// step table: ``name``, ``kind``, ``dt_s``, ``period_s``, ``joint_names`` (the servo joints,
/// ``Model.servo_joint_names`` order), ``goals_rad`` ([slice, joint], the table's goals),
/// ``segments`` (what each joint does when: ``joint``, ``start_s``, ``end_s``, ``motion`` and its
/// parameters) and ``table`` (the step table's bytes, checked by the rules of any gait; refused
/// with a ValueError in ``dbot excite``'s words).
#[pyfunction]
#[pyo3(signature = (kind, model = None))]
pub fn excitation<'py>(
    py: Python<'py>,
    kind: &str,
    model: Option<&Model>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let m = match model {
        Some(m) => m.inner.clone(),
        None => planner::model::builtin("drosophibot2").map_err(value_error)?,
    };
    let kind: planner::excitation::ExcitationKind = kind.parse().map_err(value_error)?;
    let (exc, tables) = py
        .detach(|| {
            let exc = planner::excitation::excitation(
                &m,
                kind,
                &planner::excitation::ExcitationOptions::default(),
            )
            .map_err(|e| e.to_string())?;
            let tables = exc
                .trials
                .iter()
                .map(|t| board::rules::build::excitation_table(&m, t).map_err(|e| e.to_string()))
                .collect::<Result<Vec<_>, _>>()?;
            Ok::<_, String>((exc, tables))
        })
        .map_err(value_error)?;
    let servo = planner::plan::table::servo_joints(&m);
    let names: Vec<String> = servo.iter().map(|&j| m.joints[j].name.clone()).collect();
    let mut out = Vec::new();
    for (t, table) in exc.trials.iter().zip(tables) {
        let d = PyDict::new(py);
        d.set_item("name", &t.name)?;
        d.set_item("kind", t.kind.name())?;
        d.set_item("dt_s", t.dt_s)?;
        d.set_item("period_s", t.period_s())?;
        d.set_item("joint_names", names.clone())?;
        let goals = Array2::from_shape_fn((t.slices(), servo.len()), |(s, k)| t.q[s][servo[k]]);
        d.set_item("goals_rad", goals.to_pyarray(py))?;
        let segments = t
            .segments
            .iter()
            .map(|s| segment(py, s))
            .collect::<PyResult<Vec<_>>>()?;
        d.set_item("segments", segments)?;
        d.set_item("table", PyBytes::new(py, table.bytes()))?;
        out.push(d);
    }
    Ok(out)
}

/// A segment as a dict: `joint`, `start_s`, `end_s`, `motion` (`ramp`, `chirp`, `posture`)
/// and the motion's parameters (as in excitation.json).
fn segment<'py>(py: Python<'py>, s: &planner::excitation::Segment) -> PyResult<Bound<'py, PyDict>> {
    use planner::excitation::Motion;
    let d = PyDict::new(py);
    d.set_item("joint", &s.joint)?;
    d.set_item("start_s", s.start_s)?;
    d.set_item("end_s", s.end_s)?;
    match s.motion {
        Motion::Ramp { from, to, speed } => {
            d.set_item("motion", "ramp")?;
            d.set_item("from", from)?;
            d.set_item("to", to)?;
            d.set_item("speed", speed)?;
        }
        Motion::Chirp {
            centre,
            amplitude_rad,
            f0_hz,
            f1_hz,
            taper_s,
        } => {
            d.set_item("motion", "chirp")?;
            d.set_item("centre", centre)?;
            d.set_item("amplitude_rad", amplitude_rad)?;
            d.set_item("f0_hz", f0_hz)?;
            d.set_item("f1_hz", f1_hz)?;
            d.set_item("taper_s", taper_s)?;
        }
        Motion::Posture { what, amplitude } => {
            d.set_item("motion", "posture")?;
            d.set_item("what", what)?;
            d.set_item("amplitude", amplitude)?;
        }
    }
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(excitation, m)?)
}
