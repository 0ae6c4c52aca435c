//! `dbot._native`: the PyO3 module behind the `dbot` Python package. Thin bindings over the host
//! libraries `planner` (models, planning, plan directories), `board` (the link, streaming) and
//! `physics` (robots opened by name, the physics robot's body); every rule lives in Rust, this crate only
//! converts between Python/NumPy values and the host types.

mod arrays;
mod bench;
mod board;
mod body;
mod compare;
mod doctor;
mod env_step;
mod errors;
mod excitation;
mod identify;
mod lab;
mod model;
mod names;
mod plan;
mod plan_dir;
mod records;
mod render;
mod standing;
mod stream;
mod trial;
mod trial_record;
mod vector;
mod vector_sub;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("DbotError", py.get_type::<errors::DbotError>())?;
    m.add("BoardError", py.get_type::<errors::BoardError>())?;
    m.add("TrialFaulted", py.get_type::<errors::TrialFaulted>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("BUILTIN_MODELS", planner::model::BUILTIN_NAMES.to_vec())?;
    m.add_class::<model::Model>()?;
    m.add_class::<plan::Plan>()?;
    m.add_function(wrap_pyfunction!(plan::plan, m)?)?;
    m.add_class::<plan_dir::PlanDir>()?;
    m.add_function(wrap_pyfunction!(plan_dir::read_plan_dir, m)?)?;
    m.add_class::<board::Board>()?;
    m.add_class::<bench::Bench>()?;
    m.add_class::<env_step::EnvStepper>()?;
    m.add_class::<vector_sub::Options>()?;
    m.add_class::<vector::VectorCore>()?;
    m.add_function(wrap_pyfunction!(trial::read_trial, m)?)?;
    m.add_function(wrap_pyfunction!(compare::compare, m)?)?;
    m.add_function(wrap_pyfunction!(doctor::doctor, m)?)?;
    lab::register(m)?;
    render::register(m)?;
    standing::register(m)?;
    excitation::register(m)?;
    identify::register(m)?;
    Ok(())
}
