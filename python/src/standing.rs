//! `dbot.plan_standing(model)`: the planner's solution of the robot standing still on flat ground
//! in the physics robot's resting posture (joint angles, actuator torques, foot forces, predicted
//! gauge strain), the prediction the `strain` block of docs/validation.md compares the simulated
//! gauges with (`lab::validation::strain::standing`, the same calls).

use numpy::ToPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;
use crate::model::Model;

/// The robot standing still, all feet down, on flat ground in the posture the physics robot starts
/// in (`physics::PhysicsRobot::options(model, flat).stance_q`, the planner's resting posture), its
/// dynamics solved as a plan's slice is (floating base, QP foot forces of least elastic energy).
/// A dict: `angles_rad` and `torques_nm` (servo joints, `Model.servo_joint_names` order: the
/// setpoint of the standing robot with the torque bias), `foot_force_n` ([foot, xyz], N, the
/// model's foot order), `gauge_names` and `strain_microstrain` (the gauges' predicted readings).
#[pyfunction]
pub fn plan_standing<'py>(py: Python<'py>, model: &Model) -> PyResult<Bound<'py, PyDict>> {
    let m = &model.inner;
    let (q, sol, readings) = py
        .detach(|| {
            let options = physics::PhysicsRobot::options(m, &planner::terrain::Ground::Flat)
                .map_err(|e| e.to_string())?;
            let q = options.stance_q;
            let still = planner::dynamics::SliceInput::still(m, q.clone());
            let sol = planner::dynamics::solve_slice(
                m,
                &still,
                &planner::dynamics::DynamicsOptions::default(),
                0,
            )
            .map_err(|e| e.to_string())?;
            let sites = planner::strain::sites(m).map_err(|e| e.to_string())?;
            let readings = planner::strain::slice_readings(m, &sites, &still, &sol.grf);
            Ok::<_, String>((q, sol, readings))
        })
        .map_err(|e| value_error(format!("plan_standing({}): {e}", m.name)))?;
    let servo = planner::plan::table::servo_joints(m);
    let d = PyDict::new(py);
    d.set_item(
        "angles_rad",
        Array1::from_iter(servo.iter().map(|&j| q[j])).to_pyarray(py),
    )?;
    d.set_item(
        "torques_nm",
        Array1::from_iter(servo.iter().map(|&j| sol.torque[j])).to_pyarray(py),
    )?;
    d.set_item(
        "foot_force_n",
        Array2::from_shape_fn((sol.grf.len(), 3), |(i, k)| sol.grf[i][k]).to_pyarray(py),
    )?;
    d.set_item(
        "gauge_names",
        m.gauges.iter().map(|g| g.name.clone()).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "strain_microstrain",
        Array1::from_iter(readings.iter().map(|r| r.microstrain)).to_pyarray(py),
    )?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(plan_standing, m)?)
}
