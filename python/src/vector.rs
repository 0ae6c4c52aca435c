//! `dbot._native.VectorCore`: N physics robots (the firmware library over the simulated bus
//! moving a MuJoCo body, each its own `physics::Robot`), the engine under `dbot.env.VectorEnv`
//! (python/dbot/vector_env.py, which keeps the Gymnasium side: spaces, autoreset, infos). They
//! step on worker threads with the GIL released or, with `threads = 0`, on the calling thread
//! with the GIL held (no hand-over of every step between threads: the cheapest for one robot or
//! a process that parallelises elsewhere, a process pool or Ray actors).
//!
//! A robot's link is not `Send` (its simulated wire is single-threaded), so each robot is opened
//! on the thread that owns it and stays there: sub-environment `i` lives on worker
//! `i % threads`, or with `threads = 0` on the Python thread that made the core (`unsendable`:
//! the core stays on that thread). Every sub-environment runs the same calls in the same order
//! on its own robot whatever the thread count, and nothing is shared between robots, so results
//! are bit-identical for any thread count, 0 included.
//!
//! The reset and the step are those of `dbot.env.DbotEnv` on the physics robot, call for call on
//! the link (each `Board.status()` of the Python class is the same three requests here:
//! `vector_sub::status`), so a sub-environment equals `DbotEnv` step by step
//! (python/tests/test_vector_env.py checks it against `SyncVectorEnv`).

use std::cell::RefCell;
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use numpy::{PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::arrays::written;
use crate::errors::{board_error, value_error};
use crate::vector_sub::{Options, Row, SubEnv};

/// What one sub-environment does in a batch.
enum Job {
    /// Reset (a scene replaces the kept one; a stiffness holds for this episode).
    Reset {
        scene: Option<String>,
        stiffness: Option<f64>,
    },
    /// Step with these joint targets (rad, already clipped) and torques (N m).
    Step {
        angles: Vec<f64>,
        torques: Option<Vec<f64>>,
    },
}

/// A worker's share of a batch: (sub-environment, job).
type Batch = Vec<(usize, Job)>;
/// A worker's answer: (sub-environment, its row or what went wrong).
type Answer = Vec<(usize, Result<Row, String>)>;

/// The worker threads and their mailboxes.
struct Workers {
    to: Vec<Sender<Batch>>,
    from: Receiver<Answer>,
    handles: Vec<JoinHandle<()>>,
}

/// Where the robots run (None inside: closed).
enum Engine {
    /// On worker threads, the GIL released.
    Threads(Mutex<Option<Workers>>),
    /// One after another on the calling thread, the GIL held (`threads = 0`).
    Inline(RefCell<Option<Vec<SubEnv>>>),
}

/// N physics robots on worker threads or on the calling thread.
#[pyclass(module = "dbot._native", unsendable)]
pub struct VectorCore {
    engine: Engine,
    num_envs: usize,
    threads: usize,
    /// Each sub-environment's latest row (what a batch that skips it returns).
    rows: RefCell<Vec<Row>>,
    joints: usize,
    gauges: usize,
    /// The bounds actions are clipped to (`np.clip`'s rule), when given.
    limits: Option<Limits>,
    /// The observation's keys in the observation space's order (`step_env`'s dict).
    obs_keys: Vec<String>,
    /// Which sub-environments ended at the last `step_env` (next-step autoreset: the next step
    /// resets them).
    autoreset: RefCell<Vec<bool>>,
}

/// The action space's bounds: joint targets in [low, high], torques in [-stall, stall].
#[derive(Debug, Clone)]
struct Limits {
    low: Vec<f64>,
    high: Vec<f64>,
    stall: Vec<f64>,
}

/// `np.clip(x, lo, hi)` as NumPy computes it, `minimum(maximum(x, lo), hi)`: a NaN stays NaN.
fn clip(x: f64, lo: f64, hi: f64) -> f64 {
    let y = if x < lo { lo } else { x };
    if y > hi { hi } else { y }
}

/// Each of `values` clipped to its `[lo, hi]` ([`clip`]; the slices are equally long).
pub(crate) fn clip_row(values: &mut [f64], lo: &[f64], hi: &[f64]) {
    for ((v, &lo), &hi) in values.iter_mut().zip(lo).zip(hi) {
        *v = clip(*v, lo, hi);
    }
}

/// The message when the core was closed.
const CLOSED: &str = "the vector environment was closed";

/// `threads` workers, each to build its sub-environments with `options`.
fn spawn(threads: usize, options: &Options) -> PyResult<Workers> {
    let (answer_to, from) = channel();
    let mut to = Vec::new();
    let mut handles = Vec::new();
    for t in 0..threads {
        let (tx, rx) = channel();
        let answers = answer_to.clone();
        let opts = options.clone();
        let h = std::thread::Builder::new()
            .name(format!("dbot-vector-{t}"))
            .spawn(move || worker(opts, rx, answers))
            .map_err(board_error)?;
        to.push(tx);
        handles.push(h);
    }
    Ok(Workers { to, from, handles })
}

fn worker(options: Options, batches: Receiver<Batch>, answers: Sender<Answer>) {
    let mut envs: std::collections::HashMap<usize, SubEnv> = std::collections::HashMap::new();
    while let Ok(batch) = batches.recv() {
        let mut out = Vec::with_capacity(batch.len());
        for (i, job) in batch {
            let env = envs
                .entry(i)
                .or_insert_with(|| SubEnv::new(options.clone()));
            out.push((i, run_job(env, i, job)));
        }
        if answers.send(out).is_err() {
            return;
        }
    }
}

impl std::fmt::Debug for VectorCore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("VectorCore")
            .field("num_envs", &self.num_envs)
            .field("threads", &self.threads)
            .finish_non_exhaustive()
    }
}

impl VectorCore {
    /// Runs `jobs` (at most one per sub-environment, in sub-environment order) and keeps the rows
    /// they give: on the workers with the GIL released, or here.
    fn run(&self, py: Python<'_>, jobs: Vec<(usize, Job)>) -> PyResult<()> {
        let workers = match &self.engine {
            Engine::Threads(workers) => workers,
            Engine::Inline(envs) => {
                let mut envs = envs.borrow_mut();
                let envs = envs.as_mut().ok_or_else(|| board_error(CLOSED))?;
                let mut rows = self.rows.borrow_mut();
                for (i, job) in jobs {
                    rows[i] = run_job(&mut envs[i], i, job).map_err(board_error)?;
                }
                return Ok(());
            }
        };
        let threads = self.threads;
        let answers = py.detach(|| -> Result<Vec<(usize, Row)>, String> {
            let guard = workers.lock().unwrap_or_else(|e| e.into_inner());
            let w = guard.as_ref().ok_or(CLOSED)?;
            let mut batches: Vec<Batch> = (0..threads).map(|_| Vec::new()).collect();
            for (i, job) in jobs {
                batches[i % threads].push((i, job));
            }
            let mut sent = 0;
            for (t, batch) in batches.into_iter().enumerate() {
                if !batch.is_empty() {
                    w.to[t].send(batch).map_err(|_| "a worker thread stopped")?;
                    sent += 1;
                }
            }
            let mut rows = Vec::new();
            let mut first_error = None;
            for _ in 0..sent {
                let answer = w.from.recv().map_err(|_| "a worker thread stopped")?;
                for (i, r) in answer {
                    match r {
                        Ok(row) => rows.push((i, row)),
                        Err(e) => first_error = first_error.or(Some((i, e))),
                    }
                }
            }
            // The lowest failing sub-environment, whatever the thread count.
            if let Some((_, e)) = first_error {
                return Err(e);
            }
            Ok(rows)
        });
        let answers = answers.map_err(board_error)?;
        let mut rows = self.rows.borrow_mut();
        for (i, row) in answers {
            rows[i] = row;
        }
        Ok(())
    }
}

/// `k` values of each row side by side as an N x k array (a row short of `k`: NaN).
fn mat<'py>(
    py: Python<'py>,
    rows: &[Row],
    k: usize,
    g: impl Fn(&Row) -> &[f64],
) -> Bound<'py, PyArray2<f64>> {
    // Written straight into NumPy's array (no vector in between: eight of these a step).
    written(py, [rows.len(), k], |cells: &mut [f64]| {
        for (row, r) in cells.chunks_exact_mut(k.max(1)).zip(rows) {
            let v = g(r);
            if v.len() == k {
                row.copy_from_slice(v);
            } else {
                for (j, c) in row.iter_mut().enumerate() {
                    *c = v.get(j).copied().unwrap_or(f64::NAN);
                }
            }
        }
    })
}

/// One value of each row as an array of N.
fn col<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: &[Row],
    g: impl Fn(&Row) -> T,
) -> Bound<'py, PyArray1<T>> {
    let v: Vec<T> = rows.iter().map(g).collect();
    PyArray1::from_slice(py, &v)
}

/// The observation's array under `key` (None: not an observation key).
fn observed<'py>(
    py: Python<'py>,
    rows: &[Row],
    key: &str,
    joints: usize,
    gauges: usize,
) -> Option<Bound<'py, PyArray2<f64>>> {
    Some(match key {
        "present_rad" => mat(py, rows, joints, |r| &r.present),
        "velocity_rad_s" => mat(py, rows, joints, |r| &r.velocity),
        "load_raw" => mat(py, rows, joints, |r| &r.load),
        "setpoint_age" => mat(py, rows, 1, |r| std::slice::from_ref(&r.setpoint_age)),
        "strain_microstrain" => mat(py, rows, gauges, |r| &r.strain),
        "strain_age_s" => mat(py, rows, 1, |r| std::slice::from_ref(&r.strain_age_s)),
        _ => return None,
    })
}

/// Every sub-environment's latest row as a dict of arrays (first axis: sub-environment).
fn batch<'py>(
    py: Python<'py>,
    rows: &[Row],
    joints: usize,
    gauges: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let mut keys = vec!["present_rad", "velocity_rad_s", "load_raw", "setpoint_age"];
    if gauges > 0 {
        keys.extend(["strain_microstrain", "strain_age_s"]);
    }
    for k in keys {
        d.set_item(k, observed(py, rows, k, joints, gauges))?;
    }
    d.set_item(intern!(py, "time_s"), col(py, rows, |r| r.time_s))?;
    d.set_item(
        intern!(py, "thorax_position_m"),
        mat(py, rows, 3, |r| &r.position),
    )?;
    d.set_item(
        intern!(py, "thorax_orientation"),
        mat(py, rows, 4, |r| &r.orientation),
    )?;
    d.set_item(intern!(py, "rest_rad"), mat(py, rows, joints, |r| &r.rest))?;
    d.set_item(
        intern!(py, "settle_skipped"),
        col(py, rows, |r| r.settle_skipped),
    )?;
    d.set_item(intern!(py, "reward"), col(py, rows, |r| r.reward))?;
    d.set_item(intern!(py, "terminated"), col(py, rows, |r| r.terminated))?;
    d.set_item(intern!(py, "truncated"), col(py, rows, |r| r.truncated))?;
    d.set_item(
        intern!(py, "state"),
        rows.iter().map(|r| r.state).collect::<Vec<&str>>(),
    )?;
    Ok(d)
}

/// One job on one sub-environment, as a worker (or the inline engine) runs it.
fn run_job(env: &mut SubEnv, i: usize, job: Job) -> Result<Row, String> {
    match job {
        Job::Reset { scene, stiffness } => env.reset(scene, stiffness),
        Job::Step { angles, torques } => env.step(&angles, torques.as_deref()),
    }
    .map_err(|e| format!("sub-environment {i}: {e}"))
}

fn mask(m: Option<PyReadonlyArray1<'_, bool>>, n: usize) -> PyResult<Vec<bool>> {
    match m {
        None => Ok(vec![true; n]),
        Some(m) => {
            let m = m.as_array().to_vec();
            if m.len() != n {
                return Err(value_error(format!(
                    "mask: {} entries for {n} sub-environments",
                    m.len()
                )));
            }
            Ok(m)
        }
    }
}

/// Each row of `a` (N x j), clipped to [lo, hi] per joint when bounds are given.
fn rows_of(
    a: &PyReadonlyArray2<'_, f64>,
    n: usize,
    j: usize,
    what: &str,
    bounds: Option<(&[f64], &[f64])>,
) -> PyResult<Vec<Vec<f64>>> {
    let a = a.as_array();
    if a.dim() != (n, j) {
        return Err(value_error(format!(
            "{what}: shape {:?}, give ({n}, {j}): one row of {j} joints per sub-environment",
            a.dim()
        )));
    }
    Ok(a.outer_iter()
        .map(|r| {
            let mut row = r.to_vec();
            if let Some((lo, hi)) = bounds {
                clip_row(&mut row, lo, hi);
            }
            row
        })
        .collect())
}

/// The jobs of a reset: the sub-environments `mask` selects (None: all).
fn reset_jobs(
    n: usize,
    mask: Option<PyReadonlyArray1<'_, bool>>,
    scene: Option<String>,
    stiffness_nm_rad: Option<f64>,
) -> PyResult<Vec<(usize, Job)>> {
    let m = self::mask(mask, n)?;
    Ok((0..n)
        .filter(|&i| m[i])
        .map(|i| {
            let job = Job::Reset {
                scene: scene.clone(),
                stiffness: stiffness_nm_rad,
            };
            (i, job)
        })
        .collect())
}

/// The jobs of a step: each sub-environment's row of actions (clipped to `limits` when given),
/// or a reset where `resets` says.
fn step_jobs(
    n: usize,
    joints: usize,
    angles_rad: PyReadonlyArray2<'_, f64>,
    torques_nm: Option<PyReadonlyArray2<'_, f64>>,
    resets: &[bool],
    limits: Option<&Limits>,
) -> PyResult<Vec<(usize, Job)>> {
    let angle_bounds = limits.map(|l| (&l.low[..], &l.high[..]));
    let angles = rows_of(&angles_rad, n, joints, "angles_rad", angle_bounds)?;
    let minus_stall: Option<Vec<f64>> = limits.map(|l| l.stall.iter().map(|s| -s).collect());
    let torque_bounds = limits
        .zip(minus_stall.as_deref())
        .map(|(l, lo)| (lo, &l.stall[..]));
    let torques = torques_nm
        .map(|t| rows_of(&t, n, joints, "torques_nm", torque_bounds))
        .transpose()?;
    let mut torques = torques.map(|t| t.into_iter().map(Some).collect::<Vec<_>>());
    Ok(angles
        .into_iter()
        .enumerate()
        .map(|(i, angles)| {
            let job = if resets[i] {
                Job::Reset {
                    scene: None,
                    stiffness: None,
                }
            } else {
                Job::Step {
                    angles,
                    torques: torques.as_mut().and_then(|t| t[i].take()),
                }
            };
            (i, job)
        })
        .collect())
}

/// A fresh array of N booleans, all `v` (one per info key: Gymnasium's masks are not shared).
fn flags<'py>(py: Python<'py>, n: usize, v: bool) -> Bound<'py, PyArray1<bool>> {
    // NumPy's own memory, no Rust vector behind it (six of these a step).
    written(py, n, |cells: &mut [bool]| cells.fill(v))
}

#[pymethods]
impl VectorCore {
    /// `num_envs` physics robots on `threads` worker threads (0: on the calling thread), each
    /// built with `options` (`VectorOptions`: the step table uploaded at every reset, which tells
    /// the board its joint map, calibration, limits and stiffness, and the other arguments as
    /// `dbot.env.DbotEnv` takes them). `low`, `high` (joint targets, rad) and `stall` (torques,
    /// N m), when given, are the bounds every action is clipped to, as `np.clip` does it;
    /// `obs_keys` the observation's keys in the order `step_env` gives them.
    #[new]
    #[pyo3(signature = (num_envs, threads, options, low = None, high = None, stall = None,
        obs_keys = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        num_envs: usize,
        threads: usize,
        options: &Options,
        low: Option<Vec<f64>>,
        high: Option<Vec<f64>>,
        stall: Option<Vec<f64>>,
        obs_keys: Option<Vec<String>>,
    ) -> PyResult<Self> {
        if num_envs == 0 {
            return Err(value_error("num_envs = 0: give 1 or more"));
        }
        let model = planner::model::builtin("drosophibot2").map_err(value_error)?;
        let joints = model.servo_chain().len();
        let gauges = model.gauges.len();
        let limits = match (low, high, stall) {
            (None, None, None) => None,
            (Some(low), Some(high), Some(stall)) => {
                for (what, v) in [("low", &low), ("high", &high), ("stall", &stall)] {
                    if v.len() != joints {
                        return Err(value_error(format!(
                            "{what}: {} values, give {joints}: one per joint",
                            v.len()
                        )));
                    }
                }
                Some(Limits { low, high, stall })
            }
            _ => return Err(value_error("low, high and stall: give all three or none")),
        };
        let mut default_keys = vec!["present_rad", "velocity_rad_s", "load_raw", "setpoint_age"];
        if gauges > 0 {
            default_keys.extend(["strain_microstrain", "strain_age_s"]);
        }
        let obs_keys =
            obs_keys.unwrap_or_else(|| default_keys.iter().map(|k| (*k).to_owned()).collect());
        if let Some(k) = obs_keys
            .iter()
            .find(|k| !default_keys.contains(&k.as_str()))
        {
            return Err(value_error(format!(
                "obs_keys: {k} is not observed (give some of {})",
                default_keys.join(", ")
            )));
        }
        let options = options.clone();
        let threads = threads.min(num_envs);
        let engine = if threads == 0 {
            let envs = (0..num_envs).map(|_| SubEnv::new(options.clone()));
            Engine::Inline(RefCell::new(Some(envs.collect())))
        } else {
            Engine::Threads(Mutex::new(Some(spawn(threads, &options)?)))
        };
        Ok(Self {
            engine,
            num_envs,
            threads,
            rows: RefCell::new(vec![Row::default(); num_envs]),
            joints,
            gauges,
            limits,
            obs_keys,
            autoreset: RefCell::new(vec![false; num_envs]),
        })
    }

    /// Sub-environments.
    #[getter]
    fn num_envs(&self) -> usize {
        self.num_envs
    }

    /// Worker threads (at most one per sub-environment; 0: the calling thread).
    #[getter]
    fn threads(&self) -> usize {
        self.threads
    }

    /// Resets the sub-environments `mask` selects (None: all) as `DbotEnv.reset` does; `scene`
    /// (kept for later resets) and `stiffness_nm_rad` (this episode's) apply to each of them.
    /// Returns every sub-environment's latest row (see `step`).
    #[pyo3(signature = (mask = None, scene = None, stiffness_nm_rad = None))]
    fn reset<'py>(
        &self,
        py: Python<'py>,
        mask: Option<PyReadonlyArray1<'_, bool>>,
        scene: Option<String>,
        stiffness_nm_rad: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let jobs = reset_jobs(self.num_envs, mask, scene, stiffness_nm_rad)?;
        {
            let mut autoreset = self.autoreset.borrow_mut();
            for (i, _) in &jobs {
                autoreset[*i] = false;
            }
        }
        self.run(py, jobs)?;
        batch(py, &self.rows.borrow(), self.joints, self.gauges)
    }

    /// Steps every sub-environment with its row of `angles_rad` (N x 22, rad) and `torques_nm`
    /// (N x 22, N m, or None), both clipped to the bounds given at construction (without them,
    /// the caller clips to the joint limits), except those `reset` selects (N booleans, or
    /// None), which are reset instead (Gymnasium's next-step autoreset: their action is
    /// ignored). Returns a dict of arrays, first axis the sub-environment: the
    /// observation's keys (`present_rad`, `velocity_rad_s`, `load_raw`, `setpoint_age` and, with
    /// gauges, `strain_microstrain`, `strain_age_s`), `time_s`, `thorax_position_m`,
    /// `thorax_orientation`, `reward` (forward progress, m; 0 after a reset), `terminated`,
    /// `truncated` and `state` (run state names).
    #[pyo3(signature = (angles_rad, torques_nm = None, reset = None))]
    fn step<'py>(
        &self,
        py: Python<'py>,
        angles_rad: PyReadonlyArray2<'_, f64>,
        torques_nm: Option<PyReadonlyArray2<'_, f64>>,
        reset: Option<PyReadonlyArray1<'_, bool>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let resets = match reset {
            None => vec![false; self.num_envs],
            Some(_) => self::mask(reset, self.num_envs)?,
        };
        let jobs = step_jobs(
            self.num_envs,
            self.joints,
            angles_rad,
            torques_nm,
            &resets,
            self.limits.as_ref(),
        )?;
        self.run(py, jobs)?;
        batch(py, &self.rows.borrow(), self.joints, self.gauges)
    }

    /// `gymnasium.vector.VectorEnv.step` in one call: the actions clipped to the bounds given at
    /// construction, the sub-environments that ended at the previous call reset instead (next-
    /// step autoreset: their action ignored, reward 0, both flags False). Returns `(obs, reward,
    /// terminated, truncated, infos, rest)`: `obs` a dict of the `obs_keys`; `infos` with
    /// `time_s`, `settle_skipped`, `state` (object array) and `body` (`thorax_position_m`,
    /// `thorax_orientation`), each key beside its mask `_key` (all True); `rest` None, or after
    /// an autoreset `(mask, rest_rad)`: which were reset and every sub-environment's resting
    /// posture (N x 22, rad).
    #[pyo3(signature = (angles_rad, torques_nm = None))]
    fn step_env<'py>(
        &self,
        py: Python<'py>,
        angles_rad: PyReadonlyArray2<'_, f64>,
        torques_nm: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let n = self.num_envs;
        let resetting = self.autoreset.borrow().clone();
        let jobs = step_jobs(
            n,
            self.joints,
            angles_rad,
            torques_nm,
            &resetting,
            self.limits.as_ref(),
        )?;
        self.run(py, jobs)?;
        let rows = self.rows.borrow();
        let obs = PyDict::new(py);
        for k in &self.obs_keys {
            obs.set_item(k, observed(py, &rows, k, self.joints, self.gauges))?;
        }
        let mut reward: Vec<f64> = rows.iter().map(|r| r.reward).collect();
        let mut terminated: Vec<bool> = rows.iter().map(|r| r.terminated).collect();
        let mut truncated: Vec<bool> = rows.iter().map(|r| r.truncated).collect();
        for i in (0..n).filter(|&i| resetting[i]) {
            reward[i] = 0.0;
            terminated[i] = false;
            truncated[i] = false;
        }
        {
            let mut autoreset = self.autoreset.borrow_mut();
            for i in 0..n {
                autoreset[i] = terminated[i] || truncated[i];
            }
        }
        let body = PyDict::new(py);
        body.set_item(
            intern!(py, "thorax_position_m"),
            mat(py, &rows, 3, |r| &r.position),
        )?;
        body.set_item(intern!(py, "_thorax_position_m"), flags(py, n, true))?;
        body.set_item(
            intern!(py, "thorax_orientation"),
            mat(py, &rows, 4, |r| &r.orientation),
        )?;
        body.set_item(intern!(py, "_thorax_orientation"), flags(py, n, true))?;
        let infos = PyDict::new(py);
        infos.set_item(intern!(py, "time_s"), col(py, &rows, |r| r.time_s))?;
        infos.set_item(intern!(py, "_time_s"), flags(py, n, true))?;
        infos.set_item(
            intern!(py, "settle_skipped"),
            col(py, &rows, |r| r.settle_skipped),
        )?;
        infos.set_item(intern!(py, "_settle_skipped"), flags(py, n, true))?;
        let states: Vec<Py<PyAny>> = rows
            .iter()
            .map(|r| pyo3::types::PyString::new(py, r.state).into_any().unbind())
            .collect();
        infos.set_item(intern!(py, "state"), PyArray1::from_vec(py, states))?;
        infos.set_item(intern!(py, "_state"), flags(py, n, true))?;
        infos.set_item(intern!(py, "body"), body)?;
        infos.set_item(intern!(py, "_body"), flags(py, n, true))?;
        let rest = if resetting.iter().any(|&r| r) {
            let mask = PyArray1::from_slice(py, &resetting);
            (mask, mat(py, &rows, self.joints, |r| &r.rest))
                .into_pyobject(py)?
                .into_any()
        } else {
            py.None().into_bound(py)
        };
        (
            obs,
            PyArray1::from_slice(py, &reward),
            PyArray1::from_slice(py, &terminated),
            PyArray1::from_slice(py, &truncated),
            infos,
            rest,
        )
            .into_pyobject(py)
    }

    /// Stops the workers and closes every robot (idempotent).
    fn close(&self, py: Python<'_>) {
        match &self.engine {
            Engine::Threads(workers) => {
                let w = workers.lock().unwrap_or_else(|e| e.into_inner()).take();
                if let Some(w) = w {
                    py.detach(move || w.stop());
                }
            }
            Engine::Inline(envs) => drop(envs.borrow_mut().take()),
        }
    }
}

impl Workers {
    /// Closes the mailboxes and waits for each worker to close its robots and end.
    fn stop(self) {
        drop(self.to);
        for h in self.handles {
            let _ = h.join();
        }
    }
}

impl Drop for VectorCore {
    fn drop(&mut self) {
        if let Engine::Threads(workers) = &mut self.engine
            && let Some(w) = workers.get_mut().unwrap_or_else(|e| e.into_inner()).take()
        {
            w.stop();
        }
    }
}
