//! The refinement after Levenberg-Marquardt: each identified joint's block of [`MOTION`]
//! parameters (in the fit's scaled parameterisation, [`MotionFit::model_at`]) minimised by
//! **Nelder-Mead** (the `argmin` crate's) on that joint's own cost, the sum of its squared
//! position and velocity residuals over the recordings that move it, with a budget of replays.
//!
//! Why a derivative-free method: the replay is not smooth in the parameters (Coulomb friction,
//! deadband, backlash, the tick rounding), so Levenberg-Marquardt's forward-difference Jacobian
//! can stop predicting the cost's change and the trust region collapse in a curved valley short
//! of the optimum (docs/identification.md, "Why TrF1 and FTi miss"). Nelder-Mead compares costs
//! only. Why per joint: a suspended joint's parameters change only its own residuals (the fit's
//! block-diagonal Jacobian), so seven parameters at a time instead of seven per joint, and each
//! cost replays only the recordings that move the joint. The better of before and after is kept.

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use nalgebra_lm::DVector;

use super::fit::{self, MotionFit};
use super::params::MOTION;
use super::rollout;
use crate::error::Result;

/// Replays the refinement is given per identified joint when asked for (`dbot identify
/// --refine-replays`; each cost replays every recording that moves the joint once): what the
/// one-leg stand-in's run used (docs/identification.md).
pub const REPLAYS_PER_JOINT: usize = 300;

/// What the refinement did to one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointRefinement {
    pub joint: String,
    /// The joint's cost (squared residuals per tick and per velocity scale, summed) where
    /// Levenberg-Marquardt ended and where the refinement ended.
    pub cost_before: f64,
    pub cost_after: f64,
    /// Replays spent on the joint.
    pub replays: usize,
    /// Whether the refined block was kept (its cost lower).
    pub kept: bool,
}

/// One joint's cost as `argmin` sees it: the joint's block varied, the other joints held at
/// `x`. Counts replays and keeps the best point seen in `tally` (the budget ends the run by an
/// error, which loses the solver's state, not the tally).
struct JointCost<'a, 'b> {
    fit: &'a MotionFit<'b>,
    x: &'a DVector<f64>,
    slot: usize,
    budget: usize,
    tally: &'a Tally,
}

/// What a joint's run has spent and found.
#[derive(Default)]
struct Tally {
    replays: std::cell::Cell<usize>,
    best: std::cell::RefCell<Option<(f64, Vec<f64>)>>,
    error: std::cell::RefCell<Option<crate::LabError>>,
}

/// The error that ends a run when the budget is spent (not a failure).
const BUDGET_SPENT: &str = "replay budget spent";

impl JointCost<'_, '_> {
    /// The joint's cost with its block at `block` (scaled, clamped onto the bounds).
    fn at(&self, block: &[f64]) -> Result<f64> {
        let np = MOTION.len();
        let mut x = self.x.clone();
        for (i, f) in MOTION.iter().enumerate() {
            x[self.slot * np + i] = block[i].clamp(f.lo / f.scale, f.hi / f.scale);
        }
        let model = self.fit.model_at(&x);
        let joint = self.fit.joints[self.slot];
        let mut cost = 0.0;
        for rec in self.fit.recordings {
            let Some(t) = rec.joints.iter().position(|jt| jt.joint == joint) else {
                continue;
            };
            let n = &self.tally.replays;
            n.set(n.get() + 1);
            let out = rollout::replay(&model, rec)?;
            for (position, velocity) in fit::residuals(&out, t, &rec.joints[t]) {
                cost += position.powi(2) + velocity.powi(2);
            }
        }
        Ok(cost)
    }
}

impl CostFunction for JointCost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, block: &Vec<f64>) -> std::result::Result<f64, argmin::core::Error> {
        // A failed replay is kept for the caller and ends the search: every later point costs
        // infinity (an error here would panic in the solver's first simplex).
        if self.tally.error.borrow().is_some() {
            return Ok(f64::INFINITY);
        }
        if self.tally.replays.get() >= self.budget {
            return Err(argmin::core::Error::msg(BUDGET_SPENT));
        }
        // Outside the bounds: the clamped point's cost, raised by how far outside (so the
        // simplex comes back rather than wander on a plateau).
        let outside: f64 = MOTION
            .iter()
            .zip(block)
            .map(|(f, v)| (v - v.clamp(f.lo / f.scale, f.hi / f.scale)).powi(2))
            .sum();
        match self.at(block) {
            Ok(c) => {
                let c = c * (1.0 + outside);
                let mut best = self.tally.best.borrow_mut();
                if best.as_ref().is_none_or(|(b, _)| c < *b) {
                    *best = Some((c, block.clone()));
                }
                Ok(c)
            }
            Err(e) => {
                *self.tally.error.borrow_mut() = Some(e);
                Ok(f64::INFINITY)
            }
        }
    }
}

/// How far the starting simplex reaches from where Levenberg-Marquardt ended, a fraction of
/// each parameter's value: wide enough to span the valley it stops in (its estimates there
/// were 10 to 25 % off) and to step over the cost's unevenness at the scale of a tick (a
/// tenth stalled: see docs/identification.md).
const SIMPLEX: f64 = 0.4;

/// The starting simplex around `x0`: one vertex per parameter, moved by [`SIMPLEX`] of its value
/// (at least twice its differencing step, and towards the inside of its bounds).
fn simplex(x0: &[f64]) -> Vec<Vec<f64>> {
    let mut s = vec![x0.to_vec()];
    for (i, f) in MOTION.iter().enumerate() {
        let v = x0[i] * f.scale;
        let d = (SIMPLEX * v.abs()).max(2.0 * f.step);
        let moved = if v + d > f.hi { v - d } else { v + d };
        let mut p = x0.to_vec();
        p[i] = moved / f.scale;
        s.push(p);
    }
    s
}

/// Refines every identified joint of `fit` from `x` (scaled, as Levenberg-Marquardt ended),
/// each with at most `replays_per_joint` replays; returns the parameters (each joint's block
/// the better of before and after) and what it did per joint.
pub fn refine(
    fit: &MotionFit<'_>,
    x: &DVector<f64>,
    replays_per_joint: usize,
) -> Result<(DVector<f64>, Vec<JointRefinement>)> {
    let np = MOTION.len();
    let mut out = x.clone();
    let mut done = Vec::new();
    for (slot, &j) in fit.joints.iter().enumerate() {
        let tally = Tally::default();
        let problem = JointCost {
            fit,
            x,
            slot,
            budget: replays_per_joint,
            tally: &tally,
        };
        let x0: Vec<f64> = (0..np).map(|i| x[slot * np + i]).collect();
        let before = problem.at(&x0)?;
        let n = np as f64;
        // The adaptive parameters of Gao and Han (2012) for the expansion and the shrink, which
        // keep the simplex from collapsing early in more than a few dimensions (argmin allows a
        // contraction of at most 0.5: its default).
        let solver = NelderMead::new(simplex(&x0))
            .with_gamma(1.0 + 2.0 / n)
            .and_then(|s| s.with_sigma(1.0 - 1.0 / n))
            .expect("valid Nelder-Mead parameters");
        // The run ends on its tolerance, its iterations or the budget (an error the cost raises):
        // what it found is in the tally either way. Its first simplex must fit in the budget
        // (the solver cannot stop inside it): one cost per vertex, each as many replays as the
        // joint's start cost took.
        let per_cost = tally.replays.get().max(1);
        if replays_per_joint >= per_cost * (np + 2) {
            let _ = Executor::new(problem, solver)
                .configure(|s| s.max_iters(replays_per_joint as u64))
                .run();
        }
        if let Some(e) = tally.error.borrow_mut().take() {
            return Err(e);
        }
        let (after, block) = tally.best.borrow().clone().unwrap_or((before, x0.clone()));
        let kept = after < before;
        if kept {
            for (i, v) in block.iter().enumerate() {
                let f = &MOTION[i];
                out[slot * np + i] = v.clamp(f.lo / f.scale, f.hi / f.scale);
            }
        }
        done.push(JointRefinement {
            joint: fit.model.joints[j].name.clone(),
            cost_before: before,
            cost_after: after.min(before),
            replays: tally.replays.get(),
            kept,
        });
    }
    Ok((out, done))
}
