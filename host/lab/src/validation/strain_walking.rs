//! The `strain_walking` block of docs/validation.md and its plot: the demo's walk (the servo-safe
//! tripod of Drosophibot II on flat ground) played on the physics robot with the torque bias on
//! and off, its simulated gauges against the plan's prediction per gauge over the step phase
//! ([`crate::strain_walk`]), and `validation/strain_walking.png` (bias on, one panel per leg).

use std::fmt::Write;
use std::path::Path;

use planner::gait::StepParams;
use planner::model::builtin;

use crate::error::{Context, Result};
use crate::strain_walk::{StrainWalk, load_bearing, peak, walk_strain, write_strain_files};
use crate::walk::solve_walk_dynamics;

/// Steps walked; the first is left out (it starts from the ramp), so 4 give 3 whole steps.
pub const STEPS: u32 = 4;

/// The two walks, bias on then off, and the plot of the first (PNG bytes, drawn in `scratch`).
pub fn walks(scratch: &Path) -> Result<([StrainWalk; 2], Vec<u8>)> {
    let model = builtin("drosophibot2")?;
    let params = StepParams::preset("servo-safe", &model.name).context("servo-safe preset")?;
    let plan = planner::plan::plan(&model, &params).context("planning the step")?;
    let cycle = solve_walk_dynamics(&plan)?;
    let on = walk_strain(&plan, &cycle, STEPS, true)?;
    let off = walk_strain(&plan, &cycle, STEPS, false)?;
    let dir = scratch.join("strain_walking");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let [_, png] = write_strain_files(&dir, &plan, &on.fits)?;
    let f = dir.join(png);
    let bytes = std::fs::read(&f).with_context(|| f.display().to_string())?;
    Ok(([on, off], bytes))
}

/// The block: a summary line per walk and a row per gauge.
pub fn block(walks: &[StrainWalk; 2]) -> Result<String> {
    let [on, off] = walks;
    let mut s = String::new();
    for w in walks {
        let bearing = w.fits.iter().filter(|f| load_bearing(f, &w.fits)).count();
        let worst = w
            .fits
            .iter()
            .filter(|f| load_bearing(f, &w.fits))
            .filter_map(|f| Some((f.r2?, f.name.as_str())))
            .fold((f64::INFINITY, "-"), |a, b| if b.0 < a.0 { b } else { a });
        writeln!(
            s,
            "- bias {}: {} samples per gauge over steps 2 to {} (the first, from the ramp, left out); the {bearing} load-bearing gauges (predicted peak at least {:.0} % of the largest): median R^2 {}, lowest {:.2} ({})",
            if w.bias_on { "on" } else { "off" },
            w.fits.first().map_or(0, |f| f.samples),
            w.steps,
            crate::strain_walk::LOAD_BEARING_SHARE * 100.0,
            crate::plan_comparison::r2_cell(w.load_bearing_median_r2()),
            worst.0,
            worst.1
        )?;
    }
    s.push_str(
        "\n| gauge | predicted peak (microstrain) | R^2, bias on | RMS, bias on (microstrain) | R^2, bias off | RMS, bias off (microstrain) |\n|---|---|---|---|---|---|\n",
    );
    for (a, b) in on.fits.iter().zip(&off.fits) {
        writeln!(
            s,
            "| {}{} | {:.0} | {} | {:.1} | {} | {:.1} |",
            a.name,
            if load_bearing(a, &on.fits) { " *" } else { "" },
            peak(a),
            crate::plan_comparison::r2_cell(a.r2),
            a.rms,
            crate::plan_comparison::r2_cell(b.r2),
            b.rms
        )?;
    }
    s.push_str("\n(* load-bearing)\n");
    Ok(s)
}
