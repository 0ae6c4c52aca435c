//! `dbot.plan(model, **params)` and `dbot.Plan`: one planned step cycle as NumPy arrays.

use std::sync::OnceLock;

use numpy::ndarray::Array3;
use numpy::{PyArray2, PyArray3, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyString};

use crate::arrays::rows;
use crate::errors::{rule_error, value_error, warn_overridden};
use crate::model::Model;
use lab::plan_dir_write::{PlanDynamics, PlanSource, write_plan_dir};

/// A planned step cycle of a model.
#[pyclass(frozen, module = "dbot._native")]
#[derive(Debug)]
pub struct Plan {
    inner: planner::plan::Plan,
    /// Inverse dynamics with `dbot plan`'s default options, solved on first use (`torques`,
    /// `step_table(torques=True)`, `strain`, `write`).
    dynamics: OnceLock<PlanDynamics>,
}

/// Plans one step cycle of `model`. `preset` names the stepping parameters to start from, as
/// `dbot plan --preset` does, and defaults to the CLI's default ([`planner::gait::DEFAULT_PRESET`],
/// `servo-safe`: table 1 at a swing the servos can follow). Keyword arguments override the preset's
/// values (fields of a parameter file: swing_s, duty, step_height_m, translation_m, rotation_rad,
/// body_height_m, gait, slices, terrain, ball_radius_m, ball_offset_m, placement). `turn_deg`
/// (thorax yaw per step, positive left) and `radius_m` (of the thorax path, positive with the
/// centre on the left; 0 with `turn_deg` turns on the spot) plan a curve as `dbot plan --turn
/// --radius` does, by the same rule ([`planner::gait::Turn::apply`]), after the other parameters.
#[pyfunction]
#[pyo3(signature = (model, *, preset = None, turn_deg = None, radius_m = None, **params))]
pub fn plan(
    model: &Model,
    preset: Option<&str>,
    turn_deg: Option<f64>,
    radius_m: Option<f64>,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Plan> {
    let preset = preset.unwrap_or(planner::gait::DEFAULT_PRESET);
    let mut base =
        planner::gait::StepParams::preset(preset, &model.inner.name).ok_or_else(|| {
            value_error(format!(
                "plan(): preset `{preset}` is not one of {} (physical-robot is for drosophibot2)",
                planner::gait::PRESETS.join(", ")
            ))
        })?;
    if let Some(params) = params {
        let text = toml::to_string(&to_toml_table(params)?).map_err(value_error)?;
        let file = planner::gait::ParamsFile::from_toml(&text, "plan() keyword arguments")
            .map_err(value_error)?;
        file.apply(&mut base);
    }
    planner::gait::Turn { turn_deg, radius_m }
        .apply(&mut base)
        .map_err(value_error)?;
    let inner = planner::plan::plan(&model.inner, &base).map_err(value_error)?;
    Ok(Plan {
        inner,
        dynamics: OnceLock::new(),
    })
}

/// Python keyword arguments as a TOML table, so the host's parameter-file parser (and its
/// errors naming the field) does the checking.
fn to_toml_table(d: &Bound<'_, PyDict>) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        t.insert(key.clone(), to_toml_value(&key, &v)?);
    }
    Ok(t)
}

fn to_toml_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        Ok(toml::Value::Boolean(v.extract()?))
    } else if v.is_instance_of::<PyInt>() {
        Ok(toml::Value::Integer(v.extract()?))
    } else if v.is_instance_of::<PyFloat>() {
        Ok(toml::Value::Float(v.extract()?))
    } else if v.is_instance_of::<PyString>() {
        Ok(toml::Value::String(v.extract()?))
    } else if let Ok(d) = v.cast::<PyDict>() {
        Ok(toml::Value::Table(to_toml_table(d)?))
    } else if let Ok(x) = v.extract::<f64>() {
        // NumPy scalars and other numbers.
        Ok(toml::Value::Float(x))
    } else {
        Err(value_error(format!(
            "plan(): parameter `{key}` has an unsupported type {}",
            v.get_type().name()?
        )))
    }
}

impl Plan {
    /// The step table under the library's rules (see the Python method `step_table`).
    pub(crate) fn checked_table(
        &self,
        py: Python<'_>,
        name: &str,
        torques: bool,
        allow_infeasible: bool,
    ) -> PyResult<::board::rules::build::CheckedTable> {
        let tau = if torques {
            Some(py.detach(|| self.solved().map(|d| d.torque.clone()))?)
        } else {
            None
        };
        let overrides = ::board::rules::Overrides { allow_infeasible };
        ::board::rules::build::plan_table(&self.inner, tau.as_deref(), name, overrides)
            .map_err(rule_error)
    }

    /// The plan's inverse dynamics (`dbot plan`'s default options), solved once.
    fn solved(&self) -> PyResult<&PlanDynamics> {
        if let Some(d) = self.dynamics.get() {
            return Ok(d);
        }
        let options = planner::dynamics::DynamicsOptions::default();
        let d =
            PlanDynamics::solve(&self.inner, options).map_err(|e| value_error(e.chain_text()))?;
        Ok(self.dynamics.get_or_init(|| d))
    }
}

#[pymethods]
impl Plan {
    /// Joint angles, rad: array [slice, joint] in `joint_names` order.
    #[getter]
    fn angles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, &self.inner.q)
    }

    /// Joint velocities, rad/s: array [slice, joint].
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, &self.inner.qd)
    }

    /// Joint accelerations, rad/s^2: array [slice, joint].
    #[getter]
    fn accelerations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, &self.inner.qdd)
    }

    /// Stance flags: bool array [slice, leg] in `legs` order.
    #[getter]
    fn stance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<bool>> {
        rows(py, &self.inner.stance)
    }

    /// Foot targets in the thorax frame, m: array [slice, leg, xyz].
    #[getter]
    fn feet<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let f = &self.inner.feet;
        let cols = f.first().map_or(0, Vec::len);
        Array3::from_shape_fn((f.len(), cols, 3), |(i, j, k)| f[i][j][k]).to_pyarray(py)
    }

    /// Actuator torques from the inverse dynamics (floating base, the paper's problem), N m:
    /// array [slice, joint]. Solved on first access.
    #[getter]
    fn torques<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let t = py.detach(|| self.solved().map(|d| d.torque.clone()))?;
        Ok(rows(py, &t))
    }

    #[getter]
    fn legs(&self) -> Vec<&'static str> {
        self.inner.legs.iter().map(|l| l.name()).collect()
    }

    #[getter]
    fn joint_names(&self) -> Vec<String> {
        crate::model::joint_names(&self.inner.model)
    }

    /// Start of each leg's cycle, fraction of the period, in `legs` order.
    #[getter]
    fn phases(&self) -> Vec<f64> {
        self.inner.phases.clone()
    }

    /// Slice duration, s.
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt
    }

    /// Step period, s.
    #[getter]
    fn period_s(&self) -> f64 {
        self.inner.period_s
    }

    #[getter]
    fn duty(&self) -> f64 {
        self.inner.params.duty
    }

    #[getter]
    fn slices(&self) -> usize {
        self.inner.slices()
    }

    /// Predicted strain of every gauge of the model (docs/strain.md), microstrain: array
    /// [slice, gauge] in `gauge_names` order, from the inverse dynamics (floating base, the
    /// paper's problem), solved once. Width 0 for a model without gauges.
    #[getter]
    fn strain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = py.detach(|| self.solved().and_then(|d| predicted_strain(&self.inner, d)))?;
        Ok(rows(py, &s))
    }

    /// The model's gauges, e.g. `LF_troch_axial`, in the order of `strain`'s columns (for the
    /// built-in Drosophibot II, the strain board's channel order).
    #[getter]
    fn gauge_names(&self) -> Vec<String> {
        self.inner
            .model
            .gauges
            .iter()
            .map(|g| g.name.clone())
            .collect()
    }

    #[getter]
    fn model(&self) -> Model {
        Model {
            inner: self.inner.model.clone(),
        }
    }

    /// The step table for the board (bytes): servo joints, angles and, with `torques=True`, the
    /// planned torques as the bias feed-forward. Refused (ValueError, the words of `dbot table`)
    /// when a servo cannot follow the plan, unless `allow_infeasible` (then a UserWarning).
    #[pyo3(signature = (name = "dbot-gait", torques = false, allow_infeasible = false))]
    fn step_table<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        torques: bool,
        allow_infeasible: bool,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let table = self.checked_table(py, name, torques, allow_infeasible)?;
        warn_overridden(py, table.warning())?;
        Ok(PyBytes::new(py, table.bytes()))
    }

    /// Writes the plan directory `dbot plan` writes (plan.json, model.toml, model.urdf,
    /// joints.csv, feet.csv, the plots, feasibility.md, README.md and with `dynamics` the torque
    /// columns, joint_forces.csv, torques.png, grf.png and the predicted strain) into `dir`,
    /// created if missing; every file replaced whole. `name` is the gait name its step table gets
    /// (at most 16 bytes; default: the directory's name). Returns the file names.
    #[pyo3(signature = (dir, *, name = None, dynamics = true))]
    fn write(
        &self,
        py: Python<'_>,
        dir: std::path::PathBuf,
        name: Option<&str>,
        dynamics: bool,
    ) -> PyResult<Vec<&'static str>> {
        if let Some(n) = name.filter(|n| n.len() > protocol::gait::NAME_LEN) {
            return Err(value_error(format!(
                "write(): name `{n}`: a gait name has at most {} bytes",
                protocol::gait::NAME_LEN
            )));
        }
        let d = if dynamics { Some(self.solved()?) } else { None };
        let source = PlanSource {
            model_source: &self.inner.model.name,
            table_name: name,
            spring: None,
        };
        let written = py
            .detach(|| write_plan_dir(&dir, &self.inner, &source, d))
            .map_err(|e| value_error(e.chain_text()))?;
        Ok(written.files)
    }

    fn __repr__(&self) -> String {
        format!(
            "Plan(model={:?}, slices={}, period_s={:.4}, duty={})",
            self.inner.model.name,
            self.inner.slices(),
            self.inner.period_s,
            self.inner.params.duty
        )
    }
}

/// `microstrain[slice][gauge]` of a plan from its solved cycle.
fn predicted_strain(plan: &planner::plan::Plan, d: &PlanDynamics) -> PyResult<Vec<Vec<f64>>> {
    let strain = planner::strain::predict_plan(plan, &d.cycle).map_err(value_error)?;
    Ok(strain.microstrain())
}
