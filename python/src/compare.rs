//! `dbot.compare(a, b, out)`: two plan directories or trials DoF by DoF, as `dbot compare A B`
//! (`lab::plan_comparison::compare_dirs`: the same rows, compare.csv and plots).

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

/// Per common DoF of `a` and `b` (plan directories or trial folders, in any mix) the R^2 of a
/// linear regression of the angles and of the torques; writes compare.csv and the overlay plots
/// into `out` (created if missing). One dict per row: `leg`, `dof`, `summed_in` (`"A"`, `"B"` or
/// `""`), `r2_angle`, `r2_torque` (None where no regression fits).
#[pyfunction]
pub fn compare<'py>(
    py: Python<'py>,
    a: PathBuf,
    b: PathBuf,
    out: PathBuf,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let rows = py
        .detach(|| {
            std::fs::create_dir_all(&out)
                .map_err(|e| lab::LabError::invalid(format!("creating {}: {e}", out.display())))?;
            lab::plan_comparison::compare_dirs(&a, &b, &out)
        })
        .map_err(|e| value_error(e.chain_text()))?;
    rows.iter()
        .map(|r| {
            let d = PyDict::new(py);
            d.set_item("leg", r.leg.name())?;
            d.set_item("dof", &r.dof)?;
            d.set_item("summed_in", lab::plan_comparison::summed_in(r))?;
            d.set_item("r2_angle", r.r2_angle)?;
            d.set_item("r2_torque", r.r2_torque)?;
            Ok(d)
        })
        .collect()
}
