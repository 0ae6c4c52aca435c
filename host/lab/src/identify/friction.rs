//! The ground's sliding friction from walking trials: the feet's friction coefficient
//! (`planner::model::Model::foot_friction`) fitted to the recorded present position and velocity
//! of every joint of the trials the robot walked (not suspended), the servo dynamics held as the
//! model gives them (fitted first from the suspended trials).
//!
//! Friction acts on the joints only where a foot slides: while every foot sticks, any larger
//! coefficient replays the same walk. The misfit is therefore flat above the coefficient at which
//! the feet stop slipping and steep below it (measured on the stand-in, docs/identification.md),
//! which a gradient method started from the default (1.5, far up the flat part) cannot leave.
//! So the fit scans [`GRID`] first, then refines around the best point with Levenberg-Marquardt
//! (the `levenberg-marquardt` crate, one parameter, forward differences, clamped to the
//! neighbouring grid points). The estimate's standard deviation is `sqrt(sigma^2 / J^T J)` at the
//! optimum (optimistic: the residuals of a standing replay are not white).
//!
//! It is identified only if the feet slip in the fitted replay enough to show: the replayed
//! joint angles at the estimate and at the grid's top ([`GRID`]'s last, where no walk slips)
//! must differ by at least [`MIN_EFFECT_RAD`] RMS. Less is within what a standing replay's start
//! alone leaves, and the trials then say only that the friction is above about the estimate.

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra_lm::{DMatrix, DVector, Dyn, Owned};
use planner::model::{FOOT_FRICTION, Model};

use super::fit::{POSITION_SCALE, VELOCITY_SCALE};
use super::recording::Recording;
use super::rollout::{self, Replayed};
use crate::error::Result;

/// The coefficients scanned before the refinement: from a wet floor's to above any dry
/// elastomer's (the model file's range is [`FOOT_FRICTION`]).
pub const GRID: [f64; 10] = [0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.85, 1.1, 2.0];
/// The smallest RMS change of the replayed joint angles between the estimate and the grid's top
/// for which friction counts as identified, rad: two servo ticks. A standing replay's start is
/// not the recorded robot's state: started in the recorded posture the stand-in's walk replays
/// 2.8 mrad off on its own model, and the physics robot's own recorded step 14.4 mrad (its
/// start ramp not replayed); a friction whose whole effect is below two ticks cannot be told from
/// that on a real robot (the stand-in's replays from its goals, 0.44 mrad off, are its best
/// case: docs/identification.md).
pub const MIN_EFFECT_RAD: f64 = 2.0 * POSITION_SCALE;
/// Forward-difference step of the refinement's Jacobian.
const STEP: f64 = 0.005;

/// What the friction fit found.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionFit {
    /// The model's coefficient the fit started from.
    pub start: f64,
    /// The coefficient of least misfit.
    pub value: f64,
    /// Its standard deviation (`None` when not identified).
    pub sd: Option<f64>,
    /// RMS of the replayed joint angles' change from the estimate to the grid's top, rad.
    pub effect_rad: f64,
    /// Position RMS of the replay at the estimate against the recording, rad, and at the start.
    pub misfit_rad: f64,
    pub misfit_start_rad: f64,
    /// Why it is not identified (`None`: identified).
    pub why: Option<String>,
    /// Replays run.
    pub replays: usize,
}

/// The refinement's problem: one parameter, the coefficient.
struct Problem<'a> {
    model: &'a Model,
    walks: &'a [Recording],
    mu: f64,
    bounds: (f64, f64),
    residuals: Option<DVector<f64>>,
    replays: std::cell::Cell<usize>,
    error: std::cell::RefCell<Option<crate::LabError>>,
}

impl Problem<'_> {
    fn replays_at(&self, mu: f64) -> Result<Vec<Replayed>> {
        let mut m = self.model.clone();
        m.foot_friction = Some(mu);
        self.walks
            .iter()
            .map(|r| {
                self.replays.set(self.replays.get() + 1);
                rollout::replay(&m, r)
            })
            .collect()
    }

    fn residuals_at(&self, mu: f64) -> Result<DVector<f64>> {
        Ok(residuals(self.walks, &self.replays_at(mu)?))
    }
}

/// Every walking joint's position (per tick) and velocity (per [`VELOCITY_SCALE`]) residual.
fn residuals(walks: &[Recording], out: &[Replayed]) -> DVector<f64> {
    let mut r = Vec::new();
    for (rec, o) in walks.iter().zip(out) {
        for (t, jt) in rec.joints.iter().enumerate() {
            for c in 0..rec.len() {
                r.push((o.q[t][c] - jt.q[c]) / POSITION_SCALE);
                r.push((o.qd[t][c] - jt.qd[c]) / VELOCITY_SCALE);
            }
        }
    }
    DVector::from_vec(r)
}

/// RMS difference of the joint angles of two replays of the same recordings, rad.
fn angle_rms(a: &[Replayed], b: &[Replayed]) -> f64 {
    let (mut sq, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(b) {
        for (qx, qy) in x.q.iter().zip(&y.q) {
            for (p, q) in qx.iter().zip(qy) {
                sq += (p - q).powi(2);
                n += 1;
            }
        }
    }
    (sq / n.max(1) as f64).sqrt()
}

/// Position RMS of replays against their recordings, rad.
fn misfit(walks: &[Recording], out: &[Replayed]) -> f64 {
    let (mut sq, mut n) = (0.0, 0usize);
    for (rec, o) in walks.iter().zip(out) {
        for (t, jt) in rec.joints.iter().enumerate() {
            for (p, q) in o.q[t].iter().zip(&jt.q) {
                sq += (p - q).powi(2);
                n += 1;
            }
        }
    }
    (sq / n.max(1) as f64).sqrt()
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.mu = x[0].clamp(self.bounds.0, self.bounds.1);
        self.residuals = match self.residuals_at(self.mu) {
            Ok(r) => Some(r),
            Err(e) => {
                self.error.borrow_mut().get_or_insert(e);
                None
            }
        };
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_element(1, self.mu)
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.residuals.clone()
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let r0 = self.residuals.as_ref()?;
        let h = if self.mu + STEP > self.bounds.1 {
            -STEP
        } else {
            STEP
        };
        match self.residuals_at(self.mu + h) {
            Ok(r1) => Some(DMatrix::from_column_slice(
                r0.len(),
                1,
                ((r1 - r0) / h).as_slice(),
            )),
            Err(e) => {
                self.error.borrow_mut().get_or_insert(e);
                None
            }
        }
    }
}

/// Fits `model`'s foot friction to the walking recordings `walks` (see the module's header).
pub fn fit(model: &Model, walks: &[Recording]) -> Result<FrictionFit> {
    let start = model.foot_friction();
    let scan = Problem {
        model,
        walks,
        mu: start,
        bounds: FOOT_FRICTION,
        residuals: None,
        replays: std::cell::Cell::new(0),
        error: std::cell::RefCell::new(None),
    };
    let at_start = scan.replays_at(start)?;
    let misfit_start_rad = misfit(walks, &at_start);
    let mut costs = Vec::with_capacity(GRID.len());
    let mut top = None;
    for (i, &mu) in GRID.iter().enumerate() {
        let out = scan.replays_at(mu)?;
        costs.push(residuals(walks, &out).norm_squared());
        if i + 1 == GRID.len() {
            top = Some(out);
        }
    }
    let top = top.expect("the grid is not empty");
    let k = (0..GRID.len())
        .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
        .expect("the grid is not empty");
    let bounds = (GRID[k.saturating_sub(1)], GRID[(k + 1).min(GRID.len() - 1)]);
    let mut problem = Problem {
        bounds,
        mu: GRID[k],
        replays: std::cell::Cell::new(scan.replays.get()),
        ..scan
    };
    problem.set_params(&DVector::from_element(1, GRID[k]));
    let (problem, _report) = LevenbergMarquardt::new()
        .with_patience(20)
        .with_xtol(1e-3)
        .with_ftol(1e-4)
        .minimize(problem);
    if let Some(e) = problem.error.borrow_mut().take() {
        return Err(e);
    }
    // The refinement's end, unless a grid point fits better.
    let refined = problem.residuals.as_ref().map(|r| r.norm_squared());
    let value = match refined {
        Some(c) if c <= costs[k] => problem.mu,
        _ => GRID[k],
    };
    let at = problem.replays_at(value)?;
    let r0 = residuals(walks, &at);
    let h = if value + STEP > FOOT_FRICTION.1 {
        -STEP
    } else {
        STEP
    };
    let r1 = problem.residuals_at(value + h)?;
    let jtj = ((r1 - &r0) / h).norm_squared();
    let sigma2 = r0.norm_squared() / (r0.len().max(2) - 1) as f64;
    let effect_rad = angle_rms(&at, &top);
    let why = (effect_rad < MIN_EFFECT_RAD).then(|| {
        format!(
            "the feet hardly slip in these walks: from {value:.2} to {:.1} the replayed joint angles \
             change by {:.2} mrad RMS, under the {:.2} mrad a standing replay's start alone can \
             leave; the trials say only that the friction is above about {value:.2} (walk on a \
             slipperier ground, or faster, to identify it)",
            GRID[GRID.len() - 1],
            effect_rad * 1e3,
            MIN_EFFECT_RAD * 1e3
        )
    });
    let sd = (why.is_none() && jtj > 0.0).then(|| (sigma2 / jtj).sqrt());
    Ok(FrictionFit {
        start,
        value,
        sd,
        effect_rad,
        misfit_rad: misfit(walks, &at),
        misfit_start_rad,
        why,
        replays: problem.replays.get(),
    })
}
