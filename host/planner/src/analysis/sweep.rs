//! Speed sweep: how the peak torque scales with the step period tells a quasi-static regime
//! (torque independent of period: gravity dominates) from an inertial one (torque ~ 1/T^2).

use crate::dynamics::{DynamicsError, DynamicsOptions, SliceInput, plan_inputs, solve_cycle};
use crate::gait::StepParams;
use crate::model::Model;
use crate::plan::{PlanError, plan};

/// Why a sweep point could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error("planning with swing {swing_s} s: {source}")]
    Plan {
        swing_s: f64,
        #[source]
        source: PlanError,
    },
    #[error("inverse dynamics with swing {swing_s} s: {source}")]
    Dynamics {
        swing_s: f64,
        #[source]
        source: DynamicsError,
    },
}

/// Plans `params` on `model`, solves its inverse dynamics with and without gravity (the latter is
/// the inertial part of the torques) and returns the peaks.
pub fn sweep_point(model: &Model, params: &StepParams) -> Result<SweepPoint, SweepError> {
    let swing_s = params.swing_s;
    let plan = plan(model, params).map_err(|source| SweepError::Plan { swing_s, source })?;
    let peak_of = |inputs: &[SliceInput]| -> Result<f64, SweepError> {
        let c = solve_cycle(&plan.model, inputs, &DynamicsOptions::default())
            .map_err(|source| SweepError::Dynamics { swing_s, source })?;
        Ok(c.slices
            .iter()
            .flat_map(|s| s.torque.iter())
            .fold(0.0f64, |m, t| m.max(t.abs())))
    };
    let mut inputs = plan_inputs(&plan);
    let peak_torque = peak_of(&inputs)?;
    // The same motion without gravity (and without springs' static share): inertia only.
    for i in &mut inputs {
        i.gravity = nalgebra::Vector3::zeros();
    }
    Ok(SweepPoint {
        period: plan.period_s,
        peak_torque,
        peak_inertial_torque: peak_of(&inputs)?,
    })
}

/// Peak actuated torque of one plan of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepPoint {
    /// Step period, s.
    pub period: f64,
    /// Largest |torque| over joints and slices, N m.
    pub peak_torque: f64,
    /// Largest |torque| of the same plan with gravity removed (inertial part only), N m.
    pub peak_inertial_torque: f64,
}

/// Verdict of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRegime {
    /// Log-log slope of the inertial peak against the period (-2 for pure inertia).
    pub inertial_exponent: f64,
    /// Inertial share of the peak torque at each period: below ~0.1 the step is quasi-static.
    pub inertial_share: Vec<f64>,
}

/// Fit the log-log slope of the inertial torque against the period and each point's inertial share.
/// `None` with fewer than two points or non-positive values.
pub fn classify_sweep(points: &[SweepPoint]) -> Option<SweepRegime> {
    if points.len() < 2
        || points
            .iter()
            .any(|p| p.period <= 0.0 || p.peak_inertial_torque <= 0.0)
    {
        return None;
    }
    let xs: Vec<f64> = points.iter().map(|p| p.period.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.peak_inertial_torque.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx == 0.0 {
        return None;
    }
    let inertial_share = points
        .iter()
        .map(|p| {
            if p.peak_torque > 0.0 {
                p.peak_inertial_torque / p.peak_torque
            } else {
                0.0
            }
        })
        .collect();
    Some(SweepRegime {
        inertial_exponent: sxy / sxx,
        inertial_share,
    })
}
