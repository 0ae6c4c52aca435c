//! `dbot._native.InlineCore`: `VectorCore`'s robots on the calling thread (`VectorEnv(threads=0)`),
//! for one environment or a process that parallelises elsewhere (a process pool, Ray actors):
//! no worker thread, so no hand-over of every step between threads, but the GIL is held while
//! the robots run (a robot's link is not `Send`, so it cannot be stepped outside the thread that
//! holds it). `unsendable`: it stays on the Python thread that made it. The same sub-environment
//! code as the workers run (python/src/vector_sub.rs), so the results are the same bit for bit.

use std::cell::RefCell;

use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{board_error, value_error};
use crate::vector::{Job, batch, reset_jobs, run_job, step_jobs};
use crate::vector_sub::{Options, Row, SubEnv};

/// N physics robots stepped one after another on the calling thread.
#[pyclass(module = "dbot._native", unsendable)]
pub struct InlineCore {
    envs: RefCell<Option<Vec<SubEnv>>>,
    rows: RefCell<Vec<Row>>,
    joints: usize,
    gauges: usize,
}

impl std::fmt::Debug for InlineCore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InlineCore")
            .field("num_envs", &self.rows.borrow().len())
            .finish_non_exhaustive()
    }
}

impl InlineCore {
    fn run(&self, jobs: Vec<(usize, Job)>) -> PyResult<()> {
        let mut envs = self.envs.borrow_mut();
        let envs = envs
            .as_mut()
            .ok_or_else(|| board_error("the vector environment was closed"))?;
        let mut rows = self.rows.borrow_mut();
        for (i, job) in jobs {
            rows[i] = run_job(&mut envs[i], i, job).map_err(board_error)?;
        }
        Ok(())
    }
}

#[pymethods]
impl InlineCore {
    /// As `VectorCore`, without `threads`.
    #[new]
    #[pyo3(signature = (num_envs, options))]
    fn new(num_envs: usize, options: &Options) -> PyResult<Self> {
        if num_envs == 0 {
            return Err(value_error("num_envs = 0: give 1 or more"));
        }
        let model = planner::model::builtin("drosophibot2").map_err(value_error)?;
        let options = options.clone();
        Ok(Self {
            envs: RefCell::new(Some(
                (0..num_envs)
                    .map(|_| SubEnv::new(options.clone()))
                    .collect(),
            )),
            rows: RefCell::new(vec![Row::default(); num_envs]),
            joints: model.servo_chain().len(),
            gauges: model.gauges.len(),
        })
    }

    /// Sub-environments.
    #[getter]
    fn num_envs(&self) -> usize {
        self.rows.borrow().len()
    }

    /// No worker thread: 0.
    #[getter]
    fn threads(&self) -> usize {
        0
    }

    /// As `VectorCore.reset`.
    #[pyo3(signature = (mask = None, scene = None, stiffness_nm_rad = None))]
    fn reset<'py>(
        &self,
        py: Python<'py>,
        mask: Option<PyReadonlyArray1<'_, bool>>,
        scene: Option<String>,
        stiffness_nm_rad: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = self.num_envs();
        self.run(reset_jobs(n, mask, scene, stiffness_nm_rad)?)?;
        batch(py, &self.rows.borrow(), self.joints, self.gauges)
    }

    /// As `VectorCore.step`.
    #[pyo3(signature = (angles_rad, torques_nm = None, reset = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        angles_rad: PyReadonlyArray2<'_, f64>,
        torques_nm: Option<PyReadonlyArray2<'_, f64>>,
        reset: Option<PyReadonlyArray1<'_, bool>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = self.num_envs();
        self.run(step_jobs(n, self.joints, angles_rad, torques_nm, reset)?)?;
        batch(py, &self.rows.borrow(), self.joints, self.gauges)
    }

    /// Closes every robot (idempotent).
    fn close(&self) {
        self.envs.borrow_mut().take();
    }
}
