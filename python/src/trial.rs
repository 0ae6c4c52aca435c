//! `dbot.read_trial(path)`: a trial folder written by `dbot record`, read by the board library's
//! one reader (`board::trial::read_trial`), as NumPy arrays ([record] and [record, joint], one
//! record per bus cycle) with its metadata (trial.json as a dict).

use std::path::PathBuf;

use numpy::ToPyArray;
use numpy::ndarray::{Array1, Array2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

/// Reads the trial folder `path`: a dict of arrays (`time_s`, `cycle`, `step`, `slice` per
/// record; `platform_goal_ticks`, `platform_present_ticks` per record, NaN without a platform;
/// `run_state` per record (a list of str such as `"Walking"`, `"Fault"`; None in a trial written
/// before the column);
/// `planned_rad`, `commanded_rad`, `present_rad`, `velocity_rad_s`, `load_raw`,
/// `torque_estimate_nm`, `modelled_torque_nm`, `error`, `flags` per record and joint, NaN where
/// the CSV has no value), `joint_names`, `meta` (trial.json) and `path`. ValueError naming the
/// file and line of anything it cannot read.
#[pyfunction]
pub fn read_trial<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let t = board::trial::read_trial(&path).map_err(value_error)?;
    let joints = t.meta.joints.len().max(1);
    // Rows come cycle by cycle, every joint of a cycle in turn.
    let records: Vec<&[board::record::Row]> = t.rows.chunks(joints).collect();
    let n = records.len();
    let d = PyDict::new(py);
    let first = |g: &dyn Fn(&board::record::Row) -> f64| {
        Array1::from_iter(records.iter().map(|r| g(&r[0])))
    };
    d.set_item("time_s", first(&|r| r.time_s).to_pyarray(py))?;
    let ifirst = |g: &dyn Fn(&board::record::Row) -> i64| {
        Array1::from_iter(records.iter().map(|r| g(&r[0])))
    };
    d.set_item("cycle", ifirst(&|r| i64::from(r.cycle)).to_pyarray(py))?;
    d.set_item("step", ifirst(&|r| i64::from(r.step)).to_pyarray(py))?;
    d.set_item("slice", ifirst(&|r| i64::from(r.slice)).to_pyarray(py))?;
    // The board's run state per record; None in a trial written before the column.
    let states: Vec<Option<&str>> = records
        .iter()
        .map(|r| r.first().and_then(|r| r.state).map(|s| s.key()))
        .collect();
    d.set_item("run_state", states)?;
    let ticks = |v: Option<u16>| v.map_or(f64::NAN, f64::from);
    d.set_item(
        "platform_goal_ticks",
        first(&|r| ticks(r.platform_goal_ticks)).to_pyarray(py),
    )?;
    d.set_item(
        "platform_present_ticks",
        first(&|r| ticks(r.platform_present_ticks)).to_pyarray(py),
    )?;
    let cell = |g: &dyn Fn(&board::record::Row) -> f64| {
        Array2::from_shape_fn((n, joints), |(i, j)| records[i].get(j).map_or(f64::NAN, g))
    };
    let none = |v: Option<f64>| v.unwrap_or(f64::NAN);
    d.set_item("planned_rad", cell(&|r| none(r.planned_rad)).to_pyarray(py))?;
    d.set_item("commanded_rad", cell(&|r| r.commanded_rad).to_pyarray(py))?;
    d.set_item("present_rad", cell(&|r| r.present_rad).to_pyarray(py))?;
    d.set_item("velocity_rad_s", cell(&|r| r.velocity_rad_s).to_pyarray(py))?;
    d.set_item(
        "torque_estimate_nm",
        cell(&|r| none(r.torque_estimate_nm)).to_pyarray(py),
    )?;
    d.set_item(
        "modelled_torque_nm",
        cell(&|r| none(r.modelled_nm)).to_pyarray(py),
    )?;
    let raw = |g: &dyn Fn(&board::record::Row) -> i32| {
        Array2::from_shape_fn((n, joints), |(i, j)| records[i].get(j).map_or(0, g))
    };
    d.set_item("load_raw", raw(&|r| i32::from(r.load_raw)).to_pyarray(py))?;
    d.set_item("error", raw(&|r| i32::from(r.error)).to_pyarray(py))?;
    d.set_item("flags", raw(&|r| i32::from(r.flags)).to_pyarray(py))?;
    d.set_item("joint_names", t.meta.joints.clone())?;
    let meta = py
        .import("json")?
        .call_method1("loads", (t.meta.to_json(),))?;
    d.set_item("meta", meta)?;
    d.set_item("path", t.path.display().to_string())?;
    Ok(d)
}
