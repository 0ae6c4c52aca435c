//! Telemetry, proprioception and status as Python values: per-cycle records become one dict of
//! NumPy arrays ([record] and [record, joint]) in SI units, with the joints' names
//! (`joint_names`, one per column); raw registers stay raw and say so.

use numpy::ToPyArray;
use numpy::ndarray::{Array1, Array2};
use protocol::{Counters, JointFeedback, LossReason, Proprioception, SlotInfo, Status, Telemetry};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::names::JointNaming;

/// A joint's present angle, rad: the one conversion every record and observation of it makes
/// (`Board`'s records, `Board.stream_step`, `VectorEnv`'s rows), so all hold the same double.
pub fn present_rad(x: &JointFeedback) -> f64 {
    f64::from(x.present) / protocol::units::ANGLE_PER_RAD
}

/// A joint's present velocity, rad/s, as [`present_rad`] converts the angle.
pub fn velocity_rad_s(x: &JointFeedback) -> f64 {
    f64::from(x.velocity) / protocol::units::VELOCITY_PER_RAD_S
}

/// Per-joint columns of a batch of records, converted to SI where a unit exists, and the name of
/// each column.
fn joint_columns<'py>(
    py: Python<'py>,
    d: &Bound<'py, PyDict>,
    rows: &[&[JointFeedback]],
    naming: &JointNaming,
) -> PyResult<()> {
    let n = rows.len();
    let j = rows.iter().map(|r| r.len()).max().unwrap_or(0);
    d.set_item("joint_names", naming.names(j))?;
    let get = |i: usize, k: usize| rows[i].get(k).copied();
    let f = |conv: &dyn Fn(&JointFeedback) -> f64| {
        Array2::from_shape_fn((n, j), |(i, k)| get(i, k).map_or(f64::NAN, |x| conv(&x)))
    };
    let angle = protocol::units::ANGLE_PER_RAD;
    d.set_item(
        "commanded_rad",
        f(&|x| f64::from(x.commanded) / angle).to_pyarray(py),
    )?;
    d.set_item("present_rad", f(&present_rad).to_pyarray(py))?;
    d.set_item("velocity_rad_s", f(&velocity_rad_s).to_pyarray(py))?;
    let raw = |g: &dyn Fn(&JointFeedback) -> i32| {
        Array2::from_shape_fn((n, j), |(i, k)| get(i, k).map_or(0, |x| g(&x)))
    };
    // Register 126 as read: MX-28 load in 0.1 % of max, MX-64 current in ~3.36 mA.
    d.set_item("load_raw", raw(&|x| i32::from(x.load)).to_pyarray(py))?;
    d.set_item("error", raw(&|x| i32::from(x.error)).to_pyarray(py))?;
    d.set_item("flags", raw(&|x| i32::from(x.flags)).to_pyarray(py))?;
    Ok(())
}

/// Playback telemetry records as a dict of arrays.
pub fn telemetry_dict<'py>(
    py: Python<'py>,
    recs: &[Telemetry],
    naming: &JointNaming,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |g: &dyn Fn(&Telemetry) -> f64| Array1::from_iter(recs.iter().map(g));
    d.set_item("time_s", col(&|t| t.time_us as f64 * 1e-6).to_pyarray(py))?;
    let icol = |g: &dyn Fn(&Telemetry) -> i64| Array1::from_iter(recs.iter().map(g));
    d.set_item("cycle", icol(&|t| i64::from(t.cycle)).to_pyarray(py))?;
    d.set_item("step", icol(&|t| i64::from(t.step)).to_pyarray(py))?;
    d.set_item("slice", icol(&|t| i64::from(t.slice)).to_pyarray(py))?;
    d.set_item(
        "cycle_us",
        icol(&|t| i64::from(t.bus.cycle_us)).to_pyarray(py),
    )?;
    // The board's run state per record (`"Walking"`, ..., `"Fault"`).
    let states: Vec<&str> = recs.iter().map(|t| t.state.key()).collect();
    d.set_item("run_state", states)?;
    // The platform servo (goal and present position, ticks; NaN in a record without it), only
    // when a platform is set up.
    if recs.iter().any(|t| t.platform.is_some()) {
        let ticks = |g: fn(&protocol::PlatformFeedback) -> u16| {
            col(&|t| t.platform.as_ref().map_or(f64::NAN, |p| f64::from(g(p)))).to_pyarray(py)
        };
        d.set_item("platform_goal_ticks", ticks(|p| p.goal))?;
        d.set_item("platform_present_ticks", ticks(|p| p.present))?;
    }
    let rows: Vec<&[JointFeedback]> = recs.iter().map(|t| t.joints.as_slice()).collect();
    joint_columns(py, &d, &rows, naming)?;
    // Each servo's last heat and supply reading ([record, joint]; NaN until first read).
    let j = rows.iter().map(|r| r.len()).max().unwrap_or(0);
    let health = |g: &dyn Fn(&protocol::ServoHealth) -> f64| {
        Array2::from_shape_fn((recs.len(), j), |(i, k)| {
            recs[i]
                .health
                .get(k)
                .filter(|h| h.is_read())
                .map_or(f64::NAN, g)
        })
        .to_pyarray(py)
    };
    d.set_item("temperature_c", health(&|h| f64::from(h.temperature_c)))?;
    d.set_item(
        "input_voltage_v",
        health(&|h| f64::from(h.voltage_dv) / 10.0),
    )?;
    Ok(d)
}

/// A heat or supply alarm as a dict: `joint`, `id`, `kind` (`"hot"`, `"low_voltage"`,
/// `"high_voltage"`), `level` (`"warn"`, `"stop"`), `value` and `limit` (degC or V), `message`
/// (the words `dbot status` prints, naming the joint by `names`).
pub fn health_alarm_dict<'py>(
    py: Python<'py>,
    a: &protocol::HealthAlarm,
    names: &[String],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("joint", a.joint)?;
    d.set_item("id", a.id)?;
    let (kind, scale) = match a.kind {
        protocol::HealthKind::Hot => ("hot", 1.0),
        protocol::HealthKind::LowVoltage => ("low_voltage", 0.1),
        protocol::HealthKind::HighVoltage => ("high_voltage", 0.1),
    };
    d.set_item("kind", kind)?;
    d.set_item(
        "level",
        match a.level {
            protocol::HealthLevel::Warn => "warn",
            protocol::HealthLevel::Stop => "stop",
        },
    )?;
    d.set_item("value", f64::from(a.value) * scale)?;
    d.set_item("limit", f64::from(a.limit) * scale)?;
    d.set_item("message", board::health::alarm_line(a, names))?;
    Ok(d)
}

/// Streaming proprioception records as a dict of arrays.
pub fn proprioception_dict<'py>(
    py: Python<'py>,
    recs: &[Proprioception],
    naming: &JointNaming,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |g: &dyn Fn(&Proprioception) -> f64| Array1::from_iter(recs.iter().map(g));
    d.set_item("time_s", col(&|p| p.time_us as f64 * 1e-6).to_pyarray(py))?;
    let icol = |g: &dyn Fn(&Proprioception) -> i64| Array1::from_iter(recs.iter().map(g));
    d.set_item("time_us", icol(&|p| p.time_us as i64).to_pyarray(py))?;
    d.set_item("cycle", icol(&|p| i64::from(p.cycle)).to_pyarray(py))?;
    d.set_item(
        "setpoint_seq",
        icol(&|p| i64::from(p.setpoint_seq)).to_pyarray(py),
    )?;
    d.set_item(
        "setpoint_age",
        icol(&|p| i64::from(p.setpoint_age)).to_pyarray(py),
    )?;
    d.set_item(
        "cycle_us",
        icol(&|p| i64::from(p.bus.cycle_us)).to_pyarray(py),
    )?;
    let rows: Vec<&[JointFeedback]> = recs.iter().map(|p| p.joints.as_slice()).collect();
    joint_columns(py, &d, &rows, naming)?;
    Ok(d)
}

/// The board's counters since boot, one named integer each (keys as in `protocol::Counters`).
fn counters_dict<'py>(py: Python<'py>, c: &Counters) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("cycles", c.cycles)?;
    d.set_item("missed_deadlines", c.missed_deadlines)?;
    d.set_item("bus_timeouts", c.bus_timeouts)?;
    d.set_item("crc_errors", c.crc_errors)?;
    d.set_item("rejected_frames", c.rejected_frames)?;
    d.set_item("telemetry_dropped", c.telemetry_dropped)?;
    d.set_item("rate_limited", c.rate_limited)?;
    Ok(d)
}

/// The board's status as a dict (`state`, `fault`, `torque_enabled`, `counters`): `state` is the
/// state's key (`Streaming`); `fault` holds `kind` and `name` (both the fault's key,
/// `ServoStuck`), `detail` (what it is in words, with its numbers: `servo stuck: its goal moved
/// over 312 ticks, its position over 0`), `joint` and `message` (the whole sentence).
pub fn status_dict<'py>(py: Python<'py>, s: &Status) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("state", s.state.key())?;
    match &s.fault {
        Some(f) => {
            let fd = PyDict::new(py);
            fd.set_item("kind", f.kind.name())?;
            fd.set_item("detail", f.kind.to_string())?;
            fd.set_item("name", f.kind.name())?;
            fd.set_item("message", f.to_string())?;
            fd.set_item("joint", f.joint)?;
            d.set_item("fault", fd)?;
        }
        None => d.set_item("fault", py.None())?,
    }
    d.set_item("torque_enabled", s.torque_enabled)?;
    d.set_item("counters", counters_dict(py, &s.counters)?)?;
    d.set_item("playback", s.playback.map(|p| (p.slot, p.step, p.slice)))?;
    Ok(d)
}

/// What slot `s` lost, in the words `dbot gaits` prints (`board::slot_health::loss`, the one
/// place they are made), after the slot's number; None for a healthy slot.
pub fn loss_message(s: &SlotInfo) -> Option<String> {
    board::slot_health::loss(s).map(|l| format!("slot {}: {l}", s.slot))
}

/// One gait slot as a dict: `slot`, `gait` (None, or `name`, `crc`, `joints`, `slices`,
/// `period_s`, `duty`), `lost` (None, or `seq`, `crc`, `name`, `reason` `"table_crc"` or
/// `"record_damaged"`) and `message` (what was lost, in words; None for a healthy slot).
pub fn slot_dict<'py>(py: Python<'py>, s: &SlotInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("slot", s.slot)?;
    match &s.gait {
        Some(g) => {
            let gd = PyDict::new(py);
            gd.set_item("name", g.header.name_str())?;
            gd.set_item("crc", g.crc)?;
            gd.set_item("joints", g.header.joint_count)?;
            gd.set_item("slices", g.header.slice_count)?;
            gd.set_item("period_s", f64::from(g.header.step_period_us) * 1e-6)?;
            gd.set_item("duty", f64::from(g.header.duty) * 1e-4)?;
            d.set_item("gait", gd)?;
        }
        None => d.set_item("gait", py.None())?,
    }
    match &s.lost {
        Some(l) => {
            let ld = PyDict::new(py);
            ld.set_item("seq", l.seq)?;
            ld.set_item("crc", l.crc)?;
            ld.set_item("name", l.name_str())?;
            ld.set_item(
                "reason",
                match l.reason {
                    LossReason::TableChecksum => "table_crc",
                    LossReason::RecordDamaged => "record_damaged",
                },
            )?;
            d.set_item("lost", ld)?;
        }
        None => d.set_item("lost", py.None())?,
    }
    d.set_item("message", loss_message(s))?;
    Ok(d)
}

/// Adds a strain recording's arrays to a telemetry dict (see `Board.record`).
pub fn strain_items(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    end: ::board::strain::StrainEnd,
    dir: &std::path::Path,
) -> PyResult<()> {
    let mut error = end.recording.err().map(|e| e.to_string());
    if let Err(e) = &end.clock {
        error.get_or_insert_with(|| e.to_string());
    }
    let csv = dir.join(::board::strain::recorder::STRAIN_CSV);
    let a = ::board::strain::beside::read_aligned(&csv).map_err(crate::errors::value_error)?;
    let t = Array1::from_iter(a.time_s.iter().map(|t| t.unwrap_or(f64::NAN)));
    let n = a.counts.len();
    let counts = Array2::from_shape_fn((n, ::board::strain::channels::CHANNELS), |(i, c)| {
        a.counts[i][c]
    });
    d.set_item("strain_time_s", t.to_pyarray(py))?;
    d.set_item("strain_counts", counts.to_pyarray(py))?;
    d.set_item("strain_names", ::board::strain::channels::names())?;
    d.set_item("strain_error", error)?;
    Ok(())
}

/// How old a gauge sample taken at `sample_s` is at a record of `record_s` (both the simulated
/// clock, s). The record's time comes from the board's microseconds, the sample's from the body's
/// summed timesteps, so a sample taken at the record's instant can land a rounding after it
/// (-3e-14 s): that is an age of 0, not a negative one.
pub fn strain_age_s(record_s: f64, sample_s: f64) -> f64 {
    (record_s - sample_s).max(0.0)
}

/// On the physics robot, what each proprioception record knew of the strain gauges: the latest
/// simulated sample at or before its time (`physics::PhysicsRobot::strain_at`; `strain`: per
/// record its sample's time, s, and microstrain per gauge, None if none). Adds
/// `strain_names`, `strain_microstrain` ([record, gauge]; NaN where no sample was that old) and
/// `strain_age_s` ([record]: the record's time less the sample's).
pub fn proprioception_strain(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    recs: &[Proprioception],
    strain: &[Option<(f64, Vec<f64>)>],
    names: Vec<String>,
) -> PyResult<()> {
    let n = names.len();
    let m = Array2::from_shape_fn((recs.len(), n), |(i, g)| {
        strain[i]
            .as_ref()
            .and_then(|s| s.1.get(g).copied())
            .unwrap_or(f64::NAN)
    });
    let age = Array1::from_iter(recs.iter().zip(strain).map(|(p, s)| {
        s.as_ref()
            .map_or(f64::NAN, |s| strain_age_s(p.time_us as f64 * 1e-6, s.0))
    }));
    d.set_item("strain_names", names)?;
    d.set_item("strain_microstrain", m.to_pyarray(py))?;
    d.set_item("strain_age_s", age.to_pyarray(py))?;
    Ok(())
}

/// With a strain board beside a board (`Board.attach_strain`), what each proprioception record
/// knew of the gauges when the host read it: the same `strain_names`, `strain_microstrain`
/// ([record, gauge]: (counts - baseline) / the gauge's gain; NaN before the first sample),
/// `strain_reading` (per gauge `calibrated` or `ESTIMATE`) and
/// `strain_age_s` ([record]: `now` less the instant the sample's line ended) as on the physics
/// robot, gauges in the strain board's order.
pub fn proprioception_strain_board(
    py: Python<'_>,
    d: &Bound<'_, PyDict>,
    records: usize,
    latest: Option<::board::strain::recorder::LatestSample>,
    now: std::time::Instant,
    gains: &crate::board::StrainGains,
) -> PyResult<()> {
    let names = ::board::strain::channels::names();
    let m = Array2::from_shape_fn((records, names.len()), |(_, g)| {
        latest
            .as_ref()
            .map_or(f64::NAN, |l| (l.counts[g] - l.baseline[g]) / gains.gains[g])
    });
    d.set_item("strain_reading", gains.readings.clone())?;
    let age = latest.as_ref().map_or(f64::NAN, |l| {
        now.saturating_duration_since(l.host).as_secs_f64()
    });
    d.set_item("strain_names", names)?;
    d.set_item("strain_microstrain", m.to_pyarray(py))?;
    d.set_item(
        "strain_age_s",
        Array1::from_elem(records, age).to_pyarray(py),
    )?;
    Ok(())
}
