//! The motion fit: Levenberg-Marquardt (the `levenberg-marquardt` crate, MINPACK's trust-region
//! algorithm) over every identified joint's [`MOTION`] parameters at once, the residuals each
//! recorded joint's present position (per tick) and velocity (per [`VELOCITY_SCALE`]) against
//! the replay.
//!
//! The Jacobian is by forward differences with one replay per parameter, not per joint and
//! parameter: every joint's copy of parameter `p` is stepped together, and each joint's readings
//! are credited to its own copy. That holds while the joints move independently of each other's
//! servo parameters (a suspended robot: each joint's servo drives its own segment, the body
//! fixed); it makes the Jacobian block diagonal, one block per joint. Bounds: a step outside
//! them is clamped onto them; a parameter at its upper bound is differenced downward.

use nalgebra_lm::{DMatrix, DVector, Dyn, Owned};
use planner::model::{Model, ServoParamsEntry};

use super::params::MOTION;
use super::recording::{JointTrace, Recording};
use super::rollout::{self, Replayed};
use crate::error::Result;

/// Residual scale of a position, rad: one servo tick.
pub const POSITION_SCALE: f64 = std::f64::consts::TAU / 4096.0;
/// Residual scale of a velocity, rad/s: four of the register's 0.229 rev/min units.
pub const VELOCITY_SCALE: f64 = 4.0 * 0.229 * std::f64::consts::TAU / 60.0;

/// The fit's residuals of traced joint `t` of a recording, cycle by cycle: its replayed against
/// its recorded (`jt`) present position, per tick, and velocity, per [`VELOCITY_SCALE`]. The one
/// definition Levenberg-Marquardt, the refinement's per-joint cost and the examples use.
pub fn residuals<'a>(
    out: &'a Replayed,
    t: usize,
    jt: &'a JointTrace,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    (0..jt.q.len()).map(move |c| {
        (
            (out.q[t][c] - jt.q[c]) / POSITION_SCALE,
            (out.qd[t][c] - jt.qd[c]) / VELOCITY_SCALE,
        )
    })
}

/// Each residual's identified-joint slot and row.
type Owners = Vec<(usize, usize)>;

/// The fit's problem: the model, the recordings, the identified joints (model indices) and the
/// parameters now (scaled, joint-major).
pub struct MotionFit<'a> {
    pub model: &'a Model,
    pub recordings: &'a [Recording],
    pub joints: Vec<usize>,
    x: DVector<f64>,
    residuals: Option<DVector<f64>>,
    /// Each residual's joint slot and row (with `residuals`).
    owner: Owners,
    /// Replays run so far, and the budget after which the fit stops.
    pub replays: std::cell::Cell<usize>,
    pub budget: usize,
    /// Each identified joint's torque-speed slope at the start, N m s/rad (kept: see
    /// [`Self::model_at`]).
    kv: Vec<f64>,
    /// Each identified joint's stall torque at the start, N m (see [`Self::model_at`]).
    stall0: Vec<f64>,
    /// The lowest cost seen and its parameters.
    pub best: Option<(f64, DVector<f64>)>,
    pub error: std::cell::RefCell<Option<crate::LabError>>,
}

impl std::fmt::Debug for MotionFit<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MotionFit")
            .field("joints", &self.joints)
            .field("replays", &self.replays.get())
            .finish_non_exhaustive()
    }
}

impl<'a> MotionFit<'a> {
    /// The fit of `joints` from `model`'s present values.
    pub fn new(
        model: &'a Model,
        recordings: &'a [Recording],
        joints: Vec<usize>,
        budget: usize,
    ) -> Self {
        let mut x = DVector::zeros(joints.len() * MOTION.len());
        for (k, &j) in joints.iter().enumerate() {
            let p = model
                .servo_params(j)
                .expect("identified joints have servos");
            for (i, f) in MOTION.iter().enumerate() {
                x[k * MOTION.len() + i] = (f.get)(&p) / f.scale;
            }
        }
        let kv = joints
            .iter()
            .map(|&j| {
                model
                    .servo_params(j)
                    .expect("a servo joint")
                    .back_emf_nm_s_per_rad()
            })
            .collect();
        let stall0 = joints
            .iter()
            .map(|&j| {
                model
                    .servo_params(j)
                    .expect("a servo joint")
                    .stall_torque_nm
            })
            .collect();
        let mut fit = Self {
            kv,
            stall0,
            model,
            recordings,
            joints,
            x: x.clone(),
            residuals: None,
            owner: Vec::new(),
            replays: std::cell::Cell::new(0),
            budget,
            best: None,
            error: std::cell::RefCell::new(None),
        };
        levenberg_marquardt::LeastSquaresProblem::set_params(&mut fit, &x);
        fit
    }

    /// `model` with the parameters `x` (scaled) as each identified joint's overrides, clamped
    /// to the bounds. The torque-speed line keeps its start slope: the no-load speed follows
    /// the stall torque (the slope and the gear damping are one to the motion below saturation,
    /// `params::NOT_FROM_MOTION`). The optimiser's divisor is the one at the start stall torque,
    /// so that it alone sets the stiffness (Kp is the stall torque over the divisor, times the
    /// register) and the stall torque alone the I and D gains' scale and the saturation: the
    /// file's divisor is that one times the fitted stall over the start's.
    pub fn model_at(&self, x: &DVector<f64>) -> Model {
        let mut m = self.model.clone();
        for (k, &j) in self.joints.iter().enumerate() {
            let name = &m.joints[j].name;
            let mut e = m.servo_dynamics.of_joint(name).copied().unwrap_or_default();
            for (i, f) in MOTION.iter().enumerate() {
                (f.set)(
                    &mut e,
                    (x[k * MOTION.len() + i] * f.scale).clamp(f.lo, f.hi),
                );
            }
            if let Some(stall) = e.stall_torque_nm {
                e.no_load_speed_rad_s = Some(stall / self.kv[k]);
                if let Some(d) = e.p_gain_divisor {
                    e.p_gain_divisor = Some(d * stall / self.stall0[k]);
                }
            }
            let name = name.clone();
            m.servo_dynamics.set_joint(&name, e);
        }
        m
    }

    /// The residuals of every recording replayed on `model`, one position and one velocity per
    /// identified joint and cycle, and where each joint's rows are: `(joint slot, row)`.
    fn residuals_of(&self, model: &Model) -> Result<(DVector<f64>, Owners)> {
        let mut r = Vec::new();
        let mut owner = Vec::new();
        for rec in self.recordings {
            self.replays.set(self.replays.get() + 1);
            let out: Replayed = rollout::replay(model, rec)?;
            for (t, jt) in rec.joints.iter().enumerate() {
                let Some(k) = self.joints.iter().position(|&j| j == jt.joint) else {
                    continue;
                };
                for (position, velocity) in residuals(&out, t, jt) {
                    owner.push((k, r.len()));
                    r.push(position);
                    owner.push((k, r.len()));
                    r.push(velocity);
                }
            }
        }
        Ok((DVector::from_vec(r), owner))
    }

    /// The block-diagonal Jacobian at the present parameters (see the module's header), with
    /// the residuals it was taken from.
    pub fn jacobian_now(&self) -> Result<DMatrix<f64>> {
        let (r0, owner) = match &self.residuals {
            Some(r) => (r.clone(), self.owner.clone()),
            None => self.residuals_of(&self.model_at(&self.x))?,
        };
        let n = self.x.len();
        let mut jac = DMatrix::zeros(r0.len(), n);
        for (i, f) in MOTION.iter().enumerate() {
            let mut x = self.x.clone();
            let mut steps = vec![0.0; self.joints.len()];
            for (k, s) in steps.iter_mut().enumerate() {
                let v = x[k * MOTION.len() + i] * f.scale;
                let h = if v + f.step > f.hi { -f.step } else { f.step };
                x[k * MOTION.len() + i] = (v + h) / f.scale;
                *s = h / f.scale;
            }
            let (r1, _) = self.residuals_of(&self.model_at(&x))?;
            for &(k, row) in &owner {
                jac[(row, k * MOTION.len() + i)] = (r1[row] - r0[row]) / steps[k];
            }
        }
        Ok(jac)
    }

    /// The parameters now (scaled).
    pub fn x(&self) -> &DVector<f64> {
        &self.x
    }
}

impl levenberg_marquardt::LeastSquaresProblem<f64, Dyn, Dyn> for MotionFit<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        // Onto the bounds: the optimiser then sees the clamped point.
        let mut x = x.clone();
        for k in 0..self.joints.len() {
            for (i, f) in MOTION.iter().enumerate() {
                let v = &mut x[k * MOTION.len() + i];
                *v = v.clamp(f.lo / f.scale, f.hi / f.scale);
            }
        }
        self.x = x;
        self.residuals = None;
        if self.replays.get() >= self.budget || self.error.borrow().is_some() {
            return;
        }
        match self.residuals_of(&self.model_at(&self.x)) {
            Ok((r, owner)) => {
                self.owner = owner;
                let cost = r.norm_squared();
                if self.best.as_ref().is_none_or(|(c, _)| cost < *c) {
                    self.best = Some((cost, self.x.clone()));
                }
                self.residuals = Some(r);
            }
            Err(e) => *self.error.borrow_mut() = Some(e),
        }
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.residuals.clone()
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        if self.replays.get() >= self.budget {
            return None;
        }
        match self.jacobian_now() {
            Ok(j) => Some(j),
            Err(e) => {
                *self.error.borrow_mut() = Some(e);
                None
            }
        }
    }
}

/// The entry `model` gives joint `j` (its override, else empty).
pub fn entry_of(model: &Model, j: usize) -> ServoParamsEntry {
    model
        .servo_dynamics
        .of_joint(&model.joints[j].name)
        .copied()
        .unwrap_or_default()
}
