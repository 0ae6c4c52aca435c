//! `dbot.read_plan_dir(path)` and `dbot.PlanDir`: a plan directory written by `dbot plan` or
//! `dbot demo`, read by the planner's one reader (`planner::plan_dir`), as NumPy arrays; its step
//! table is the same bytes `dbot table --plan` writes.

use std::path::PathBuf;

use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::arrays::rows;
use crate::errors::{rule_error, value_error, warn_overridden};
use crate::model::Model;

/// A plan directory as read: angles, torques and stance per slice, timing, the model.
#[pyclass(frozen, module = "dbot._native")]
#[derive(Debug)]
pub struct PlanDir {
    inner: planner::plan_dir::PlanDir,
}

/// Reads the plan directory `path` (ValueError naming the file, line or format version).
#[pyfunction]
pub fn read_plan_dir(path: PathBuf) -> PyResult<PlanDir> {
    let inner = planner::plan_dir::read(&path).map_err(value_error)?;
    Ok(PlanDir { inner })
}

impl PlanDir {
    /// The step table under the library's rules (`dbot table --plan`'s).
    pub(crate) fn checked_table(
        &self,
        name: Option<&str>,
        allow_infeasible: bool,
    ) -> PyResult<::board::rules::build::CheckedTable> {
        let overrides = ::board::rules::Overrides { allow_infeasible };
        ::board::rules::build::plan_dir_table(&self.inner, name, overrides).map_err(rule_error)
    }
}

#[pymethods]
impl PlanDir {
    /// Joint angles, rad: array [slice, joint] in `joint_names` order.
    #[getter]
    fn angles<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        rows(py, &self.inner.angle)
    }

    /// Actuator torques, N m: array [slice, joint]; None when planned without dynamics.
    #[getter]
    fn torques<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        self.inner.torque.as_ref().map(|t| rows(py, t))
    }

    /// Stance flags: bool array [slice, leg] in `legs` order.
    #[getter]
    fn stance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<bool>> {
        rows(py, &self.inner.stance)
    }

    #[getter]
    fn legs(&self) -> Vec<&'static str> {
        self.inner.json.legs.iter().map(|l| l.name()).collect()
    }

    #[getter]
    fn joint_names(&self) -> Vec<String> {
        crate::model::joint_names(&self.inner.model)
    }

    /// Step period, s.
    #[getter]
    fn period_s(&self) -> f64 {
        self.inner.json.period_s
    }

    #[getter]
    fn duty(&self) -> f64 {
        self.inner.json.parameters.duty
    }

    #[getter]
    fn slices(&self) -> usize {
        self.inner.json.slices
    }

    /// The plan directory format version of the directory.
    #[getter]
    fn format_version(&self) -> u32 {
        self.inner.json.format_version
    }

    /// The gait name its step table gets by default.
    #[getter]
    fn table_name(&self) -> String {
        self.inner.table_name()
    }

    #[getter]
    fn model(&self) -> Model {
        Model {
            inner: self.inner.model.clone(),
        }
    }

    /// The step table for the board (bytes), named `name` or else `table_name`: the bytes
    /// `dbot table --plan DIR` writes, refused as it refuses (ValueError, the same words) unless
    /// `allow_infeasible` (then a UserWarning, as `--allow-infeasible` warns).
    #[pyo3(signature = (name = None, allow_infeasible = false))]
    fn step_table<'py>(
        &self,
        py: Python<'py>,
        name: Option<&str>,
        allow_infeasible: bool,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let table = self.checked_table(name, allow_infeasible)?;
        warn_overridden(py, table.warning())?;
        Ok(PyBytes::new(py, table.bytes()))
    }

    fn __repr__(&self) -> String {
        format!(
            "PlanDir(path={:?}, model={:?}, slices={}, period_s={:.4})",
            self.inner.path,
            self.inner.model.name,
            self.inner.json.slices,
            self.inner.json.period_s
        )
    }
}
