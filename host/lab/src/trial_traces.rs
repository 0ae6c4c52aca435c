//! A trial as DoF traces, so that `dbot compare` takes trials as it takes plans: per joint the
//! measured angle and the servo-load torque (an ESTIMATE from Present Load) at each slice of the
//! step table, averaged over the walking steps. Step 0 is left out (it holds the start ramp, whose
//! goals are not the table's), as is the step the walk stopped in, and any record of a joint that
//! did not answer or had its torque off.

use std::collections::BTreeMap;
use std::path::Path;

use board::trial::{Trial, read_trial};
use planner::analysis::DofTrace;
use planner::model::{JointKind, Leg};

use crate::bail;
use crate::error::{Context, Result};

/// `flags` bits of a telemetry row that make it no measurement of the walk: 1 no reply (the
/// values repeat the last good ones), 8 torque off (board::record, telemetry.csv's README).
const NOT_MEASURED: u8 = 1 | 8;

/// Whether `dir` is a trial folder (it holds `trial.json`) rather than a plan directory.
pub fn is_trial(dir: &Path) -> bool {
    dir.join(board::trial::TRIAL_JSON).is_file()
}

/// The DoF traces of the trial folder `dir` (see the module's header).
pub fn trial_traces(dir: &Path) -> Result<Vec<DofTrace>> {
    let trial = read_trial(dir).with_context(|| format!("reading the trial {}", dir.display()))?;
    traces(&trial)
}

/// The DoF traces of `trial`.
pub fn traces(trial: &Trial) -> Result<Vec<DofTrace>> {
    let place = trial.path.display();
    let Some(gait) = &trial.meta.gait else {
        bail!("trial {place}: no gait was played (trial.json has no `gait`): nothing to compare");
    };
    let slices = usize::from(gait.slices);
    // The last step begun: with a count it is the count (the walk then stands), without one the
    // step it was stopped in, which may be partial.
    let last = trial.rows.iter().map(|r| r.step).max().unwrap_or(0);
    let whole = match trial.meta.steps {
        Some(n) => n.min(last),
        None => last,
    };
    if whole < 2 {
        bail!(
            "trial {place}: {whole} whole step(s) recorded; comparing needs at least 2 (the first \
             holds the start ramp and is left out)"
        );
    }
    let mut kinds = Vec::with_capacity(trial.meta.joints.len());
    for name in &trial.meta.joints {
        kinds.push(dof_of(name).with_context(|| {
            format!(
                "trial {place}: joint `{name}` is not named LEG_JOINT (e.g. LF_CTr); record with \
                 --table or --plan (Python: table=, plan=) so the joints carry the model's names"
            )
        })?);
    }
    // Per joint and slice: sums and counts of angle and torque.
    let mut angle = vec![vec![(0.0, 0u32); slices]; kinds.len()];
    let mut torque = vec![vec![(0.0, 0u32); slices]; kinds.len()];
    for r in &trial.rows {
        if r.step < 1 || r.step >= whole || r.flags & NOT_MEASURED != 0 {
            continue;
        }
        let (Some(a), Some(t)) = (angle.get_mut(r.joint), torque.get_mut(r.joint)) else {
            bail!(
                "trial {place}: a row names joint {} of {}",
                r.joint,
                kinds.len()
            );
        };
        let s = usize::from(r.slice);
        if s >= slices {
            bail!(
                "trial {place}: a row at cycle {} is at slice {s} of a {slices}-slice gait",
                r.cycle
            );
        }
        a[s].0 += r.present_rad;
        a[s].1 += 1;
        if let Some(nm) = r.torque_estimate_nm {
            t[s].0 += nm;
            t[s].1 += 1;
        }
    }
    let mut by_dof: BTreeMap<(Leg, JointKind), DofTrace> = BTreeMap::new();
    for (j, &(leg, kind)) in kinds.iter().enumerate() {
        let name = &trial.meta.joints[j];
        let mut a = Vec::with_capacity(slices);
        for (s, &(sum, n)) in angle[j].iter().enumerate() {
            if n == 0 {
                bail!(
                    "trial {place}: joint {name} has no measured record at slice {s} in steps 1 \
                     to {}: record every cycle (--every 1, Python: every=1) or walk more steps",
                    whole - 1
                );
            }
            a.push(sum / f64::from(n));
        }
        // A joint whose servo model is unknown has no torque estimate: a flat 0 trace, which no
        // regression can fit (its R^2 is shown as `-`).
        let t = torque[j]
            .iter()
            .map(|&(sum, n)| if n == 0 { 0.0 } else { sum / f64::from(n) })
            .collect();
        let (lo, hi) = a
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(*v), h.max(*v))
            });
        by_dof.insert(
            (leg, kind),
            DofTrace {
                leg,
                kind,
                // A servo holding still moves a few ticks: 0.01 rad (6 ticks) is no DoF.
                mobile: hi - lo > 0.01,
                angle: a,
                torque: t,
            },
        );
    }
    Ok(by_dof.into_values().collect())
}

/// The leg and joint a model joint name (`LF_CTr`) stands for.
fn dof_of(name: &str) -> Option<(Leg, JointKind)> {
    let (leg, kind) = name.split_once('_')?;
    let leg = Leg::ALL.into_iter().find(|l| l.name() == leg)?;
    let kind = serde_json::from_value(serde_json::Value::String(kind.to_owned())).ok()?;
    Some((leg, kind))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joint_names_are_leg_and_kind() {
        assert_eq!(dof_of("LF_CTr"), Some((Leg::LF, JointKind::CTr)));
        assert_eq!(dof_of("RH_ThC1"), Some((Leg::RH, JointKind::ThC1)));
        assert_eq!(dof_of("J3"), None);
        assert_eq!(dof_of("XX_CTr"), None);
        assert_eq!(dof_of("LF_Knee"), None);
    }
}
