//! Walking: the physics robot's simulated gauges against the plan's predicted strain, per gauge
//! over the step phase (issue 26 item 3, walking; the standing comparison is
//! [`crate::validation::strain`]).
//!
//! Alignment is by the firmware, not the clock: the physics robot logs each gauge sample with the
//! step and slice the firmware played in the bus cycle it was taken at ([`physics::WalkSample`]'s
//! `strain`), and that sample is paired with the prediction at that slice
//! (`planner::strain::predict_plan`, from the same inverse dynamics the step table's torques come
//! from). Samples of the whole steps after the first count ([`crate::walk_fits`]'s rule: the first
//! starts from the ramp). Per gauge: the R^2 of the prediction (`prediction_r2`, 1 - SS_res /
//! SS_tot: scale and offset count, both readings are microstrain) and the RMS difference.
//!
//! Why they differ, while standing they agree to a few per cent: the plan's joints move exactly
//! on their trajectories with the QP's foot forces, the body's servos lag them (the tracking
//! error the demo prints), a swing foot's touch-down is an impact the plan does not have (the
//! planner switches the load to a foot at one slice, the body loads it over a few cycles, after
//! an impact), and the load of a stance tripod shares out by where the feet really stand. The
//! gauges carrying the stance load see the same shape; those that read little (the swing leg's,
//! the 45 deg gauges' torsion) are dominated by these differences.

use std::path::Path;

use board::files::write_atomically;
use board::link::Board;
use physics::{PhysicsRobot, PhysicsTransport, WalkLog};
use planner::dynamics::CycleSolution;
use planner::plan::Plan;

use crate::error::{Context, Result};
use crate::physics_walk::walk_forward;
use crate::walk_fits::{Fit, counted, phase_csv};

/// Per slice, every gauge's predicted reading in microstrain (`[slice][gauge]`, the model's gauge
/// order), from the plan and its solved cycle; empty without gauges.
pub fn predicted(plan: &Plan, cycle: &CycleSolution) -> Result<Vec<Vec<f64>>> {
    if plan.model.gauges.is_empty() {
        return Ok(Vec::new());
    }
    let p = planner::strain::predict_plan(plan, cycle).context("the plan's predicted strain")?;
    Ok(p.readings
        .iter()
        .map(|s| s.iter().map(|r| r.microstrain).collect())
        .collect())
}

/// Per gauge (`names`, the model's order), the simulated readings of `log` against
/// `predicted[slice][gauge]` over the walking samples of the whole steps after the first (of
/// `steps` played); empty when the log holds no gauge samples.
pub fn strain_fits(
    log: &WalkLog,
    names: &[String],
    predicted: &[Vec<f64>],
    steps: u32,
) -> Vec<Fit> {
    names
        .iter()
        .enumerate()
        .map(|(g, name)| {
            let mut pairs = Vec::new();
            let mut by_slice = Vec::new();
            for s in &log.samples {
                let (Some((step, slice)), true, Some(strain)) =
                    (s.playback, s.walking, s.strain.as_ref())
                else {
                    continue;
                };
                let slice = usize::from(slice);
                let (Some(&sim), Some(&pred)) = (
                    strain.get(g),
                    predicted.get(slice).and_then(|row| row.get(g)),
                ) else {
                    continue;
                };
                if !counted(step, steps) {
                    continue;
                }
                pairs.push((sim, pred));
                by_slice.push((slice, sim));
            }
            let modelled = predicted.iter().map(|row| row[g]).collect();
            Fit::of(name.clone(), &pairs, &by_slice, modelled)
        })
        .collect()
}

/// The largest predicted |reading| of a gauge's fit, microstrain.
pub fn peak(fit: &Fit) -> f64 {
    fit.modelled.iter().map(|m| m.abs()).fold(0.0, f64::max)
}

/// The gauges that carry the stance load: a predicted peak of at least this share of the largest
/// gauge's (the others read little, and their R^2 measures the differences, not the load).
pub const LOAD_BEARING_SHARE: f64 = 0.25;

/// Whether `fit` is one of the load-bearing gauges among `fits` ([`LOAD_BEARING_SHARE`]).
pub fn load_bearing(fit: &Fit, fits: &[Fit]) -> bool {
    let top = fits.iter().map(peak).fold(0.0, f64::max);
    top > 0.0 && peak(fit) >= LOAD_BEARING_SHARE * top
}

/// Writes `strain_vs_plan.csv` (per gauge and slice: predicted, simulated mean and SD) and
/// `strain_vs_plan.png` (one panel per leg, predicted solid and simulated dashed over the phase)
/// into `dir`; returns the file names.
pub fn write_strain_files(dir: &Path, plan: &Plan, fits: &[Fit]) -> Result<[&'static str; 2]> {
    let csv = phase_csv(fits, "gauge", "microstrain");
    write_atomically(&dir.join(STRAIN_CSV), |p| Ok(std::fs::write(p, &csv)?))?;
    let simulated: Vec<Vec<Option<f64>>> = fits
        .iter()
        .map(|f| {
            let mut v = vec![None; f.modelled.len()];
            for m in &f.measured {
                let s = (m.phase * f.modelled.len() as f64).round() as usize;
                if let Some(x) = v.get_mut(s) {
                    *x = Some(m.mean_nm);
                }
            }
            v
        })
        .collect();
    let predicted: Vec<Vec<f64>> = fits.iter().map(|f| f.modelled.clone()).collect();
    write_atomically(&dir.join(STRAIN_PNG), |p| {
        Ok(
            report::strain::plot_strain_walk(plan, &predicted, &simulated, p)
                .map_err(|e| format!("plotting strain: {e}"))?,
        )
    })?;
    Ok([STRAIN_CSV, STRAIN_PNG])
}

/// The per-phase strain of a walk, beside its recording.
pub const STRAIN_CSV: &str = "strain_vs_plan.csv";
/// Its plot.
pub const STRAIN_PNG: &str = "strain_vs_plan.png";

/// A walk's gauges against the plan.
#[derive(Debug, Clone)]
pub struct StrainWalk {
    pub bias_on: bool,
    pub steps: u32,
    /// Per gauge, the model's order.
    pub fits: Vec<Fit>,
}

impl StrainWalk {
    /// The median R^2 of the load-bearing gauges (None: none has an R^2).
    pub fn load_bearing_median_r2(&self) -> Option<f64> {
        load_bearing_median_r2(&self.fits)
    }
}

/// The median R^2 of the load-bearing gauges among `fits` (None: none has an R^2).
pub fn load_bearing_median_r2(fits: &[Fit]) -> Option<f64> {
    let mut r: Vec<f64> = fits
        .iter()
        .filter(|f| load_bearing(f, fits))
        .filter_map(|f| f.r2)
        .collect();
    r.sort_by(f64::total_cmp);
    (!r.is_empty()).then(|| r[r.len() / 2])
}

/// One line about a walk's gauges: the load-bearing ones' count, median and lowest R^2.
pub fn summary_line(label: &str, fits: &[Fit]) -> String {
    let bearing: Vec<&Fit> = fits.iter().filter(|f| load_bearing(f, fits)).collect();
    let lowest = bearing
        .iter()
        .filter_map(|f| Some((f.r2?, f.name.as_str())))
        .fold(None, |a: Option<(f64, &str)>, b| match a {
            Some(a) if a.0 <= b.0 => Some(a),
            _ => Some(b),
        });
    let samples = fits.first().map_or(0, |f| f.samples);
    match (load_bearing_median_r2(fits), lowest) {
        (Some(m), Some((lo, at))) => format!(
            "{label}: {} load-bearing gauges (predicted peak at least {:.0} % of the largest), median R^2 {m:.2}, lowest {lo:.2} ({at}); {samples} samples per gauge",
            bearing.len(),
            LOAD_BEARING_SHARE * 100.0
        ),
        _ => format!(
            "{label}: no R^2 ({samples} samples per gauge; the first step is left out, walk 2 or more)"
        ),
    }
}

/// Walks `plan` (solved as `cycle`, the step table's torques from it) forward for `steps` steps
/// (at least 2: the first is left out) on a fresh physics robot on flat ground, the torque bias on
/// or off, and compares its gauges with the prediction.
pub fn walk_strain(
    plan: &Plan,
    cycle: &CycleSolution,
    steps: u32,
    bias_on: bool,
) -> Result<StrainWalk> {
    if steps < 2 {
        crate::bail!("steps {steps}: the first step is left out, give 2 or more");
    }
    let torques = planner::dynamics::output::torque_rows(cycle);
    let table = board::rules::build::plan_table(plan, Some(&torques), "strain", Default::default())
        .context("the step table `strain`")?
        .into_bytes();
    let predicted = predicted(plan, cycle)?;
    let mut robot = PhysicsRobot::new(&plan.model, &planner::terrain::Ground::Flat)?;
    let names = robot.gauge_names();
    robot.start_log(usize::MAX);
    let joints = protocol::GaitTable::parse(&table)?.joint_count();
    let no_bias = |b: &mut Board<PhysicsTransport>| -> Result<()> {
        if !bias_on {
            // Stiffness 0 is the firmware's setting for "no bias" (firmware/src/bias.rs).
            for j in 0..joints {
                b.set_stiffness(j as u8, board::rules::stiffness::Stiffness::OFF)?;
            }
        }
        Ok(())
    };
    let log = walk_forward(robot, &table, steps, "the strain walk", no_bias, |_| {})?.log;
    Ok(StrainWalk {
        bias_on,
        steps,
        fits: strain_fits(&log, &names, &predicted, steps),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use physics::WalkSample;

    fn sample(step: u32, slice: u16, walking: bool, strain: Option<Vec<f64>>) -> WalkSample {
        WalkSample {
            time_s: 0.0,
            playback: Some((step, slice)),
            walking,
            thorax: ([0.0; 3], [1.0, 0.0, 0.0, 0.0]),
            foot_forces: vec![],
            foot_spheres: vec![],
            pose: None,
            strain,
        }
    }

    #[test]
    fn samples_pair_with_the_slice_the_firmware_played_in_whole_steps_after_the_first() {
        // Two gauges, three slices: predicted 10, 20, 30 and -1, -2, -3.
        let predicted = vec![vec![10.0, -1.0], vec![20.0, -2.0], vec![30.0, -3.0]];
        let log = WalkLog {
            pose_every: 1,
            samples: vec![
                // Step 0 (the ramp's step) and a cycle without a gauge sample: left out.
                sample(0, 1, true, Some(vec![99.0, 99.0])),
                sample(1, 0, true, None),
                // Counted: step 1 slice 1 twice, step 2 slice 2.
                sample(1, 1, true, Some(vec![21.0, -2.0])),
                sample(1, 1, true, Some(vec![19.0, -2.0])),
                sample(2, 2, true, Some(vec![30.0, -3.0])),
                // Not walking, and the last step (of 3 played): left out.
                sample(2, 0, false, Some(vec![99.0, 99.0])),
                sample(3, 0, true, Some(vec![99.0, 99.0])),
            ],
        };
        let names = vec!["a".to_string(), "b".to_string()];
        let fits = strain_fits(&log, &names, &predicted, 3);
        assert_eq!(fits[0].samples, 3);
        // Residuals 1, -1, 0: RMS sqrt(2/3). Measured 21, 19, 30: mean 70/3, SS_tot = (7/3)^2 +
        // (13/3)^2 + (20/3)^2 = 618/9 = 206/3, SS_res = 2, R^2 = 1 - 6/206.
        assert!((fits[0].rms - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert!((fits[0].r2.unwrap() - (1.0 - 6.0 / 206.0)).abs() < 1e-12);
        // Slice 1's mean 20, SD 1; slice 2's 30.
        assert_eq!(fits[0].measured.len(), 2);
        assert_eq!(
            (fits[0].measured[0].mean_nm, fits[0].measured[0].sd_nm),
            (20.0, 1.0)
        );
        assert_eq!(fits[0].modelled, vec![10.0, 20.0, 30.0]);
        // Gauge b matches exactly.
        assert_eq!(fits[1].rms, 0.0);
        assert_eq!(fits[1].r2, Some(1.0));
        // Gauge a peaks at 30, b at 3 (a tenth): only a bears the load.
        assert!(load_bearing(&fits[0], &fits) && !load_bearing(&fits[1], &fits));
    }
}
