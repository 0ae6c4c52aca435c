//! `DbotEnv.step` on the physics robot in one call (`EnvStepper`): the action clipped to the
//! spaces' bounds, the setpoint exchanged for the step's bus cycles (`Board::exchange`, the same
//! exchange as `Board.stream_step`), the observation, `info` and the fall rule's verdict. Python
//! keeps the episode (steps, truncation, the reward's previous x, rendering); the general path in
//! `python/dbot/env.py` (a board, or a reward function of the user's) is the reference this one
//! is tested against, value for value.

use std::time::Duration;

use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::board::{Board, seconds};
use crate::errors::{board_error, value_error};
use crate::stream;
use crate::vector::clip_row;
use crate::vector_sub::fell;

/// One episode's step rule on a physics robot's `Board`, made by `DbotEnv` at reset.
#[pyclass(module = "dbot._native", unsendable)]
#[derive(Debug)]
pub struct EnvStepper {
    board: Py<Board>,
    low: Vec<f64>,
    high: Vec<f64>,
    /// The torques' bounds: minus and plus each servo's stall torque.
    stall_low: Vec<f64>,
    stall: Vec<f64>,
    cycles: u32,
    wait: Duration,
    strain: bool,
    fall_height_m: f64,
    fall_tilt_rad: f64,
}

/// `values` clipped as NumPy's `np.clip` does (a NaN stays NaN, for the setpoint's conversion to
/// refuse by joint), after its length is checked against the space's.
fn clipped(name: &str, values: &mut [f64], low: &[f64], high: &[f64]) -> PyResult<()> {
    if values.len() != low.len() {
        return Err(value_error(format!(
            "{name}: {} values; give one per servo joint ({})",
            values.len(),
            low.len()
        )));
    }
    clip_row(values, low, high);
    Ok(())
}

#[pymethods]
impl EnvStepper {
    /// A stepper on `board` (a physics robot): targets clipped to `[low, high]` (rad), torques
    /// to `[-stall, stall]` (N m), `cycles` bus cycles a step, each record awaited up to
    /// `timeout_s`; the strain keys observed when `strain`; a fall below `fall_height_m` or
    /// tilted past `fall_tilt_rad`.
    #[new]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (board, low, high, stall, cycles, timeout_s, strain, fall_height_m,
                        fall_tilt_rad))]
    fn new(
        board: Py<Board>,
        low: Vec<f64>,
        high: Vec<f64>,
        stall: Vec<f64>,
        cycles: u32,
        timeout_s: f64,
        strain: bool,
        fall_height_m: f64,
        fall_tilt_rad: f64,
    ) -> PyResult<Self> {
        if cycles == 0 {
            return Err(value_error("cycles = 0: give 1 or more"));
        }
        if high.len() != low.len() || stall.len() != low.len() {
            return Err(value_error(format!(
                "low, high and stall: {}, {} and {} values; give one per servo joint each",
                low.len(),
                high.len(),
                stall.len()
            )));
        }
        Ok(Self {
            board,
            low,
            high,
            stall_low: stall.iter().map(|s| -s).collect(),
            stall,
            cycles,
            wait: seconds(timeout_s, "timeout_s")?,
            strain,
            fall_height_m,
            fall_tilt_rad,
        })
    }

    /// One step: `(obs, info, x, fell)` (the observation; `info` with `time_s`, `state` and
    /// `body` as `Board.body()` gives it; the thorax's world x, m; whether the fall rule holds),
    /// or None if a record did not come (streaming stopped).
    #[pyo3(signature = (angles_rad, torques_nm = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        angles_rad: &Bound<'_, PyAny>,
        torques_nm: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let (mut angles, mut torques) = stream::vectors(angles_rad, torques_nm)?;
        clipped("angles_rad", &mut angles, &self.low, &self.high)?;
        if let Some(t) = torques.as_mut() {
            clipped("torques_nm", t, &self.stall_low, &self.stall)?;
        }
        let board = self.board.borrow(py);
        let Some(rec) = board.exchange(py, &angles, torques.as_deref(), self.cycles, self.wait)?
        else {
            return Ok(None);
        };
        let (obs, body) = board.with(py, |l| {
            let t = l.transport();
            let gauges = if self.strain { t.physics() } else { None };
            Ok((stream::observation(py, &rec, gauges), t.body()))
        })?;
        let obs = obs?;
        let body =
            body.ok_or_else(|| board_error("EnvStepper: the board has no simulated body"))?;
        let time_s = rec.time_us as f64 * 1e-6;
        board.keep_step(rec);
        let info = PyDict::new(py);
        info.set_item(intern!(py, "time_s"), time_s)?;
        info.set_item(intern!(py, "state"), intern!(py, "Streaming"))?;
        info.set_item(intern!(py, "body"), crate::body::body_dict(py, &body)?)?;
        let t = &body.thorax;
        let fell = fell(
            &t.position_m,
            &t.orientation,
            self.fall_height_m,
            self.fall_tilt_rad,
        );
        Ok(Some((obs, info, t.position_m[0], fell).into_pyobject(py)?))
    }
}
