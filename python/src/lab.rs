//! `dbot.physics_walk(...)` and `dbot.walk_figures(walk)`: a walk the user runs themselves (a plan
//! directory's gait on a fresh physics robot, `lab::plan_walk`) and the figures `dbot demo`
//! prints for it, computed by the same functions (`lab`), so the numbers are the demo's; and
//! `dbot.compare_strain(trial, plan_dir)`, a recording's strain against the plan's prediction.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

/// A recorded walk of a plan directory's gait on the physics robot.
#[pyclass(frozen, module = "dbot._native")]
#[derive(Debug)]
pub struct PhysicsWalk {
    inner: lab::plan_walk::PlanWalk,
}

/// Walks the gait of the plan directory `plan_dir` (written by `dbot plan` or `dbot demo`) for
/// `steps` steps on a fresh physics robot on `scene`, recording into `out` (telemetry.csv and
/// plots). ValueError naming the file or the step count.
#[pyfunction]
#[pyo3(signature = (plan_dir, steps, out, backward = false, scene = "flat"))]
pub fn physics_walk(
    py: Python<'_>,
    plan_dir: PathBuf,
    steps: u32,
    out: PathBuf,
    backward: bool,
    scene: &str,
) -> PyResult<PhysicsWalk> {
    let direction = if backward {
        protocol::Direction::Backward
    } else {
        protocol::Direction::Forward
    };
    let scene = planner::terrain::Ground::parse(scene).map_err(|e| value_error(e.to_string()))?;
    let inner = py
        .detach(|| {
            lab::plan_walk::walk_plan_dir(&plan_dir, &scene, steps, direction, &out, || false)
        })
        .map_err(|e| value_error(e.chain_text()))?;
    Ok(PhysicsWalk { inner })
}

#[pymethods]
impl PhysicsWalk {
    /// Steps played.
    #[getter]
    fn steps(&self) -> u32 {
        self.inner.steps
    }

    /// Bus cycles recorded.
    #[getter]
    fn cycles(&self) -> usize {
        self.inner.walk.rec.cycles()
    }

    /// Simulated seconds recorded.
    #[getter]
    fn duration_s(&self) -> f64 {
        self.inner.walk.rec.duration_s()
    }

    fn __repr__(&self) -> String {
        format!(
            "PhysicsWalk({} steps {}, {} cycles)",
            self.inner.steps,
            self.inner.walk.label,
            self.inner.walk.rec.cycles()
        )
    }
}

/// The figures `dbot demo` prints for a walk: a dict of the body's distance per step against the
/// plan, heading, thorax height, tilt, slip per foot, tracking error per leg and the servo loads'
/// fit to the planned torques (R^2 of the plan's prediction, RMS difference), in SI units.
#[pyfunction]
pub fn walk_figures<'py>(py: Python<'py>, walk: &PhysicsWalk) -> PyResult<Bound<'py, PyDict>> {
    let f = lab::plan_walk::walk_figures(&walk.inner).ok_or_else(|| {
        value_error("the walk has no body: it was not walked on the physics robot")
    })?;
    let d = PyDict::new(py);
    d.set_item("distance_per_step_m", f.distance.per_step_m)?;
    d.set_item("planned_per_step_m", f.distance.planned_m)?;
    d.set_item("distance_off_percent", f.distance.off_percent)?;
    d.set_item("stroke_m", walk.inner.translation_m)?;
    d.set_item("lateral_m", f.body.lateral_m)?;
    d.set_item("heading_rad", f.body.heading_rad)?;
    d.set_item("height_start_m", f.body.height_start_m)?;
    d.set_item("height_min_m", f.body.height_min_m)?;
    d.set_item("height_end_m", f.body.height_end_m)?;
    d.set_item("tilt_max_rad", f.body.tilt_max_rad)?;
    let slip = PyDict::new(py);
    for (leg, m) in &f.body.slip_m {
        slip.set_item(leg.name(), m)?;
    }
    d.set_item("slip_m", slip)?;
    let tracking = PyDict::new(py);
    for t in &f.tracking {
        let row = PyDict::new(py);
        row.set_item("rms_rad", t.rms_rad)?;
        row.set_item("max_abs_rad", t.max_abs_rad)?;
        row.set_item("joints", t.joints)?;
        tracking.set_item(t.leg.name(), row)?;
    }
    d.set_item("tracking", tracking)?;
    let loads = PyDict::new(py);
    for l in &f.loads {
        let row = PyDict::new(py);
        row.set_item("r2", l.r2)?;
        row.set_item("rms_nm", l.rms)?;
        row.set_item("samples", l.samples)?;
        loads.set_item(&l.name, row)?;
    }
    d.set_item("loads", loads)?;
    Ok(d)
}

/// Adds the lab's classes and functions to the module.
/// A trial's strain (recorded with `strain=` / `dbot record --strain`) against the prediction of
/// the plan directory `plan_dir`, per gauge, as `dbot compare --strain` computes it
/// (`lab::strain_compare`): a list of dicts with `gauge`, `samples`, `r2` (over the step phase)
/// and `gain` (counts per predicted microstrain) and `rms_residual_counts` (None where there is
/// no value), `reading` (`calibrated`: the plan model's calibration file has the gauge, else
/// `ESTIMATE`), `reading_gain` (its counts per microstrain) and `rms_microstrain` (the recorded
/// strain through that gain against the prediction). ValueError naming the file.
#[pyfunction]
pub fn compare_strain<'py>(
    py: Python<'py>,
    trial: PathBuf,
    plan_dir: PathBuf,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let fits = py
        .detach(|| lab::strain_compare::compare_trial(&trial, &plan_dir))
        .map_err(|e| value_error(e.chain_text()))?;
    fits.iter()
        .map(|f| {
            let d = PyDict::new(py);
            d.set_item("gauge", &f.gauge)?;
            d.set_item("samples", f.samples)?;
            d.set_item("r2", f.r2)?;
            d.set_item("gain", f.gain)?;
            d.set_item("rms_residual_counts", f.rms_residual_counts)?;
            d.set_item("reading", f.reading.word())?;
            d.set_item("reading_gain", f.reading_gain)?;
            d.set_item("rms_microstrain", f.rms_microstrain)?;
            Ok(d)
        })
        .collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PhysicsWalk>()?;
    m.add_function(wrap_pyfunction!(physics_walk, m)?)?;
    m.add_function(wrap_pyfunction!(walk_figures, m)?)?;
    m.add_function(wrap_pyfunction!(compare_strain, m)?)?;
    Ok(())
}
