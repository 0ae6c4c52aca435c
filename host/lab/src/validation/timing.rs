//! The performance block of docs/validation.md: thread CPU time of the inverse dynamics of one
//! 100-slice cycle of Drosophibot II (table 1) in its three solver paths, and of its inverse
//! kinematics, measured in this process. Timings vary from run to run and between builds, so
//! `--check` compares them only as generous ratios, and only against a block measured with the
//! same build profile (see [`super::same_up_to_timing`]).

use std::fmt::Write as _;

use crate::error::Result;
use nix::time::{ClockId, clock_gettime};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;

/// The build profile named in the block.
pub const PROFILE: &str = if cfg!(debug_assertions) {
    "debug build"
} else {
    "release build"
};

/// Thread CPU time of `f`, s.
fn cpu_time(f: &mut dyn FnMut() -> Result<()>) -> Result<f64> {
    let t = || -> Result<f64> {
        let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID)?;
        Ok(t.tv_sec() as f64 + t.tv_nsec() as f64 * 1e-9)
    };
    let t0 = t()?;
    f()?;
    Ok(t()? - t0)
}

/// Median of `runs` timings of `f`, s.
fn median(runs: usize, f: &mut dyn FnMut() -> Result<()>) -> Result<f64> {
    let mut v = (0..runs)
        .map(|_| cpu_time(f))
        .collect::<Result<Vec<f64>>>()?;
    v.sort_by(f64::total_cmp);
    Ok(v[runs / 2])
}

pub fn performance() -> Result<String> {
    let model = builtin("drosophibot2")?;
    let params = StepParams::table1(&model.name);
    let plan = planner::plan::plan(&model, &params)?;
    let inputs = plan_inputs(&plan);
    let runs = if cfg!(debug_assertions) { 5 } else { 51 };
    let mut s = format!(
        "Median thread CPU time of {runs} runs in one `dbot validate` process ({PROFILE}), Drosophibot II, table 1, 100 slices:\n\n| case | time per 100-slice cycle |\n|---|---|\n"
    );
    let ik = median(runs, &mut || {
        planner::plan::plan(&model, &params)?;
        Ok(())
    })?;
    writeln!(
        s,
        "| plan: resting posture, footpaths, inverse kinematics of 22 joints, derivatives | {:.2} ms |",
        ik * 1e3
    )?;
    for (case, opts) in [
        (
            "inverse dynamics, no contact constraints (direct null-space solve)",
            DynamicsOptions::default(),
        ),
        (
            "inverse dynamics, friction cones (mu 0.5) + push-only feet (Clarabel)",
            DynamicsOptions {
                friction_cone: true,
                push_only: true,
                ..Default::default()
            },
        ),
        (
            "inverse dynamics, no contact constraints, forced through Clarabel",
            DynamicsOptions {
                always_clarabel: true,
                ..Default::default()
            },
        ),
    ] {
        let t = median(runs, &mut || {
            solve_cycle(&plan.model, &inputs, &opts)?;
            Ok(())
        })?;
        writeln!(s, "| {case} | {:.2} ms |", t * 1e3)?;
    }
    Ok(s)
}
