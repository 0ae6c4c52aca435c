//! A plan directory's own consistency: plan.json's timing (period, duty, slices, step) against
//! its own parameters, its leg phases against its gait, and feet.csv's stance flags against that
//! timing. A hand-edited plan.json (issue #30: a period or duty changed) or a feet.csv that
//! contradicts its header would otherwise build and play a table whose timing and stance bits
//! disagree with its angles; the reader refuses it naming the field, the slice and the leg.

use std::path::Path;

use super::columns::{FEET_CSV, PLAN_JSON};
use super::{PlanDirError, PlanJson};

/// Relative agreement of two timings that one computed the other (rounding only).
const REL: f64 = 1e-9;
/// A slice this close (fraction of the period) to a leg's touch-down or lift-off may round either
/// way: its stance flag is not checked.
const EDGE: f64 = 1e-9;

fn disagree(dir: &Path, file: &str, problem: String) -> PlanDirError {
    PlanDirError::Disagrees {
        file: dir.join(file),
        problem,
    }
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= REL * a.abs().max(b.abs())
}

/// plan.json's timing, its phases and the stance flags `stance[slice][leg]` of feet.csv agree.
pub(crate) fn check(dir: &Path, json: &PlanJson, stance: &[Vec<bool>]) -> Result<(), PlanDirError> {
    let in_plan_json = |problem: String| disagree(dir, PLAN_JSON, problem);
    let p = &json.parameters;
    p.validate()
        .map_err(|e| in_plan_json(format!("parameters: {e}")))?;
    let period = p.period_s();
    if !same(json.period_s, period) {
        return Err(in_plan_json(format!(
            "period_s = {} s, but its parameters (swing_s {} s, duty {}) give a period of {period} s",
            json.period_s, p.swing_s, p.duty
        )));
    }
    if json.slices != p.slices {
        return Err(in_plan_json(format!(
            "slices = {}, but parameters.slices = {}",
            json.slices, p.slices
        )));
    }
    if !same(json.dt_s * json.slices as f64, json.period_s) {
        return Err(in_plan_json(format!(
            "dt_s = {} s x {} slices is not the period {} s",
            json.dt_s, json.slices, json.period_s
        )));
    }
    if json.leg_phases.len() != json.legs.len() {
        return Err(in_plan_json(format!(
            "{} leg_phases for {} legs",
            json.leg_phases.len(),
            json.legs.len()
        )));
    }
    for (leg, &phase) in json.legs.iter().zip(&json.leg_phases) {
        let want = p.gait.phase(*leg);
        if !(phase - want).abs().is_finite() || (phase - want).abs() > REL {
            return Err(disagree(
                dir,
                PLAN_JSON,
                format!(
                    "leg_phases: {} starts its cycle at {phase}, but the gait (phi_i {}, phi_c {}) puts it at {want}",
                    leg.name(),
                    p.gait.phi_i,
                    p.gait.phi_c
                ),
            ));
        }
    }
    for (s, row) in stance.iter().enumerate() {
        // As the planner's footpaths: the leg is in stance for the first `duty` of its own cycle.
        let t = s as f64 / json.slices as f64;
        for ((leg, &phase), &on) in json.legs.iter().zip(&json.leg_phases).zip(row) {
            let local = (t - phase).rem_euclid(1.0);
            let near_edge = local < EDGE || 1.0 - local < EDGE || (local - p.duty).abs() < EDGE;
            let planned = local < p.duty;
            if !near_edge && on != planned {
                let word = |b: bool| if b { "stance" } else { "swing" };
                return Err(disagree(
                    dir,
                    FEET_CSV,
                    format!(
                        "slice {s} leg {}: {}, but plan.json's duty {} and phase {phase} put the leg in {} there",
                        leg.name(),
                        word(on),
                        p.duty,
                        word(planned)
                    ),
                ));
            }
        }
    }
    Ok(())
}
