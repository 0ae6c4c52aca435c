//! `dbot.Model`: an organism model (built-in, TOML file or AnimatLab project).

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{PyArray2, PyArrayDyn, PyReadonlyArrayDyn, ToPyArray};
use pyo3::prelude::*;

use crate::errors::value_error;

/// An organism model: bodies, joints, feet and the servo map.
#[pyclass(frozen, module = "dbot._native")]
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) inner: planner::model::Model,
}

/// Register values as floats: a float or integer array (or sequence) of any shape.
fn registers(v: &Bound<'_, PyAny>) -> PyResult<numpy::ndarray::ArrayD<f64>> {
    if let Ok(a) = v.extract::<PyReadonlyArrayDyn<'_, f64>>() {
        return Ok(a.as_array().to_owned());
    }
    if let Ok(a) = v.extract::<PyReadonlyArrayDyn<'_, i32>>() {
        return Ok(a.as_array().mapv(f64::from));
    }
    if let Ok(a) = v.extract::<PyReadonlyArrayDyn<'_, i64>>() {
        return Ok(a.as_array().mapv(|x| x as f64));
    }
    if let Ok(a) = v.extract::<Vec<f64>>() {
        return Ok(numpy::ndarray::Array1::from(a).into_dyn());
    }
    Err(value_error(
        "load_torques_nm: load_raw: give an array of register values (float or integer)",
    ))
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

    /// Servo torques estimated from register 126 values (`load_raw` of proprioception or of the
    /// environment's observation), N m: an array of `load_raw`'s shape, its last axis the servo
    /// joints (`servo_joint_names` order). An ESTIMATE (`dynamixel::units::load_to_torque_nm`, as
    /// `dbot record`'s `torque_estimate_nm`): MX-28 Present Load (0.1 % of maximum, itself
    /// estimated by the servo) times its stall torque; MX-64 Present Current (3.36 mA/unit) times
    /// stall torque / stall current. Sign: the register's (the servo's direction). NaN for a
    /// joint driven by a generic actuator (no servo). ValueError if the last axis is not the
    /// servo count or a value is not a register value (an integer in -32768..32767).
    fn load_torques_nm<'py>(
        &self,
        py: Python<'py>,
        load_raw: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let a = registers(load_raw)?;
        let joints = planner::plan::table::servo_joints(&self.inner);
        let shape = a
            .shape()
            .iter()
            .map(usize::to_string)
            .collect::<Vec<_>>()
            .join(", ");
        if a.ndim() == 0 || a.shape()[a.ndim() - 1] != joints.len() {
            return Err(value_error(format!(
                "load_torques_nm: load_raw has shape ({shape}); its last axis must be the {} servo \
                 joints of {}",
                joints.len(),
                self.inner.name
            )));
        }
        let servos: Vec<Option<protocol::ServoModel>> = joints
            .iter()
            .map(|&j| match self.inner.joints[j].actuation {
                planner::model::Actuation::Actuated { actuator, .. } => actuator.servo(),
                planner::model::Actuation::Fixed { .. } => None,
            })
            .collect();
        let mut out = a;
        let last = numpy::ndarray::Axis(out.ndim() - 1);
        for mut lane in out.lanes_mut(last) {
            for (k, v) in lane.iter_mut().enumerate() {
                let raw = *v;
                if raw.fract() != 0.0 || !(-32768.0..=32767.0).contains(&raw) {
                    return Err(value_error(format!(
                        "load_torques_nm: load_raw {raw} of {} is not a register value (an \
                         integer in -32768..32767)",
                        self.inner.joints[joints[k]].name
                    )));
                }
                *v = servos[k].map_or(f64::NAN, |m| {
                    f64::from(dynamixel::units::load_to_torque_nm(m, raw as i16))
                });
            }
        }
        Ok(out.to_pyarray(py))
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
