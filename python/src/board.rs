//! `dbot.Board`: a board, the RP2040 emulator's pseudo-terminal, or the in-process virtual robot,
//! opened by port name exactly as `dbot --port` does. Blocking calls release the GIL.

use std::sync::Mutex;
use std::time::Duration;

use ::board::link::Transport;
use numpy::ToPyArray;
use protocol::{Direction, PlayCommand, ServoSelect, Steps, StreamConfig};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::errors::{board_error, rule_error, value_error, warn_overridden};
use crate::model::Model;
use crate::names::JointNaming;
use crate::plan::Plan;
use crate::plan_dir::PlanDir;
use crate::records;
use crate::stream;

/// The robot behind a `Board`; its link says which kind it is (`physics::RobotLink`).
type Link = physics::Robot;

/// A connected board (real, emulated or virtual).
///
/// `unsendable`: the in-process virtual robot runs the firmware library on a single-threaded
/// simulated wire, so a link is not `Send`; a `Board` stays on the Python thread that opened it and
/// keeps the GIL while it talks to the board.
#[pyclass(module = "dbot._native", unsendable)]
#[derive(Debug)]
pub struct Board {
    /// None once closed.
    link: Mutex<Option<Link>>,
    port: String,
    next_seq: Mutex<u32>,
    /// Names of the joints in records (the tables this `Board` uploaded, the model).
    naming: Mutex<JointNaming>,
    /// A strain board beside this board (`attach_strain`) and its counts per microstrain.
    strain: Mutex<Option<(::board::strain::StrainBeside, StrainGains)>>,
    /// The record the last `stream_step` took.
    last_step: Mutex<Option<protocol::Proprioception>>,
}

/// A record as a dict, or None (none came).
type MaybeDict<'py> = PyResult<Option<Bound<'py, PyDict>>>;

pub(crate) fn seconds(s: f64, what: &str) -> PyResult<Duration> {
    Duration::try_from_secs_f64(s)
        .map_err(|_| value_error(format!("{what} = {s} s: give a finite, non-negative time")))
}

impl Board {
    /// Proprioception records as a dict; on the physics robot with the strain each record knew
    /// (`records::proprioception_strain`).
    fn proprioception<'py>(
        &self,
        py: Python<'py>,
        recs: &[protocol::Proprioception],
    ) -> PyResult<Bound<'py, PyDict>> {
        self.note_beside(recs);
        self.proprioception_unnoted(py, recs)
    }

    /// Tells a strain board beside this board (if any) the board time of each record as it
    /// arrives (`StrainBeside::note`: the clock alignment of its `strain.csv`).
    fn note_beside(&self, recs: &[protocol::Proprioception]) {
        let mut beside = self.strain.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((b, _)) = beside.as_mut() {
            for r in recs {
                b.note(r.time_us as f64 * 1e-6);
            }
        }
    }

    /// [`Self::proprioception`] without noting the records' arrival.
    fn proprioception_unnoted<'py>(
        &self,
        py: Python<'py>,
        recs: &[protocol::Proprioception],
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = records::proprioception_dict(py, recs, &self.naming())?;
        let strain = self.with(py, |l| {
            let t = l.transport();
            // The samples by reference (`RobotLink::strain_at` clones each, its 36 names too).
            Ok(t.physics().map(|p| {
                let names = p.gauge_names();
                let s: Vec<_> = recs
                    .iter()
                    .map(|r| {
                        p.strain_at(r.time_us as f64 * 1e-6)
                            .map(|s| (s.time_s, s.microstrain()))
                    })
                    .collect();
                (names, s)
            }))
        })?;
        if let Some((names, s)) = strain {
            records::proprioception_strain(py, &d, recs, &s, names)?;
        }
        let beside = self.strain.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((b, gains)) = beside.as_ref() {
            let now = std::time::Instant::now();
            records::proprioception_strain_board(py, &d, recs.len(), b.latest(), now, gains)?;
            d.set_item("strain_stopped", b.failed())?;
        }
        Ok(d)
    }

    /// Runs `f` on the link.
    pub(crate) fn with<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut Link) -> Result<R, ::board::link::LinkError>,
    ) -> PyResult<R> {
        self.with_rules(py, f, board_error)
    }

    /// [`Self::with`] for a call whose error `error` turns into Python's (a rule's refusal:
    /// `rule_error`).
    fn with_rules<R, E>(
        &self,
        _py: Python<'_>,
        f: impl FnOnce(&mut Link) -> Result<R, E>,
        error: impl FnOnce(E) -> PyErr,
    ) -> PyResult<R> {
        let mut guard = self.link.lock().unwrap_or_else(|e| e.into_inner());
        guard
            .as_mut()
            .map(f)
            .ok_or_else(|| board_error(format!("{}: the board was closed", self.port)))?
            .map_err(error)
    }

    /// The next record `take` brings within `timeout_s` of the board's clock, as `dict` makes it;
    /// None if none came.
    fn next_record<'py, R>(
        &self,
        py: Python<'py>,
        timeout_s: f64,
        take: impl FnOnce(&mut Link, Duration) -> Result<Option<R>, ::board::link::LinkError>,
        dict: impl FnOnce(R) -> PyResult<Bound<'py, PyDict>>,
    ) -> MaybeDict<'py> {
        let d = seconds(timeout_s, "timeout_s")?;
        self.with(py, |l| take(l, d))?.map(dict).transpose()
    }

    /// The table in `slot` for the period rule (the one this `Board` uploaded, else the one a
    /// `virtual:PATH` robot's image holds) and the model that names its joints.
    fn slot_table(&self, slot: u8) -> PyResult<(Option<Vec<u8>>, planner::model::Model)> {
        let (known, model) = {
            let naming = self.naming();
            let (table, model) = naming.uploaded_table(slot);
            (table.map(<[u8]>::to_vec), model.clone())
        };
        let known = match known {
            Some(t) => Some(t),
            None => ::board::rules::period::table_of_port(&self.port, slot).map_err(value_error)?,
        };
        Ok((known, model))
    }

    /// Runs a period rule's door (`period::play`, `period::queue`) with `command` on the table in
    /// its slot ([`Self::slot_table`]) with `allow_infeasible`, warning when it was overridden.
    fn by_period_rule(
        &self,
        py: Python<'_>,
        command: PlayCommand,
        allow_infeasible: bool,
        door: impl FnOnce(
            &mut Link,
            PlayCommand,
            Option<&[u8]>,
            &planner::model::Model,
            ::board::rules::Overrides,
        )
            -> Result<Option<::board::rules::Overridden>, ::board::rules::RuleError>,
    ) -> PyResult<()> {
        let (known, model) = self.slot_table(command.slot)?;
        let overrides = ::board::rules::Overrides { allow_infeasible };
        let warning = self.with_rules(
            py,
            |link| door(link, command, known.as_deref(), &model, overrides),
            rule_error,
        )?;
        warn_overridden(py, warning.as_ref())
    }

    /// `stream_step`'s exchange: for each of `cycles` (1 or more) bus cycles the setpoint of
    /// `angles` (rad, and `torques`, N m) sent and that cycle's record taken (waiting up to
    /// `wait`); the last record, None if one did not come (streaming stopped).
    pub(crate) fn exchange(
        &self,
        py: Python<'_>,
        angles: &[f64],
        torques: Option<&[f64]>,
        cycles: u32,
        wait: Duration,
    ) -> PyResult<Option<protocol::Proprioception>> {
        let mut rec = None;
        for _ in 0..cycles {
            let sp = ::board::link::setpoint_from_si(self.take_seq(), angles, torques)
                .map_err(value_error)?;
            self.with(py, |l| l.send_setpoint(&sp))?;
            match self.with(py, |l| l.proprioception(wait))? {
                Some(p) => {
                    self.note_beside(std::slice::from_ref(&p));
                    rec = Some(p);
                }
                None => return Ok(None),
            }
        }
        Ok(rec)
    }

    /// Keeps `rec` as the last step's record (`last_stream_record`).
    pub(crate) fn keep_step(&self, rec: protocol::Proprioception) {
        *self.last_step.lock().unwrap_or_else(|e| e.into_inner()) = Some(rec);
    }

    /// The next setpoint's sequence number (taken).
    fn take_seq(&self) -> u32 {
        let mut s = self.next_seq.lock().unwrap_or_else(|e| e.into_inner());
        let v = *s;
        *s = s.wrapping_add(1);
        v
    }

    fn naming(&self) -> std::sync::MutexGuard<'_, JointNaming> {
        self.naming.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[pymethods]
impl Board {
    /// Opens `port`: a serial device or pseudo-terminal path (a board, the RP2040 emulator),
    /// `virtual` (an in-process virtual robot with an erased gait store) or `virtual:PATH` (one
    /// whose flash lives in the file PATH), or `physics` / `physics:SCENE` (the virtual robot with a
    /// MuJoCo body: loads are the body's, not the plan's; scenes `flat`, `incline:DEG`, `ball`,
    /// `ball-fixed`). Checks the protocol and table format versions. A `virtual:PATH` robot gets
    /// the settings `dbot set` kept beside its store (bus, telemetry rate, stiffness).
    #[staticmethod]
    #[pyo3(signature = (port, reply_timeout_s = 2.0))]
    fn open(port: &str, reply_timeout_s: f64) -> PyResult<Self> {
        let timeout = seconds(reply_timeout_s, "reply_timeout_s")?;
        // The library's opener: a `virtual:PATH` robot gets what `dbot set` saved beside it.
        let mut link = physics::open_within(port, timeout).map_err(board_error)?;
        let mut naming =
            JointNaming::new(planner::model::builtin("drosophibot2").map_err(value_error)?);
        // The gait the board selected at start-up, which this `Board` did not upload.
        naming.board_reported(link.joint_map(None).map_err(board_error)?);
        Ok(Self {
            link: Mutex::new(Some(link)),
            port: port.to_owned(),
            next_seq: Mutex::new(1),
            naming: Mutex::new(naming),
            strain: Mutex::new(None),
            last_step: Mutex::new(None),
        })
    }

    /// The port name given to `open`.
    #[getter]
    fn port(&self) -> String {
        self.port.clone()
    }

    /// What the port is: `"serial"` (a board or the emulator's pseudo-terminal), `"virtual"` or
    /// `"physics"`.
    #[getter]
    fn kind(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.with(py, |l| Ok(l.transport().kind()))
    }

    /// The physics robot's body now (see `dbot.Body`): thorax pose and velocity, each foot's
    /// contact force, contact and slip, simulated time; world frame, SI units. Raises
    /// `BoardError` on any other kind of port (a board or the virtual robot has no simulated
    /// body).
    fn body<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let body = self.with(py, |l| Ok(l.transport().body()))?;
        let body = body.ok_or_else(|| {
            board_error(format!(
                "{}: no simulated body: this is a {} port; the body exists only on the physics \
                 robot (open `physics` or `physics:SCENE`)",
                self.port,
                self.with(py, |l| Ok(l.transport().kind()))
                    .unwrap_or("closed")
            ))
        })?;
        crate::body::body_dict(py, &body)
    }

    /// The board's clock as the host sees it, s: wall time on a port, simulated time on the
    /// virtual robot.
    fn now(&self) -> PyResult<f64> {
        let guard = self.link.lock().unwrap_or_else(|e| e.into_inner());
        let link = guard
            .as_ref()
            .ok_or_else(|| board_error("the board was closed"))?;
        Ok(link.now().as_secs_f64())
    }

    /// Closes the link (the port can be opened again; a virtual robot with a flash file saves
    /// it). Further calls raise `BoardError`.
    fn close(&self) -> PyResult<()> {
        let link = self.link.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(link) = link {
            link.into_transport().shutdown().map_err(board_error)?;
        }
        Ok(())
    }

    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }

    #[pyo3(signature = (*_args))]
    fn __exit__(&self, _py: Python<'_>, _args: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close()?;
        Ok(false)
    }

    /// Firmware version, protocol and table format versions, slots.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let guard = self.link.lock().unwrap_or_else(|e| e.into_inner());
        let link = guard
            .as_ref()
            .ok_or_else(|| board_error("the board was closed"))?;
        let i = link.info();
        let d = PyDict::new(py);
        let f = i.firmware;
        d.set_item("firmware", format!("{}.{}.{}", f.major, f.minor, f.patch))?;
        d.set_item("protocol_version", i.protocol_version)?;
        d.set_item("table_format_version", i.table_format_version)?;
        d.set_item("slots", i.slots.len())?;
        d.set_item("slot_capacity", i.slot_capacity)?;
        d.set_item("store", store_health(&i.slots))?;
        Ok(d)
    }

    /// Every gait slot as a dict (see `gaits()` entries: `slot`, `gait`, `lost`, `message`). A slot
    /// whose `lost` is not None fell back to an older gait (`gait` set) or holds no readable one.
    fn gaits<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let slots = self.with(py, |l| l.gaits())?;
        slots.iter().map(|s| records::slot_dict(py, s)).collect()
    }

    /// Run state, fault (kind and joint), torque mask, playback position and the board's counters
    /// since boot as a dict of named integers (`cycles`, `missed_deadlines`, `bus_timeouts`,
    /// `crc_errors`, `rejected_frames`, `telemetry_dropped`, `rate_limited`).
    fn status<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.with(py, |l| l.status())?;
        let d = records::status_dict(py, &s)?;
        // The servos' heat and supply: the worst warning now, the servo that stopped the last
        // walk (None: none), named as `dbot status` names them.
        let names = if s.health_warning.is_some() || s.health_stop.is_some() {
            let n = self.with(py, |l| l.settings())?.joints.len();
            self.naming().names(n)
        } else {
            Vec::new()
        };
        for (key, alarm) in [
            ("health_warning", s.health_warning),
            ("health_stop", s.health_stop),
        ] {
            match alarm {
                Some(a) => d.set_item(key, records::health_alarm_dict(py, &a, &names)?)?,
                None => d.set_item(key, py.None())?,
            }
        }
        // Asked afresh (not the slots of `info()`, read at open): an upload since clears a mark.
        let store = self.with(py, |l| l.gaits().map(|g| store_health(&g)))?;
        d.set_item("store", store)?;
        Ok(d)
    }

    /// Uploads a step table (bytes, e.g. `Plan.step_table()` or a `.dbgt` file's) into `slot`
    /// and verifies it. The bytes are checked by the library's rules first, as `dbot upload
    /// --table` checks a file (same words): a table the servos cannot follow at its planned
    /// period (one built with `allow_infeasible=True`) is refused (ValueError) unless
    /// `allow_infeasible` (then a UserWarning), and a stiffness a servo's P gain cannot hold is
    /// refused. Returns the number of bytes sent.
    #[pyo3(signature = (slot, table, allow_infeasible = false))]
    fn upload(
        &self,
        py: Python<'_>,
        slot: u8,
        table: &Bound<'_, PyBytes>,
        allow_infeasible: bool,
    ) -> PyResult<u32> {
        let bytes = table.as_bytes().to_vec();
        let model = self.naming().uploaded_table(slot).1.clone();
        let overrides = ::board::rules::Overrides { allow_infeasible };
        let checked = ::board::rules::build::table_bytes(bytes, "step table", &model, overrides)
            .map_err(rule_error)?;
        warn_overridden(py, checked.warning())?;
        let report = self.with(py, |l| l.upload(slot, &checked, |_, _| {}))?;
        self.naming().uploaded(slot, checked.into_bytes());
        Ok(report.bytes)
    }

    /// Builds the step table of `plan` (a `Plan`, with the planned torques as bias if `torques`;
    /// or a `PlanDir`, as `dbot upload --plan DIR` does) under the library's rules and uploads it
    /// into `slot`. A plan the servos cannot follow is refused (ValueError, the words of `dbot
    /// upload --plan`) unless `allow_infeasible` (then a UserWarning).
    #[pyo3(signature = (slot, plan, name = None, torques = false, allow_infeasible = false))]
    fn upload_plan(
        &self,
        py: Python<'_>,
        slot: u8,
        plan: &Bound<'_, PyAny>,
        name: Option<&str>,
        torques: bool,
        allow_infeasible: bool,
    ) -> PyResult<u32> {
        let table = if let Ok(p) = plan.cast::<Plan>() {
            p.get()
                .checked_table(py, name.unwrap_or("dbot-gait"), torques, allow_infeasible)?
        } else if let Ok(p) = plan.cast::<PlanDir>() {
            p.get().checked_table(name, allow_infeasible)?
        } else {
            return Err(value_error(format!(
                "upload_plan(): plan must be a Plan or a PlanDir, not {}",
                plan.get_type().name()?
            )));
        };
        warn_overridden(py, table.warning())?;
        let report = self.with(py, |l| {
            ::board::rules::upload::upload_checked(l, slot, &table, |_, _| {}, || false)
        })?;
        self.naming().uploaded(slot, table.into_bytes());
        Ok(report.bytes)
    }

    /// Plays the gait in `slot`: `steps` whole steps (None: until `stop()`), at `period_scale`
    /// times the planned step period, backward if asked. Faster than planned (`period_scale` < 1)
    /// the table's speeds at that period are checked against the servos, as `dbot run --period`
    /// checks them: refused (ValueError, the same words) when a servo could not follow, or when
    /// this `Board` did not upload the slot's table, unless `allow_infeasible` (a UserWarning).
    #[pyo3(signature = (slot, steps = None, period_scale = 1.0, backward = false, allow_infeasible = false))]
    fn play(
        &self,
        py: Python<'_>,
        slot: u8,
        steps: Option<u32>,
        period_scale: f64,
        backward: bool,
        allow_infeasible: bool,
    ) -> PyResult<()> {
        let command = scaled_command(slot, steps, period_scale, backward)?;
        let stored = self.with(py, |l| l.gaits())?;
        self.by_period_rule(py, command, allow_infeasible, ::board::rules::period::play)?;
        self.naming().played(slot);
        if let Some(msg) = stored
            .iter()
            .find(|s| s.slot == slot)
            .and_then(records::loss_message)
        {
            let warning = py.get_type::<pyo3::exceptions::PyUserWarning>();
            let msg = std::ffi::CString::new(format!("playing a fallback: {msg}"))
                .map_err(value_error)?;
            PyErr::warn(py, &warning, &msg, 1)?;
        }
        let map = self.with(py, |l| l.joint_map(None))?;
        self.naming().board_reported(map);
        Ok(())
    }

    /// Queues the gait in `slot` to play after the one playing (or the last queued), at a step
    /// boundary without standing still; the board refuses one that cannot follow (different legs
    /// on the ground at the boundary, a joint jump beyond one bus cycle of its servo), saying why.
    /// Faster than planned (`period_scale` < 1) it meets `play`'s rule (and `dbot run --then`'s):
    /// refused (ValueError, the same words) when a servo could not follow, or when this `Board`
    /// did not upload the slot's table, unless `allow_infeasible` (a UserWarning).
    #[pyo3(signature = (slot, steps = None, period_scale = 1.0, backward = false, allow_infeasible = false))]
    fn queue_gait(
        &self,
        py: Python<'_>,
        slot: u8,
        steps: Option<u32>,
        period_scale: f64,
        backward: bool,
        allow_infeasible: bool,
    ) -> PyResult<()> {
        let command = scaled_command(slot, steps, period_scale, backward)?;
        self.by_period_rule(py, command, allow_infeasible, |link, c, known, model, o| {
            ::board::rules::period::queue(link, protocol::QueueCommand(c), known, model, o)
        })
    }

    /// Sets the gaits `steer` blends: slots `straight`, `left`, `right`, planned for headings 0,
    /// `+range` and `-range` rad with the same leg phases, slices and period; the board refuses a
    /// family it cannot blend, saying why.
    #[pyo3(signature = (straight, left, right, range))]
    fn set_steer_family(
        &self,
        py: Python<'_>,
        straight: u8,
        left: u8,
        right: u8,
        range: f64,
    ) -> PyResult<()> {
        self.with(py, move |l| {
            l.set_steer_family(straight, left, right, range)
        })
    }

    /// The descending command: walk at `heading` rad (positive left, within the family's range)
    /// and `speed` (1 = as planned). From standing a steered walk starts (until `stop`); while it
    /// walks, the new heading and speed take over at the next step boundary. Faster than planned
    /// (`speed` > 1) the family's tables are checked against the servos at that speed, as `dbot
    /// steer --speed` checks them: refused (ValueError, the same words) when a servo could not
    /// follow one, or when this `Board` did not set the family or upload (or, on `virtual:PATH`,
    /// find) its tables, unless `allow_infeasible` (a UserWarning).
    #[pyo3(signature = (heading, speed = 1.0, allow_infeasible = false))]
    fn steer(
        &self,
        py: Python<'_>,
        heading: f64,
        speed: f64,
        allow_infeasible: bool,
    ) -> PyResult<()> {
        let (tables, model) = {
            let naming = self.naming();
            // The tables this `Board` uploaded, by slot.
            let tables: Vec<Option<Vec<u8>>> = (0..protocol::MAX_SLOTS)
                .map(|slot| {
                    let slot = u8::try_from(slot).unwrap_or(u8::MAX);
                    naming.uploaded_table(slot).0.map(<[u8]>::to_vec)
                })
                .collect();
            (tables, naming.uploaded_table(0).1.clone())
        };
        let port = self.port.clone();
        let held = move |slot: u8| match tables.get(usize::from(slot)).cloned().flatten() {
            Some(t) => Ok(Some(t)),
            None => ::board::rules::period::table_of_port(&port, slot),
        };
        let overrides = ::board::rules::Overrides { allow_infeasible };
        let warning = self.with_rules(
            py,
            |link| {
                use ::board::rules::steer::{check_steer, steer};
                let checked = check_steer(link, heading, speed, &held, &model, overrides)?;
                steer(link, checked)
            },
            rule_error,
        )?;
        warn_overridden(py, warning.as_ref())
    }

    /// Sets up the perturbation platform for the next runs, as `dbot record --perturb` does:
    /// `perturb` is `LEG:STEP:MOVE` (e.g. `"RM:3:rise"`; steps from 0, MOVE `rise` or `fall`) with
    /// the lab's positions (rest 2020, rise 2330, fall 1570 ticks, back to rest two cycles later)
    /// on servo `platform_id` (default: the lab's 22 unless the board's gait's joints use it, then
    /// the first free ID after theirs, 23 for the built-in model: `dbot`'s rule). With `steps`
    /// (the run's) a step beyond it is refused here; `play` refuses it on the board too. Raises,
    /// naming the problem, before anything moves: a leg that is not a leg, a joint's ID, a
    /// platform servo that does not answer. Returns the trial record's perturbation (`leg`,
    /// `step`, `rest`, `moved_to`) and the `platform_id` used.
    #[pyo3(signature = (perturb, steps = None, platform_id = None))]
    fn set_platform<'py>(
        &self,
        py: Python<'py>,
        perturb: &str,
        steps: Option<u32>,
        platform_id: Option<u8>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let given = platform_id.unwrap_or(::board::platform::LAB_PLATFORM_ID);
        let mut p = ::board::platform::Perturb::parse(perturb, given)
            .and_then(|p| p.check_steps(steps).map(|()| p))
            .map_err(|e| value_error(format!("perturb = {perturb:?}: {e}")))?;
        let id = self.with(py, move |l| {
            if platform_id.is_none() {
                p.setup.servo_id = match l.joint_map(None)? {
                    Some(m) => ::board::platform::default_platform_id(&m.servo_ids),
                    None => ::board::platform::default_platform_id_for(None),
                };
            }
            l.set_platform(p.setup).map(|()| p.setup.servo_id)
        })?;
        let r = p.record();
        let d = PyDict::new(py);
        d.set_item("leg", r.leg)?;
        d.set_item("step", r.step)?;
        d.set_item("rest", r.rest)?;
        d.set_item("moved_to", r.moved_to)?;
        d.set_item("platform_id", id)?;
        Ok(d)
    }

    /// No perturbation platform any more (not while moving).
    fn clear_platform(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |l| l.clear_platform())
    }

    /// Names the joints of records and setpoints after `model`'s joints (default: the built-in
    /// drosophibot2), by the servo IDs of the table this `Board` uploaded for the gait in use.
    fn set_model(&self, model: &Model) {
        self.naming().set_model(model.inner.clone());
    }

    /// Names of the board's joints in joint-map order (the columns of records and setpoints):
    /// the model joint each servo of the gait in use drives, if this `Board` uploaded that gait;
    /// else the model's servo joints in order when the counts agree; `J<n>` otherwise.
    #[getter]
    fn joint_names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let count = self.with(py, |l| l.settings())?.joints.len();
        let map = self.with(py, |l| l.joint_map(None))?;
        let mut naming = self.naming();
        naming.board_reported(map);
        Ok(naming.names(count))
    }

    /// Stops the walk as `dbot run` and `dbot record` do (`board::record::stop_walk`): walking,
    /// at the end of the current step; ramping, where the ramp got to; streaming, holding the
    /// last setpoint. Returns what it did, in words.
    fn stop(&self, py: Python<'_>) -> PyResult<String> {
        self.with(py, ::board::record::stop_walk)
            .map(|how| how.describe().to_owned())
    }

    /// Torque off on every servo at once.
    fn emergency_stop(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |l| l.emergency_stop())
    }

    /// Leaves the fault state once its cause is gone (the board is then idle, torque off).
    fn clear_fault(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |l| l.clear_fault())
    }

    /// Torque on or off for every servo (`dbot set --torque`). The board switches all servos
    /// together: one joint alone it refuses (`Unsupported`), so there is no `joint=` (issue 43).
    fn set_torque(&self, py: Python<'_>, enable: bool) -> PyResult<()> {
        self.with(py, move |l| l.set_torque(ServoSelect::All, enable))
    }

    /// Telemetry every `every` bus cycles (0: off) outside streaming; streaming's proprioception
    /// follows `enter_streaming(feedback_every=...)` instead.
    fn set_telemetry(&self, py: Python<'_>, every: u16) -> PyResult<()> {
        self.with(py, move |l| l.set_telemetry(every))
    }

    /// The servos' heat and supply limits: warn at `warn_temp_c`, stop a walk at the end of its
    /// step at `stop_temp_c` (degC; defaults 70 and 75, below the servos' own 80); warn at
    /// `warn_low_v` / `warn_high_v`, stop at `stop_low_v` / `stop_high_v` (V; defaults 10.5 /
    /// 14.8 and 10.0 / 15.5, inside the servos' own 9.5 to 16.0). Unnamed limits keep the
    /// board's. Refused (ValueError) in the words of `dbot set`. Returns the limits as set.
    #[pyo3(signature = (warn_temp_c = None, stop_temp_c = None, warn_low_v = None, stop_low_v = None, warn_high_v = None, stop_high_v = None))]
    #[allow(clippy::too_many_arguments)]
    fn set_health_limits(
        &self,
        py: Python<'_>,
        warn_temp_c: Option<f64>,
        stop_temp_c: Option<f64>,
        warn_low_v: Option<f64>,
        stop_low_v: Option<f64>,
        warn_high_v: Option<f64>,
        stop_high_v: Option<f64>,
    ) -> PyResult<String> {
        let args = board::health::HealthLimitArgs {
            warn_temperature_c: warn_temp_c,
            stop_temperature_c: stop_temp_c,
            warn_low_v,
            stop_low_v,
            warn_high_v,
            stop_high_v,
        };
        let cur = self.with(py, |l| l.settings())?.health;
        let limits = board::health::health_limits(cur, &args).map_err(value_error)?;
        self.with(py, move |l| l.set_health_limits(limits))?;
        Ok(board::health::limits_line(&limits))
    }

    /// Bus baud rate (bit/s) and bus cycle rate (Hz); only while not moving. A baud change is
    /// checked as `dbot set --baud` checks it (`board::rules::bus`): the servos keep their own baud
    /// (EEPROM), so unless every servo answers at the new baud the board is put back on the old
    /// one and ValueError says which servo and how to set the servos first (`dbot.Bench`).
    fn set_bus(&self, py: Python<'_>, baud: u32, cycle_hz: u16) -> PyResult<()> {
        self.with_rules(
            py,
            |link| ::board::rules::bus::set_bus(link, baud, cycle_hz),
            rule_error,
        )
    }

    /// The board's run-time settings, as `dbot status` shows them: `baud` (bit/s), `cycle_hz`,
    /// `telemetry_every` (cycles, 0: off) and per joint of the joint map `stiffness_nm_rad`
    /// (N m/rad) and `limits_rad` ([joint, 2] of lower, upper).
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        use numpy::ToPyArray;
        let s = self.with(py, |l| l.settings())?;
        let d = PyDict::new(py);
        d.set_item("baud", s.baud)?;
        d.set_item("cycle_hz", s.cycle_hz)?;
        d.set_item("telemetry_every", s.telemetry_every)?;
        let k = protocol::units::STIFFNESS_PER_NM_RAD;
        let stiffness: Vec<f64> = s
            .joints
            .iter()
            .map(|j| f64::from(j.stiffness) / k)
            .collect();
        d.set_item(
            "stiffness_nm_rad",
            numpy::ndarray::Array1::from(stiffness).to_pyarray(py),
        )?;
        let a = protocol::units::ANGLE_PER_RAD;
        let limits = numpy::ndarray::Array2::from_shape_fn((s.joints.len(), 2), |(i, c)| {
            let j = &s.joints[i];
            f64::from(if c == 0 { j.min } else { j.max }) / a
        });
        d.set_item("limits_rad", limits.to_pyarray(py))?;
        Ok(d)
    }

    /// Stiffness of the servo of `joint` (joint-map index), N m/rad: the board writes it to the
    /// servo's Position P Gain and the torque bias divides by it; within the hardware's limits,
    /// as `dbot set --stiffness` (protocol::limits). While walking the goals do not step: the bias
    /// moves to the new stiffness by at most the servo's one-cycle move per cycle.
    fn set_stiffness(&self, py: Python<'_>, joint: u8, stiffness_nm_rad: f64) -> PyResult<()> {
        // The library's rule, as `dbot set --stiffness` applies it: the board's unit range and
        // the P gain register of every servo model (0: the torque bias off).
        let units = ::board::rules::stiffness::Stiffness::of(stiffness_nm_rad)
            .map_err(|e| value_error(format!("joint {joint}: {e}")))?;
        self.with(py, move |l| l.set_stiffness(joint, units))
    }

    /// Lets `seconds` pass on the board's clock, keeping telemetry and proprioception that
    /// arrive (on the virtual robot, time passes only while the host waits).
    fn wait(&self, py: Python<'_>, seconds: f64) -> PyResult<()> {
        let d = self::seconds(seconds, "seconds")?;
        self.with(py, move |l| l.wait(d))
    }

    /// Reads playback telemetry for `duration_s` on the board's clock (plus what was already
    /// received): a dict of NumPy arrays, see `dbot.Telemetry`.
    ///
    /// With `strain` (a strain board's port, or `"virtual"`) the strain board is recorded beside
    /// it into `strain_dir` as `dbot record --strain` does (`board::strain::StrainBeside`: it
    /// calibrates first; the servo board's port is refused): the dict gains `strain_time_s` (on
    /// the telemetry's `time_s` clock), `strain_counts` ([sample, 36] raw counts),
    /// `strain_names` and `strain_error` (why the strain stream stopped early, else None; the
    /// telemetry is whole either way).
    #[pyo3(signature = (duration_s, strain = None, strain_dir = None))]
    fn record<'py>(
        &self,
        py: Python<'py>,
        duration_s: f64,
        strain: Option<&str>,
        strain_dir: Option<std::path::PathBuf>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = seconds(duration_s, "duration_s")?;
        let mut beside = match (strain, &strain_dir) {
            (None, _) => None,
            (Some(p), None) => {
                return Err(value_error(format!(
                    "strain = {p:?}: give strain_dir, the folder for strain.csv"
                )));
            }
            (Some(p), Some(dir)) => {
                let servo = self.port.clone();
                // Calibration takes seconds on the lab's board: other Python threads may run.
                Some(
                    py.detach(|| ::board::strain::StrainBeside::start(p, &servo, dir))
                        .map_err(|e| value_error(format!("strain = {p:?}: {e}")))?,
                )
            }
        };
        let recs = self.with(py, |l| {
            let deadline = l.now() + d;
            let mut out = Vec::new();
            loop {
                let now = l.now();
                let left = deadline.saturating_sub(now);
                match l.telemetry(left)? {
                    Some(t) => {
                        if let Some(b) = beside.as_mut() {
                            b.note(t.time_us as f64 * 1e-6);
                        }
                        out.push(t);
                    }
                    None => break,
                }
                if left.is_zero() {
                    break;
                }
            }
            Ok(out)
        })?;
        let dict = records::telemetry_dict(py, &recs, &self.naming())?;
        if let (Some(b), Some(dir)) = (beside, strain_dir) {
            records::strain_items(py, &dict, b.finish(), &dir)?;
        }
        Ok(dict)
    }

    /// Records a trial folder in `out` exactly as `dbot record` does (the same call, refusals and
    /// files; the keywords are its flags): returns the published folder. See
    /// `crate::trial_record`.
    #[pyo3(signature = (out, *, table = None, plan = None, play = None, steps = None,
        backward = false, period = None, allow_infeasible = false, seconds = None,
        notes = "", trial = None, substrate = None, strain = None, perturb = None,
        platform_id = None, every = 1))]
    #[allow(clippy::too_many_arguments)]
    fn record_trial(
        &self,
        py: Python<'_>,
        out: std::path::PathBuf,
        table: Option<std::path::PathBuf>,
        plan: Option<std::path::PathBuf>,
        play: Option<u8>,
        steps: Option<u32>,
        backward: bool,
        period: Option<f64>,
        allow_infeasible: bool,
        seconds: Option<f64>,
        notes: &str,
        trial: Option<String>,
        substrate: Option<String>,
        strain: Option<String>,
        perturb: Option<String>,
        platform_id: Option<u8>,
        every: u16,
    ) -> PyResult<String> {
        let args = lab::trial_record::TrialArgs {
            out,
            table,
            plan,
            play,
            steps,
            backward,
            period,
            allow_infeasible,
            seconds,
            notes: notes.to_owned(),
            trial,
            substrate,
            strain,
            perturb,
            platform_id,
            every,
        };
        // A table this `Board` uploaded into the played slot is what a faster period is checked
        // against (as `play` checks it).
        let (held, model) = {
            let naming = self.naming();
            let (table, model) = naming.uploaded_table(play.unwrap_or(0));
            (
                table.filter(|_| play.is_some()).map(<[u8]>::to_vec),
                model.clone(),
            )
        };
        let mut guard = self.link.lock().unwrap_or_else(|e| e.into_inner());
        let link = guard
            .as_mut()
            .ok_or_else(|| board_error(format!("{}: the board was closed", self.port)))?;
        let path = crate::trial_record::record(py, link, &args, model, held)?;
        if let (Some(slot), Some(bytes)) = (
            play,
            args.table.as_ref().and_then(|p| std::fs::read(p).ok()),
        ) {
            self.naming().uploaded(slot, bytes);
        }
        if let Some(slot) = play {
            self.naming().played(slot);
        }
        Ok(path.display().to_string())
    }

    /// The next playback telemetry record (a dict of arrays with one row, the keys of `record`),
    /// waiting up to `timeout_s` on the board's clock; None if none came. Records come every
    /// `set_telemetry(every)` bus cycles outside streaming, so a host can follow a walk cycle by
    /// cycle (the descending environment, `dbot.env_descending`).
    #[pyo3(signature = (timeout_s = 0.1))]
    fn next_telemetry<'py>(&self, py: Python<'py>, timeout_s: f64) -> MaybeDict<'py> {
        self.next_record(
            py,
            timeout_s,
            |l, d| l.telemetry(d),
            |t| records::telemetry_dict(py, &[t], &self.naming()),
        )
    }

    /// Switches from standing to streaming. After `timeout_cycles` bus cycles without a new
    /// setpoint the board holds the last one, then goes safe with fault `SetpointTimeout`.
    /// Proprioception comes every `feedback_every` cycles (1: every cycle), whatever
    /// `set_telemetry` says. Each record's `setpoint_seq`, `setpoint_age` and `commanded_rad` are
    /// what that cycle wrote to the servos (`setpoint_seq` 0: no setpoint yet this session).
    #[pyo3(signature = (timeout_cycles = 5, feedback_every = 1))]
    fn enter_streaming(
        &self,
        py: Python<'_>,
        timeout_cycles: u16,
        feedback_every: u16,
    ) -> PyResult<()> {
        let c = StreamConfig {
            timeout_cycles,
            feedback_every,
        };
        self.with(py, move |l| l.enter_streaming(c))
    }

    /// Back to standing, holding the last setpoint.
    fn leave_streaming(&self, py: Python<'_>) -> PyResult<()> {
        self.with(py, |l| l.leave_streaming())
    }

    /// Sends joint targets (rad, joint-map order: `Model.servo_joint_names`) and optional torque
    /// feed-forward (N m) from the next bus cycle on. Returns the setpoint's sequence number, echoed
    /// in proprioception's `setpoint_seq`. The board moves each goal toward its target by at most
    /// what the joint's servo moves in one cycle (no-load speed x cycle period: 37 ticks on an
    /// MX-28 at 100 Hz), so a target farther away is reached over several cycles, not in one.
    #[pyo3(signature = (angles_rad, torques_nm = None))]
    fn send_setpoint(
        &self,
        py: Python<'_>,
        angles_rad: &Bound<'_, PyAny>,
        torques_nm: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<u32> {
        let seq = self.take_seq();
        let sp = stream::setpoint(seq, angles_rad, torques_nm)?;
        self.with(py, move |l| l.send_setpoint(&sp))?;
        Ok(seq)
    }

    /// The next proprioception record (a dict of arrays with one row), waiting up to
    /// `timeout_s` on the board's clock; None if none came.
    #[pyo3(signature = (timeout_s = 0.1))]
    fn next_proprioception<'py>(&self, py: Python<'py>, timeout_s: f64) -> MaybeDict<'py> {
        self.next_record(
            py,
            timeout_s,
            |l, d| l.proprioception(d),
            |p| self.proprioception(py, &[p]),
        )
    }

    /// `DbotEnv.step`'s exchange in one call: for each of `cycles` bus cycles, sends
    /// `angles_rad` (and `torques_nm`) as `send_setpoint` does and takes that cycle's record as
    /// `next_proprioception(timeout_s)` does. Returns the last record's observation, a dict of
    /// float arrays (`present_rad`, `velocity_rad_s`, `load_raw`, `setpoint_age` of shape (1,)
    /// and, on the physics robot, `strain_microstrain` and `strain_age_s` of shape (1,)), with
    /// its `time_s`; None if a record did not come (streaming stopped).
    /// `last_stream_record()` gives that record whole.
    #[pyo3(signature = (angles_rad, torques_nm = None, cycles = 1, timeout_s = 0.1))]
    fn stream_step<'py>(
        &self,
        py: Python<'py>,
        angles_rad: &Bound<'_, PyAny>,
        torques_nm: Option<&Bound<'_, PyAny>>,
        cycles: u32,
        timeout_s: f64,
    ) -> PyResult<Option<(Bound<'py, PyDict>, f64)>> {
        if cycles == 0 {
            return Err(value_error("cycles = 0: give 1 or more"));
        }
        let wait = seconds(timeout_s, "timeout_s")?;
        let (angles, torques) = stream::vectors(angles_rad, torques_nm)?;
        let Some(rec) = self.exchange(py, &angles, torques.as_deref(), cycles, wait)? else {
            return Ok(None);
        };
        let obs = self.with(py, |l| {
            Ok(crate::stream::observation(
                py,
                &rec,
                l.transport().physics(),
            ))
        })??;
        let time_s = rec.time_us as f64 * 1e-6;
        self.keep_step(rec);
        Ok(Some((obs, time_s)))
    }

    /// The record the last `stream_step` took, whole, as `next_proprioception` gives it (its
    /// strain as the physics robot kept it for that record's time; a strain board's latest
    /// sample as of now); None before the first.
    fn last_stream_record<'py>(&self, py: Python<'py>) -> MaybeDict<'py> {
        let rec = self
            .last_step
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        rec.map(|r| self.proprioception_unnoted(py, &[r]))
            .transpose()
    }

    /// Every proprioception record received so far, without waiting: a dict of arrays.
    fn drain_proprioception<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let recs = self.with(py, |l| l.drain_proprioception())?;
        self.proprioception(py, &recs)
    }

    /// Starts the strain board on `port` (a serial path or pseudo-terminal; the servo board's own
    /// port is refused) beside this board for streaming, recording it into `strain_dir` as
    /// `record(..., strain=)` does (`board::strain::StrainBeside`: calibrated first, its first
    /// sample the zero-strain baseline). From then on every proprioception record carries, as on
    /// the physics robot, `strain_names`, `strain_microstrain` ((counts - baseline) / the gauge's
    /// gain, the latest sample when the host read the record) and `strain_age_s` (how long
    /// before that the sample's line ended, host clock), and `strain_stopped` (the strain board
    /// failed or went away: the servo stream goes on, the ages grow), and `strain_reading` (per
    /// gauge `"calibrated"` or `"ESTIMATE"`). A gauge's gain is `model`'s calibration file's
    /// (docs/identification.md, "Calibrated readings") when it has the gauge, else
    /// `counts_per_microstrain` (an ESTIMATE; needed for every gauge the calibration lacks).
    /// Not on the physics robot (its records carry its simulated gauges).
    #[pyo3(signature = (port, strain_dir, counts_per_microstrain = None, model = None))]
    fn attach_strain(
        &self,
        py: Python<'_>,
        port: &str,
        strain_dir: std::path::PathBuf,
        counts_per_microstrain: Option<f64>,
        model: Option<&crate::model::Model>,
    ) -> PyResult<()> {
        if let Some(g) = counts_per_microstrain
            && !(g.is_finite() && g > 0.0)
        {
            return Err(value_error(format!(
                "counts_per_microstrain = {g}: give the strain board's gain, a positive number of counts per microstrain"
            )));
        }
        let gains = StrainGains::of(model.map(|m| &m.inner), counts_per_microstrain)?;
        let kind = self.with(py, |l| Ok(l.transport().kind()))?;
        if kind == "physics" {
            return Err(value_error(format!(
                "strain port {port:?}: {} is the physics robot, whose proprioception already carries its simulated gauges",
                self.port
            )));
        }
        if self
            .strain
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_some()
        {
            return Err(value_error(format!(
                "strain port {port:?}: a strain board is attached already (detach_strain first)"
            )));
        }
        std::fs::create_dir_all(&strain_dir)
            .map_err(|e| value_error(format!("strain_dir {}: {e}", strain_dir.display())))?;
        let servo = self.port.clone();
        let b = py
            .detach(|| ::board::strain::StrainBeside::start(port, &servo, &strain_dir))
            .map_err(|e| value_error(format!("strain port {port:?}: {e}")))?;
        *self.strain.lock().unwrap_or_else(|e| e.into_inner()) = Some((b, gains));
        Ok(())
    }

    /// Stops the strain board `attach_strain` started and aligns its `strain.csv` with this
    /// board's clock; returns None, or why the strain stream stopped early (its rows are kept).
    fn detach_strain(&self, py: Python<'_>) -> PyResult<Option<String>> {
        let b = self.strain.lock().unwrap_or_else(|e| e.into_inner()).take();
        let Some((b, _)) = b else {
            return Err(value_error(
                "no strain board is attached (attach_strain first)",
            ));
        };
        let end = py.detach(|| b.finish());
        let mut error = end.recording.err().map(|e| e.to_string());
        if let Err(e) = &end.clock {
            error.get_or_insert_with(|| e.to_string());
        }
        Ok(error)
    }

    /// The physics robot's simulated strain gauges, the latest sample (taken every 24 ms of
    /// simulated time, as the strain board's lines come): `time_s`, `names` (the strain board's
    /// gauge names, e.g. `LF_troch_axial`) and `microstrain` (per gauge). None before the first
    /// bus cycle; BoardError on any other kind of port.
    fn strain<'py>(&self, py: Python<'py>) -> MaybeDict<'py> {
        let physics = self.with(py, |l| Ok(l.transport().physics().is_some()))?;
        if !physics {
            return Err(board_error(format!(
                "{}: no simulated strain gauges: they exist only on the physics robot (open \
                 `physics` or `physics:SCENE`)",
                self.port
            )));
        }
        let s = self.with(py, |l| Ok(l.transport().strain()))?;
        s.map(|s| {
            let d = PyDict::new(py);
            d.set_item("time_s", s.time_s)?;
            d.set_item("names", &s.names[..])?;
            d.set_item(
                "microstrain",
                numpy::ndarray::Array1::from(s.microstrain()).to_pyarray(py),
            )?;
            Ok(d)
        })
        .transpose()
    }

    fn __repr__(&self) -> String {
        format!("Board(port={:?})", self.port)
    }
}

/// Per strain board column the gain its counts are read through and whether it is calibrated.
#[derive(Debug, Clone)]
pub struct StrainGains {
    pub gains: Vec<f64>,
    pub readings: Vec<&'static str>,
}

impl StrainGains {
    /// Each gauge's gain from `model`'s calibration, else `fallback` (an ESTIMATE).
    fn of(model: Option<&planner::model::Model>, fallback: Option<f64>) -> PyResult<Self> {
        let mut out = Self {
            gains: Vec::new(),
            readings: Vec::new(),
        };
        let mut missing = Vec::new();
        for name in ::board::strain::channels::names() {
            let cal = model
                .and_then(|m| m.calibration.as_ref())
                .and_then(|c| c.gauge_gain(&name));
            match (cal, fallback) {
                (Some(_), _) => out.readings.push("calibrated"),
                (None, Some(_)) => out.readings.push("ESTIMATE"),
                (None, None) => {
                    missing.push(name);
                    continue;
                }
            }
            out.gains.push(cal.or(fallback).unwrap_or(f64::NAN));
        }
        if !missing.is_empty() {
            return Err(value_error(format!(
                "counts_per_microstrain = None: give the strain board's gain, a positive number of counts per microstrain, for the {} gauges the model's calibration has none for ({}, ...)",
                missing.len(),
                missing[0]
            )));
        }
        Ok(out)
    }
}

/// The store's health (what the board found at start-up, less what uploads since cleared): `"ok"`,
/// or the line `dbot gaits` prints (`board::slot_health::store_line`): `"store damaged: slot 0
/// fell back"`, `"store damaged: no readable record in any slot"`.
fn store_health(slots: &[protocol::SlotInfo]) -> String {
    board::slot_health::store_line(slots).unwrap_or_else(|| "ok".to_owned())
}

/// The play command of `play()` and `queue_gait()`: `period_scale` times the planned period
/// (0.1 to 10), `steps` whole steps or until stopped.
fn scaled_command(
    slot: u8,
    steps: Option<u32>,
    period_scale: f64,
    backward: bool,
) -> PyResult<PlayCommand> {
    let scale = protocol::units::to_fixed(period_scale, 1000.0, 100, 10_000)
        .ok_or_else(|| value_error(format!("period_scale = {period_scale}: give 0.1..=10")))?;
    Ok(PlayCommand::new(
        slot,
        Direction::backward_if(backward),
        scale as u16,
        steps.map_or(Steps::Continuous, Steps::Count),
    ))
}
