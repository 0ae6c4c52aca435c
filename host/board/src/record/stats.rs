//! Statistics of a recording: measured torque per phase of the step across steps (mean and spread),
//! and angle tracking error per joint (the sums themselves: `planner::analysis::fit`).

use planner::analysis::fit::{MeanSdSums, rms};

use super::csv_out::Row;

/// Measured and modelled torque of one joint at one slice of the step, over the recorded steps.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseStats {
    /// Phase in the step, 0..1 (slice / slices).
    pub phase: f64,
    pub modelled_nm: Option<f64>,
    /// Mean and standard deviation of the estimated torque, N m, over `n` samples.
    pub mean_nm: f64,
    pub sd_nm: f64,
    pub n: usize,
}

/// Per slice of the step, the statistics of `joint` over the rows that carry a torque estimate.
/// Rows of the start ramp (step 0 before walking) count like any other: the caller filters.
pub fn phase_stats(rows: &[Row], joint: usize, slices: usize) -> Vec<PhaseStats> {
    let samples = rows
        .iter()
        .filter(|r| r.joint == joint)
        .filter_map(|r| Some((usize::from(r.slice), r.torque_estimate_nm?, r.modelled_nm)));
    per_slice(samples, slices)
}

/// Mean and SD per slice of `(slice, value, modelled)` samples over a step of `slices` slices
/// (a slice beyond them is passed over; `modelled`: the latest a slice's samples carry). Slices
/// without samples are left out.
pub fn per_slice(
    samples: impl IntoIterator<Item = (usize, f64, Option<f64>)>,
    slices: usize,
) -> Vec<PhaseStats> {
    let mut acc = vec![(MeanSdSums::default(), None); slices];
    for (s, x, modelled) in samples {
        let Some(a) = acc.get_mut(s) else {
            continue;
        };
        a.0.add(x);
        a.1 = modelled.or(a.1);
    }
    acc.into_iter()
        .enumerate()
        .filter_map(|(s, (sums, modelled))| {
            let m = sums.finish()?;
            Some(PhaseStats {
                phase: s as f64 / slices as f64,
                modelled_nm: modelled,
                mean_nm: m.mean,
                sd_nm: m.sd,
                n: m.n,
            })
        })
        .collect()
}

/// How well `joint` followed the plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointTracking {
    pub joint: usize,
    /// Root mean square of present - planned angle (present - commanded where no plan is known), rad.
    pub rms_rad: f64,
    pub max_abs_rad: f64,
    pub samples: usize,
}

/// Tracking error of every joint over `rows`.
///
/// The reference is the planned angle: the commanded goal includes the torque bias, so under load
/// the present angle differs from it by about torque / stiffness by design.
pub fn tracking(rows: &[Row], joints: usize) -> Vec<JointTracking> {
    (0..joints)
        .map(|j| {
            let errors: Vec<f64> = rows
                .iter()
                .filter(|r| r.joint == j)
                .map(|r| r.present_rad - r.planned_rad.unwrap_or(r.commanded_rad))
                .collect();
            JointTracking {
                joint: j,
                rms_rad: rms(errors.iter().copied()).unwrap_or(0.0),
                max_abs_rad: errors.iter().fold(0.0f64, |m, e| m.max(e.abs())),
                samples: errors.len(),
            }
        })
        .collect()
}
