//! A walk's model-vs-measured comparisons over its whole steps (the first excluded: it starts
//! from the ramp): servo loads against the planned joint torques per joint, and the contact force
//! on each foot against the plan's ground reaction force per leg, each as the R^2 of the plan's
//! prediction ([`prediction_r2`]: 1 - SS_res / SS_tot) and RMS difference over every sample, and
//! per phase of the step (mean, SD) for the CSVs and plots.

use board::record::{PhaseStats, Row};
use physics::WalkLog;
use planner::analysis::fit::{prediction_r2, rms_difference};
use planner::model::Leg;

/// How well a model predicts one series of measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Joint or leg name.
    pub name: String,
    /// `None` when the measurements do not vary (R^2 undefined) or there are none.
    pub r2: Option<f64>,
    /// Root mean square of measured - model.
    pub rms: f64,
    pub samples: usize,
    /// Per slice of the step: the model and the measured statistics.
    pub modelled: Vec<f64>,
    pub measured: Vec<PhaseStats>,
}

impl Fit {
    /// The fit of `name` from its (measured, model) `pairs` and its measured `(slice, value)`
    /// samples, `modelled` per slice of the step (its length is the table's slice count).
    pub(crate) fn of(
        name: String,
        pairs: &[(f64, f64)],
        by_slice: &[(usize, f64)],
        modelled: Vec<f64>,
    ) -> Self {
        let (r2, rms) = fit_figures(pairs);
        Self {
            name,
            r2,
            rms,
            samples: pairs.len(),
            measured: per_slice(by_slice, modelled.len()),
            modelled,
        }
    }
}

/// The R^2 of the model predicting the measurements `pairs` (measured, model), and the RMS
/// difference (0 without samples).
pub(crate) fn fit_figures(pairs: &[(f64, f64)]) -> (Option<f64>, f64) {
    (prediction_r2(pairs), rms_difference(pairs).unwrap_or(0.0))
}

/// Mean and SD per slice of `(slice, value)` samples over a table of `slices` slices.
pub(crate) fn per_slice(samples: &[(usize, f64)], slices: usize) -> Vec<PhaseStats> {
    board::record::per_slice(samples.iter().map(|&(s, x)| (s, x, None)), slices)
}

/// Whether a sample of step `step` counts: a whole step after the first (of `steps` played).
pub(crate) fn counted(step: u32, steps: u32) -> bool {
    step >= 1 && step < steps
}

/// Servo load (ESTIMATE from Present Load) against the planned torque, per joint, over the rows of
/// whole steps after the first.
pub fn load_fits(rows: &[Row], names: &[String], modelled: &[Vec<f64>], steps: u32) -> Vec<Fit> {
    names
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let mine: Vec<&Row> = rows
                .iter()
                .filter(|r| r.joint == j && counted(r.step, steps))
                .collect();
            let pairs: Vec<(f64, f64)> = mine
                .iter()
                .filter_map(|r| Some((r.torque_estimate_nm?, r.modelled_nm?)))
                .collect();
            let by_slice: Vec<(usize, f64)> = mine
                .iter()
                .filter_map(|r| Some((usize::from(r.slice), r.torque_estimate_nm?)))
                .collect();
            let table = modelled.get(j).cloned().unwrap_or_default();
            Fit::of(name.clone(), &pairs, &by_slice, table)
        })
        .collect()
}

/// Vertical contact force on each foot against the plan's vertical GRF, per leg: `grf_z[slice][k]`
/// is leg `legs[k]`'s planned force (N, up), over the log's walking samples of whole steps after
/// the first.
pub fn grf_fits(log: &WalkLog, legs: &[Leg], grf_z: &[Vec<f64>], steps: u32) -> Vec<Fit> {
    let slices = grf_z.len();
    legs.iter()
        .enumerate()
        .map(|(k, &leg)| {
            let mut pairs = Vec::new();
            let mut by_slice = Vec::new();
            for s in &log.samples {
                let (Some((step, slice)), true) = (s.playback, s.walking) else {
                    continue;
                };
                let slice = usize::from(slice);
                if !counted(step, steps) || slice >= slices {
                    continue;
                }
                let Some((_, f)) = s.foot_forces.iter().find(|(l, _)| *l == leg) else {
                    continue;
                };
                pairs.push((f[2], grf_z[slice][k]));
                by_slice.push((slice, f[2]));
            }
            let modelled = grf_z.iter().map(|row| row[k]).collect();
            Fit::of(leg.name().to_owned(), &pairs, &by_slice, modelled)
        })
        .collect()
}

/// The per-phase CSV of `fits`: one row per item and slice.
pub fn phase_csv(fits: &[Fit], what: &str, unit: &str) -> String {
    let mut s = format!(
        "{what},slice,phase,modelled_{unit},measured_mean_{unit},measured_sd_{unit},samples\n"
    );
    for f in fits {
        for m in &f.measured {
            let slice = (m.phase * f.modelled.len() as f64).round() as usize;
            s.push_str(&format!(
                "{},{slice},{:.4},{:.4},{:.4},{:.4},{}\n",
                f.name,
                m.phase,
                f.modelled.get(slice).copied().unwrap_or(f64::NAN),
                m.mean_nm,
                m.sd_nm,
                m.n
            ));
        }
    }
    s
}

/// R^2 as printed: a number, or why there is none.
pub fn r2_text(r2: Option<f64>) -> String {
    r2.map_or_else(|| "n/a (no variation)".to_owned(), |r| format!("{r:.2}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_figures_are_the_prediction_r2_and_the_rms_difference() {
        // The mean (2) predicts with SS_res = SS_tot = 2: R^2 = 0, RMS sqrt(2/3).
        let (r2, rms) = fit_figures(&[(1.0, 2.0), (2.0, 2.0), (3.0, 2.0)]);
        assert!(r2.unwrap().abs() < 1e-12);
        assert!((rms - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(fit_figures(&[]), (None, 0.0));
    }

    #[test]
    fn per_slice_statistics_are_the_mean_and_population_sd() {
        let st = per_slice(&[(1, 2.0), (1, 4.0), (3, 5.0), (9, 1.0)], 4);
        assert_eq!(st.len(), 2);
        assert_eq!(
            (st[0].phase, st[0].mean_nm, st[0].sd_nm, st[0].n),
            (0.25, 3.0, 1.0, 2)
        );
        assert_eq!((st[1].phase, st[1].mean_nm, st[1].sd_nm), (0.75, 5.0, 0.0));
    }
}
