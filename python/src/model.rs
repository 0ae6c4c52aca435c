//! `dbot.Model`: an organism model (built-in, TOML file or AnimatLab project).

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{PyArray2, ToPyArray};
use pyo3::prelude::*;

use crate::errors::value_error;

/// An organism model: bodies, joints, feet and the servo map.
#[pyclass(frozen, module = "dbot._native")]
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) inner: planner::model::Model,
}

/// Every joint's name in model order (`Model`, `Plan` and `PlanDir.joint_names`).
pub fn joint_names(model: &planner::model::Model) -> Vec<String> {
    model.joints.iter().map(|j| j.name.clone()).collect()
}

#[pymethods]
impl Model {
    /// A built-in model by name (`dbot.BUILTIN_MODELS`).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<Self> {
        planner::model::builtin(name)
            .map(|inner| Self { inner })
            .map_err(value_error)
    }

    /// A model from a `.toml` model file or an AnimatLab `.aproj` project.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        let is_aproj = path.extension().is_some_and(|e| e == "aproj");
        let inner = if is_aproj {
            planner::model::import_aproj_file(&path, &planner::model::ImportOptions::default())
        } else {
            planner::model::load(&path)
        };
        inner.map(|inner| Self { inner }).map_err(value_error)
    }

    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Every joint's full name (`LF_ThC1`, ...), in model order: the columns of `Plan.angles`.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        joint_names(&self.inner)
    }

    /// Names of the joints with a servo, in the board's joint-map order: the columns of setpoints,
    /// telemetry and proprioception.
    #[getter]
    fn servo_joint_names(&self) -> Vec<String> {
        planner::plan::table::servo_joints(&self.inner)
            .into_iter()
            .map(|j| self.inner.joints[j].name.clone())
            .collect()
    }

    /// Indices into `joint_names` of the servo joints (so `angles[:, model.servo_joints]`).
    #[getter]
    fn servo_joints(&self) -> Vec<usize> {
        planner::plan::table::servo_joints(&self.inner)
    }

    /// Stall torque of each servo joint's actuator, N m, `servo_joint_names` order (the MJCF
    /// export's force limit: the e-manual's 12 V stall torque; infinite for a generic actuator).
    #[getter]
    fn servo_stall_torques_nm(&self) -> Vec<f64> {
        planner::plan::table::servo_joints(&self.inner)
            .into_iter()
            .map(|j| match self.inner.joints[j].actuation {
                planner::model::Actuation::Actuated {
                    actuator,
                    stiffness,
                } => planner::model::servo_actuator(actuator, stiffness).stall_nm,
                planner::model::Actuation::Fixed { .. } => 0.0,
            })
            .collect()
    }

    /// Legs of the model (`LF`, ...), in foot order.
    #[getter]
    fn legs(&self) -> Vec<&'static str> {
        self.inner.feet.iter().map(|f| f.leg.name()).collect()
    }

    /// Joint limits, rad: array [joint, 2] of (lower, upper), model order.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let n = self.inner.joints.len();
        let a = Array2::from_shape_fn((n, 2), |(j, k)| {
            let (lo, hi) = self.inner.joints[j].limits;
            if k == 0 { lo } else { hi }
        });
        a.to_pyarray(py)
    }

    /// Total mass, kg.
    #[getter]
    fn mass_kg(&self) -> f64 {
        self.inner.total_mass()
    }

    fn __repr__(&self) -> String {
        format!(
            "Model(name={:?}, joints={}, servos={})",
            self.inner.name,
            self.inner.joints.len(),
            planner::plan::table::servo_joints(&self.inner).len()
        )
    }
}
