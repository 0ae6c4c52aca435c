//! One sub-environment of `VectorCore` (python/src/vector.rs): a physics robot reset and stepped
//! as `dbot.env.DbotEnv` does it on `physics:SCENE`, the same requests on the link in the same
//! order, so its observations, rewards and flags equal the Python class's bit for bit. Its
//! resets after the first of a scene and stiffness skip the settling to the state that first
//! one stored (`physics::PhysicsRobot::skip_to_state`; `Options::cheap_reset`), with the same
//! episode after them bit for bit.

use std::time::Duration;

use ::board::link::LinkError;
use ::board::rules::stiffness::Stiffness;
use protocol::units::ANGLE_PER_RAD;
use protocol::{Proprioception, ServoSelect, Status, StreamConfig};
use pyo3::prelude::*;

use crate::errors::value_error;

/// The link to one physics robot.
type Robot = physics::Robot;

/// What every sub-environment is built with (`DbotEnv`'s arguments): Python's
/// `dbot._native.VectorOptions`, given to `VectorCore`.
#[pyclass(name = "VectorOptions", frozen, module = "dbot._native")]
#[derive(Debug, Clone)]
pub struct Options {
    table: Vec<u8>,
    scene: String,
    cycles_per_step: u32,
    max_episode_steps: u32,
    stiffness_nm_rad: Option<f64>,
    /// Torque-on to streaming: the gravity ramp's 1 s plus the settling.
    settle: Duration,
    /// Reset from the settled state stored at a first reset of the same scene and stiffness
    /// instead of simulating the settling again (`physics::PhysicsRobot::skip_to_state`).
    cheap_reset: bool,
    timeout_cycles: u16,
    reply_timeout: Duration,
    fall_height_fraction: f64,
    fall_tilt_rad: f64,
}

/// A time in seconds as `dbot.Board` converts it.
fn seconds(s: f64, what: &str) -> Result<Duration, String> {
    Duration::try_from_secs_f64(s)
        .map_err(|_| format!("{what} = {s} s: give a finite, non-negative time"))
}

#[pymethods]
impl Options {
    /// The arguments as `dbot.env.DbotEnv` takes them; `table` the step table's bytes.
    #[new]
    #[pyo3(signature = (table, scene, cycles_per_step, max_episode_steps, stiffness_nm_rad,
        settle_s, timeout_cycles, reply_timeout_s, fall_height_fraction, fall_tilt_rad,
        cheap_reset = true))]
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        table: &[u8],
        scene: String,
        cycles_per_step: u32,
        max_episode_steps: u32,
        stiffness_nm_rad: Option<f64>,
        settle_s: f64,
        timeout_cycles: u16,
        reply_timeout_s: f64,
        fall_height_fraction: f64,
        fall_tilt_rad: f64,
        cheap_reset: bool,
    ) -> PyResult<Self> {
        if cycles_per_step == 0 {
            return Err(value_error("cycles_per_step = 0: give 1 or more"));
        }
        Ok(Self {
            table: table.to_vec(),
            scene,
            cycles_per_step,
            max_episode_steps,
            stiffness_nm_rad,
            settle: seconds(1.0 + settle_s, "1 s of gravity ramp + settle_s")
                .map_err(value_error)?,
            timeout_cycles,
            reply_timeout: seconds(reply_timeout_s, "reply_timeout_s").map_err(value_error)?,
            fall_height_fraction,
            fall_tilt_rad,
            cheap_reset,
        })
    }
}

/// One sub-environment's observation, body and outcome after a reset or a step.
#[derive(Debug, Clone, Default)]
pub struct Row {
    pub present: Vec<f64>,
    pub velocity: Vec<f64>,
    pub load: Vec<f64>,
    pub setpoint_age: f64,
    pub strain: Vec<f64>,
    pub strain_age_s: f64,
    /// The proprioception's clock, s.
    pub time_s: f64,
    pub position: [f64; 3],
    pub orientation: [f64; 4],
    pub reward: f64,
    pub terminated: bool,
    pub truncated: bool,
    pub state: &'static str,
    /// The resting posture held at the episode's reset (its first setpoint), rad.
    pub rest: Vec<f64>,
    /// Whether the episode's reset skipped to a stored settled state (a cheap reset).
    pub settle_skipped: bool,
}

/// A physics robot as `DbotEnv` drives it.
pub struct SubEnv {
    options: Options,
    robot: Option<Robot>,
    /// The scene of the next reset (a reset's `scene` replaces it, as in `DbotEnv`).
    scene: String,
    /// The next setpoint's sequence number (`dbot.Board` counts from 1 per opened board).
    seq: u32,
    steps: u32,
    start_height_m: f64,
    last: Row,
    /// The settled state per (scene, stiffness in the board's unit) of a reset that simulated it.
    settled: std::collections::HashMap<(String, Option<u32>), physics::PhysicsState>,
}

/// How long before the settling's end the settled state is kept (and a cheap reset becomes it),
/// s: two bus cycles, so the cycle that keeps it surely falls inside the wait.
const KEEP_BEFORE_END_S: f64 = 0.02;

/// The wait between two looks at the cycle counter (`DbotEnv._wait_cycles`).
const POLL_S: f64 = 0.01;
/// The wait for a proprioception record on the physics robot (`DbotEnv._next`).
const NEXT_S: f64 = 1.0;

/// `dbot.Board.status()`'s requests: the status, the settings when an alarm names a joint, and
/// the store's health.
fn status(l: &mut Robot) -> Result<Status, LinkError> {
    let s = l.status()?;
    if s.health_warning.is_some() || s.health_stop.is_some() {
        l.settings()?;
    }
    l.gaits()?;
    Ok(s)
}

fn wait_s(l: &mut Robot, s: f64) -> Result<(), String> {
    l.wait(seconds(s, "wait")?).map_err(|e| e.to_string())
}

/// `DbotEnv._wait_cycles`: `cycles` bus cycles on the board's own counter.
fn wait_cycles(l: &mut Robot, cycles: u64) -> Result<(), String> {
    let target = u64::from(status(l).map_err(|e| e.to_string())?.counters.cycles) + cycles;
    for _ in 0..100 * cycles {
        if u64::from(status(l).map_err(|e| e.to_string())?.counters.cycles) >= target {
            return Ok(());
        }
        wait_s(l, POLL_S)?;
    }
    Err(format!("{cycles} bus cycles did not pass"))
}

/// `DbotEnv._clear_upload_fault`.
fn clear_upload_fault(l: &mut Robot) -> Result<(), String> {
    let state = |l: &mut Robot| status(l).map(|s| s.state.key()).map_err(|e| e.to_string());
    wait_cycles(l, 30)?;
    if state(l)? == "Fault" {
        l.clear_fault().map_err(|e| e.to_string())?;
        wait_cycles(l, 30)?;
    }
    for _ in 0..1000 {
        if matches!(state(l)?, "Idle" | "Standing") {
            return Ok(());
        }
        wait_cycles(l, 1)?;
    }
    Err("not idle after the upload".into())
}

/// `acos` of the thorax z axis against the world's (`dbot.env.tilt_rad`).
fn tilt_rad(q: &[f64; 4]) -> f64 {
    let (x, y) = (q[1], q[2]);
    (1.0 - 2.0 * (x * x + y * y)).clamp(-1.0, 1.0).acos()
}

/// `DbotEnv`'s fall rule: the thorax (at `position`, oriented `q`) below `fall_height_m` or
/// tilted past `fall_tilt_rad`.
pub(crate) fn fell(
    position: &[f64; 3],
    q: &[f64; 4],
    fall_height_m: f64,
    fall_tilt_rad: f64,
) -> bool {
    position[2] < fall_height_m || tilt_rad(q) > fall_tilt_rad
}

impl SubEnv {
    pub fn new(options: Options) -> Self {
        Self {
            scene: options.scene.clone(),
            options,
            robot: None,
            seq: 1,
            steps: 0,
            start_height_m: 0.0,
            last: Row::default(),
            settled: std::collections::HashMap::new(),
        }
    }

    /// `DbotEnv.reset`: a fresh robot on the scene, the table uploaded, torque on, settled,
    /// streaming, one setpoint holding the resting posture.
    pub fn reset(&mut self, scene: Option<String>, stiffness: Option<f64>) -> Result<Row, String> {
        if let Some(s) = scene {
            self.scene = s;
        }
        let stiffness = stiffness.or(self.options.stiffness_nm_rad);
        let stiffness = stiffness
            .map(|s| Stiffness::of(s).map_err(|e| format!("stiffness_nm_rad: {e}")))
            .transpose()?;
        // The old robot goes first, as `DbotEnv._fresh_board` closes it.
        self.robot = None;
        let port = format!("physics:{}", self.scene);
        let mut l =
            physics::open_within(&port, self.options.reply_timeout).map_err(|e| e.to_string())?;
        // Nothing here reads the walk's figures (distance, slip, ...): their sampling is spared.
        l.transport_mut()
            .physics_mut()
            .ok_or("the physics robot has no body")?
            .set_figures(false);
        l.joint_map(None).map_err(|e| e.to_string())?;
        let model = planner::model::builtin("drosophibot2").map_err(|e| e.to_string())?;
        let checked = ::board::rules::build::table_bytes(
            self.options.table.clone(),
            "step table",
            &model,
            ::board::rules::Overrides::default(),
        )
        .map_err(|e| e.to_string())?;
        l.upload(0, &checked, |_, _| {})
            .map_err(|e| e.to_string())?;
        clear_upload_fault(&mut l)?;
        if let Some(s) = stiffness {
            for j in 0..model.servo_chain().len() {
                l.set_stiffness(j as u8, s).map_err(|e| e.to_string())?;
            }
        }
        l.set_torque(ServoSelect::All, true)
            .map_err(|e| e.to_string())?;
        // The settling: simulated once per scene and stiffness, then (cheap reset) skipped to.
        let key = (self.scene.clone(), stiffness.map(|s| s.units()));
        let keep_at = (l.now() + self.options.settle).as_secs_f64() - KEEP_BEFORE_END_S;
        let body = l
            .transport_mut()
            .physics_mut()
            .ok_or("the physics robot has no body")?;
        let keeping = match self.settled.get(&key) {
            Some(state) if self.options.cheap_reset => {
                body.skip_to_state(keep_at, state.clone())
                    .map_err(|e| e.to_string())?;
                false
            }
            _ => {
                body.keep_state_at(keep_at);
                true
            }
        };
        l.wait(self.options.settle).map_err(|e| e.to_string())?;
        if keeping
            && self.options.cheap_reset
            && let Some(state) = l
                .transport_mut()
                .physics_mut()
                .and_then(physics::PhysicsRobot::take_kept_state)
        {
            self.settled.insert(key, state);
        }
        let state = status(&mut l).map_err(|e| e.to_string())?.state.key();
        if state != "Standing" {
            return Err(format!(
                "{port}: not standing after torque on (state {state})"
            ));
        }
        l.enter_streaming(StreamConfig {
            timeout_cycles: self.options.timeout_cycles,
            feedback_every: 1,
        })
        .map_err(|e| e.to_string())?;
        let first = l
            .proprioception(seconds(NEXT_S, "wait")?)
            .map_err(|e| e.to_string())?
            .ok_or_else(|| format!("{port}: no proprioception after entering streaming"))?;
        let rest: Vec<f64> = first
            .joints
            .iter()
            .map(|j| f64::from(j.commanded) / ANGLE_PER_RAD)
            .collect();
        self.robot = Some(l);
        self.seq = 1;
        self.steps = 0;
        let rec = self
            .cycles(&rest, 1, None)?
            .ok_or_else(|| format!("{port}: streaming stopped at once"))?;
        let mut row = self.row(&rec)?;
        self.start_height_m = row.position[2];
        row.rest = rest;
        row.settle_skipped = !keeping;
        self.last = row.clone();
        Ok(row)
    }

    /// `DbotEnv.step` with the default reward (the thorax's advance along world x, m).
    pub fn step(&mut self, angles: &[f64], torques: Option<&[f64]>) -> Result<Row, String> {
        if self.robot.is_none() {
            return Err("call reset() before step()".into());
        }
        let before_x = self.last.position[0];
        let got = self.cycles(angles, self.options.cycles_per_step, torques)?;
        self.steps += 1;
        let truncated = self.steps >= self.options.max_episode_steps;
        let Some(rec) = got else {
            // Streaming stopped: the firmware went safe. The last observation stays.
            let l = self.robot.as_mut().expect("checked above");
            let state = status(l).map_err(|e| e.to_string())?.state.key();
            let (position, orientation) = l
                .transport()
                .physics()
                .ok_or("the physics robot has no body")?
                .plant()
                .thorax_pose();
            let mut row = self.last.clone();
            row.position = position;
            row.orientation = orientation;
            row.reward = 0.0;
            row.terminated = true;
            row.truncated = truncated;
            row.state = state;
            self.last = row.clone();
            return Ok(row);
        };
        let mut row = self.row(&rec)?;
        row.terminated = fell(
            &row.position,
            &row.orientation,
            self.options.fall_height_fraction * self.start_height_m,
            self.options.fall_tilt_rad,
        );
        row.truncated = truncated;
        row.reward = row.position[0] - before_x;
        self.last = row.clone();
        Ok(row)
    }

    /// `DbotEnv._cycles`: the setpoint sent for each of `n` bus cycles, the last proprioception
    /// (None: streaming stopped).
    fn cycles(
        &mut self,
        angles: &[f64],
        n: u32,
        torques: Option<&[f64]>,
    ) -> Result<Option<Proprioception>, String> {
        let l = self.robot.as_mut().ok_or("no robot")?;
        let mut rec = None;
        for _ in 0..n {
            let sp = ::board::link::setpoint_from_si(self.seq, angles, torques)
                .map_err(|e| e.to_string())?;
            self.seq = self.seq.wrapping_add(1);
            l.send_setpoint(&sp).map_err(|e| e.to_string())?;
            match l
                .proprioception(seconds(NEXT_S, "wait")?)
                .map_err(|e| e.to_string())?
            {
                Some(p) => rec = Some(p),
                None => return Ok(None),
            }
        }
        Ok(rec)
    }

    /// The observation and body after `rec` (state Streaming; reward and flags left 0).
    fn row(&self, rec: &Proprioception) -> Result<Row, String> {
        let l = self.robot.as_ref().ok_or("no robot")?;
        let t = l.transport();
        let time_s = rec.time_us as f64 * 1e-6;
        // The thorax pose is all a step needs of the body (`Body` would also sum the foot
        // contacts); the gauge sample by reference (`RobotLink::strain_at` clones its names).
        let physics = t.physics().ok_or("the physics robot has no body")?;
        let (position, orientation) = physics.plant().thorax_pose();
        let (strain, strain_age_s) = match physics.strain_at(time_s) {
            Some(s) => (
                s.readings.iter().map(|r| r.microstrain).collect(),
                crate::records::strain_age_s(time_s, s.time_s),
            ),
            None => (Vec::new(), f64::NAN),
        };
        Ok(Row {
            present: rec.joints.iter().map(crate::records::present_rad).collect(),
            velocity: rec
                .joints
                .iter()
                .map(crate::records::velocity_rad_s)
                .collect(),
            load: rec.joints.iter().map(|j| f64::from(j.load)).collect(),
            setpoint_age: f64::from(rec.setpoint_age),
            strain,
            strain_age_s,
            time_s,
            position,
            orientation,
            reward: 0.0,
            terminated: false,
            truncated: false,
            state: "Streaming",
            rest: self.last.rest.clone(),
            settle_skipped: self.last.settle_skipped,
        })
    }
}
