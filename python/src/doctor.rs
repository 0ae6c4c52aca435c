//! `dbot.doctor()`: the bring-up check of `dbot doctor` (`lab::doctor`), the same items in the
//! same words: printed as the CLI prints them, and returned.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;
use crate::model::Model;

/// Checks a freshly wired robot, as `dbot doctor` does: the board on `port` (found, its versions
/// and state), every servo of `model` (default: the built-in Drosophibot II) on the servo bus
/// (`bus`: a U2D2's serial port or `dbot sim-bus`'s link; for the `virtual` and `physics` robots
/// their own bus) at `baud` (default: the board's bus rate), the supply voltage read from the
/// servos, and the strain board on `strain` (`"virtual"` or a serial port). Prints the items
/// (unless `quiet`) and returns `{"ok": bool, "items": [{"name", "outcome" ("pass", "fail" or
/// "not checked"), "detail", "fix"}], "text": str}`; `ok` is False when anything failed.
#[pyfunction]
#[pyo3(signature = (port = None, bus = None, baud = None, strain = None, strain_seconds = 2.0, model = None, quiet = false))]
#[allow(clippy::too_many_arguments)]
pub fn doctor<'py>(
    py: Python<'py>,
    port: Option<String>,
    bus: Option<String>,
    baud: Option<u32>,
    strain: Option<String>,
    strain_seconds: f64,
    model: Option<PyRef<'py, Model>>,
    quiet: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if !(strain_seconds.is_finite() && strain_seconds > 0.0) {
        return Err(value_error(format!(
            "strain_seconds {strain_seconds}: must be a number above 0"
        )));
    }
    let model = match model {
        Some(m) => m.inner.clone(),
        None => planner::model::builtin("drosophibot2").map_err(value_error)?,
    };
    let options = lab::doctor::Options {
        port,
        bus,
        baud,
        strain,
        strain_seconds,
    };
    let report = py.detach(|| lab::doctor::run(&model, &options));
    let text = report.text();
    if !quiet {
        print!("{text}");
    }
    let items = report
        .items
        .iter()
        .map(|i| {
            let d = PyDict::new(py);
            d.set_item("name", &i.name)?;
            d.set_item(
                "outcome",
                match i.outcome {
                    lab::doctor::Outcome::Pass => "pass",
                    lab::doctor::Outcome::Fail => "fail",
                    lab::doctor::Outcome::NotChecked => "not checked",
                },
            )?;
            d.set_item("detail", &i.detail)?;
            d.set_item("fix", &i.fix)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let out = PyDict::new(py);
    out.set_item("ok", report.ok())?;
    out.set_item("items", items)?;
    out.set_item("text", text)?;
    Ok(out)
}
