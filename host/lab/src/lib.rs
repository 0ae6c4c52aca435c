//! `lab`: everything a researcher computes with Drosophibot II, reachable from Rust and Python
//! alike (`dbot` parses arguments, calls this and prints; progress and Ctrl-C come in as
//! callbacks). The fit statistics themselves (the two R^2, RMS, mean and SD) are
//! `planner::analysis::fit`.
//!
//! - [`walk`]: playing and recording one walk; the walks' inverse dynamics.
//! - [`walk_body`], [`walk_fits`], [`walk_bias`]: the figures of a recorded walk against its plan
//!   (distance per step, tracking per leg, loads and contact forces against the plan, what the
//!   torque bias buys).
//! - [`walk_files`]: a recorded walk, its animation and fit files.
//! - [`demo`]: the walks of `dbot demo` on one robot; [`plan_walk`]: a walk of a plan directory
//!   on a fresh physics robot and its figures (what Python calls).
//! - [`walk_turn`]: a planned curve walked on the physics robot, its turn per step and radius
//!   measured; [`walk_sequence`]: several gaits (straight, a curve, backward) as one run.
//! - [`paper_robot`]: the paper's robot experiments (figures 5 to 7) on the physics robot.
//! - [`paper_comparison`]: the paper's robot-versus-fly comparison (tables S2 to S8).
//! - [`plan_comparison`], [`overlay`]: two plans (or trials, [`trial_traces`]) DoF by DoF, a
//!   speed sweep, their plots.
//! - [`strain_compare`]: a recording's strain against the plan's prediction, per gauge;
//!   [`strain_walk`]: the physics robot's simulated gauges walking, against the prediction.
//! - [`physics_serve`]: the physics robot's board and strain board on pseudo-terminals
//!   (`dbot sim-bus --physics`).
//! - [`physics_walk`]: one walk of a table on a fresh physics robot, followed until it stands
//!   (what the substrate, strain and perturbation walks share).
//! - [`perturbation`]: a walk with the perturbation platform under one foot, that leg's load per step.
//! - [`substrates`]: one gait walked on several substrates, slip per foot and travel per step.
//! - [`trial_record`]: recording a trial folder from a board (`dbot record`, `Board.record_trial`).
//! - [`plan_dir_write`]: the one writer of a plan directory (files, plots, the dynamics, strain).
//! - [`validation`]: the run results of docs/validation.md.
//! - [`identify`]: the servo dynamics fitted to suspended excitation trials replayed on the
//!   physics robot's body, and the stand-in robot that checks it (`dbot identify`);
//!   [`replay`]: a trial replayed on a model, per joint R^2 and RMS (`dbot replay`);
//!   [`excite_files`]: the excitation's step tables written (`dbot excite`).
//! - [`doctor`]: the bring-up check of a freshly wired robot (`dbot doctor`, `dbot.doctor()`).

pub mod calibrate;
pub mod demo;
pub mod doctor;
pub mod error;
pub mod excite_files;
pub mod identify;
pub mod markdown;
pub mod overlay;
pub mod paper_comparison;
pub mod paper_robot;
pub mod perturbation;
pub mod physics_serve;
pub mod physics_walk;
pub mod plan_comparison;
pub mod plan_dir_write;
pub mod plan_walk;
pub mod replay;
pub mod simulated;
pub mod steer_blend;
pub mod strain_compare;
pub mod strain_walk;
pub mod substrates;
pub mod trial_record;
pub mod trial_traces;
pub mod validation;
pub mod walk;
pub mod walk_bias;
pub mod walk_body;
pub mod walk_files;
pub mod walk_fits;
pub mod walk_sequence;
pub mod walk_turn;
pub mod walk_words;

pub use error::{Context, LabError, Result};
