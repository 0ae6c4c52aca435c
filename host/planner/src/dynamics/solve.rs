//! Solving slices and whole cycles, and assembling the outputs of each slice.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::problem::{SliceProblem, build, joint_stiffness, spring_torques};
use super::report::{ConstraintReport, check_slice};
use super::wrench::backward_pass;
use super::{DynamicsError, DynamicsOptions, SliceInput};
use crate::model::Model;
use crate::qp::{self, Backend, QpError, QpSolution};

/// Everything the inverse dynamics says about one slice. Vectors in the thorax frame.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceSolution {
    /// Per joint, N m: the actuator's torque about the axis for actuated joints (total axis
    /// moment minus the parallel spring's torque), the axis moment for fixed joints.
    pub torque: Vec<f64>,
    /// Per joint, N m: the total moment about the axis (actuator + spring).
    pub axis_moment: Vec<f64>,
    /// Per joint, N m: the parallel spring's torque -k_s (q - q_eq).
    pub spring_torque: Vec<f64>,
    /// Per joint: force the parent exerts on the child, N.
    pub joint_force: Vec<Vector3<f64>>,
    /// Per joint: moment the parent exerts on the child about the joint origin, N m.
    pub joint_moment: Vec<Vector3<f64>>,
    /// Per foot: ground reaction force, N (exactly zero in swing).
    pub grf: Vec<Vector3<f64>>,
    /// Per foot: contact point, m.
    pub foot_position: Vec<Vector3<f64>>,
    /// Force and moment (about the thorax origin) a fixed base's stand carries; ~0 when floating.
    pub base_force: Vector3<f64>,
    pub base_moment: Vector3<f64>,
    /// Complementary energy V* = 1/2 sum T_act^2 / k over actuated joints, J.
    pub v_star: f64,
    /// Interior-point iterations (0 when solved directly).
    pub iterations: u32,
}

/// The solution of every slice of a cycle, and which slices slip or saturate.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleSolution {
    pub slices: Vec<SliceSolution>,
    /// Joint stiffness k = actuator + parallel spring (N m/rad) per joint, used in V*; `None`
    /// for fixed joints.
    pub stiffness: Vec<Option<f64>>,
    pub report: ConstraintReport,
}

/// Solve one slice. `slice` is only used to name the slice in errors.
pub fn solve_slice(
    model: &Model,
    input: &SliceInput,
    options: &DynamicsOptions,
    slice: usize,
) -> Result<SliceSolution, DynamicsError> {
    validate_model(model)?;
    let stiffness = joint_stiffness(model)?;
    let limits = options.torque_limits.resolve(model);
    solve_prepared(model, input, options, &stiffness, &limits, slice)
}

/// Solve every slice (in parallel when `options.parallel`), stopping at the first error.
pub fn solve_cycle(
    model: &Model,
    inputs: &[SliceInput],
    options: &DynamicsOptions,
) -> Result<CycleSolution, DynamicsError> {
    validate_model(model)?;
    let stiffness = joint_stiffness(model)?;
    let limits = options.torque_limits.resolve(model);
    let one = |(i, input): (usize, &SliceInput)| {
        solve_prepared(model, input, options, &stiffness, &limits, i)
    };
    let solved: Result<Vec<SliceSolution>, DynamicsError> = if options.parallel {
        inputs.par_iter().enumerate().map(one).collect()
    } else {
        inputs.iter().enumerate().map(one).collect()
    };
    let slices = match solved {
        Ok(s) => s,
        // A solver failure with constraints on: name every such slice and what would help.
        Err(e @ DynamicsError::Solver { .. }) => {
            let failed: Vec<usize> = inputs
                .iter()
                .enumerate()
                .filter(|&(i, input)| matches!(one((i, input)), Err(DynamicsError::Solver { .. })))
                .map(|(i, _)| i)
                .collect();
            return Err(super::infeasible::diagnose(
                model, inputs, options, &limits, &failed, e,
            ));
        }
        Err(e) => return Err(e),
    };
    let mut report = ConstraintReport::default();
    for (i, (s, input)) in slices.iter().zip(inputs).enumerate() {
        check_slice(model, i, input, s, options.mu, &limits, &mut report);
    }
    Ok(CycleSolution {
        slices,
        stiffness,
        report,
    })
}

/// The QP of one slice as posed to the solver (for inspection and for checking optimality).
pub fn slice_problem(
    model: &Model,
    input: &SliceInput,
    options: &DynamicsOptions,
    slice: usize,
) -> Result<SliceProblem, DynamicsError> {
    validate_model(model)?;
    validate_input(model, input, slice)?;
    let stiffness = joint_stiffness(model)?;
    let limits = options.torque_limits.resolve(model);
    Ok(build(model, input, options, &stiffness, &limits))
}

/// Solve the QP of a built slice problem, with errors naming the slice.
pub fn solve_problem(
    model: &Model,
    problem: &SliceProblem,
    options: &DynamicsOptions,
    slice: usize,
) -> Result<QpSolution, DynamicsError> {
    let backend = if options.always_clarabel {
        Backend::Clarabel
    } else {
        Backend::Auto
    };
    let stance = || {
        problem
            .stance
            .iter()
            .map(|&i| model.feet[i].leg.name())
            .collect::<Vec<_>>()
            .join(" ")
    };
    qp::solve(&problem.qp, backend).map_err(|e| match e {
        QpError::InconsistentEqualities { residual } => DynamicsError::Unbalanced {
            slice,
            stance: stance(),
            residual,
        },
        QpError::NotUnique { condition } => DynamicsError::NotUnique {
            slice,
            stance: stance(),
            condition,
        },
        other => DynamicsError::Solver {
            slice,
            reason: other.to_string(),
        },
    })
}

fn solve_prepared(
    model: &Model,
    input: &SliceInput,
    options: &DynamicsOptions,
    stiffness: &[Option<f64>],
    limits: &[Option<f64>],
    slice: usize,
) -> Result<SliceSolution, DynamicsError> {
    validate_input(model, input, slice)?;
    let problem = build(model, input, options, stiffness, limits);
    let sol = solve_problem(model, &problem, options, slice)?;
    let grf = problem.foot_forces(model.feet.len(), &sol.x);
    let w = backward_pass(model, &problem.motions, &problem.required, &grf);
    let springs = spring_torques(model, &input.q);
    let mut torque = Vec::with_capacity(model.joints.len());
    let mut axis_moment = Vec::with_capacity(model.joints.len());
    let mut v_star = 0.0;
    for (j, joint) in model.joints.iter().enumerate() {
        let m = problem.motions[joint.child].axis.dot(&w.moment[j]);
        axis_moment.push(m);
        match stiffness[j] {
            Some(k) => {
                let t = m - springs[j];
                v_star += 0.5 * t * t / k;
                torque.push(t);
            }
            None => torque.push(m),
        }
    }
    Ok(SliceSolution {
        torque,
        axis_moment,
        spring_torque: springs,
        joint_force: w.force,
        joint_moment: w.moment,
        grf,
        foot_position: problem.feet,
        base_force: w.base_force,
        base_moment: w.base_moment,
        v_star,
        iterations: sol.iterations,
    })
}

fn validate_model(model: &Model) -> Result<(), DynamicsError> {
    let mut known = vec![false; model.bodies.len()];
    if let Some(k) = known.first_mut() {
        *k = true;
    }
    for j in &model.joints {
        if j.parent >= known.len() || !known[j.parent] || j.child >= known.len() {
            return Err(DynamicsError::JointOrder {
                joint: j.name.clone(),
                parent: j.parent,
            });
        }
        known[j.child] = true;
    }
    for f in &model.feet {
        if f.body >= model.bodies.len() {
            return Err(DynamicsError::FootBody {
                leg: f.leg.name().into(),
                body: f.body,
                bodies: model.bodies.len(),
            });
        }
    }
    Ok(())
}

fn validate_input(model: &Model, input: &SliceInput, slice: usize) -> Result<(), DynamicsError> {
    let nj = model.joints.len();
    let nf = model.feet.len();
    for (field, got, expected) in [
        ("q", input.q.len(), nj),
        ("qd", input.qd.len(), nj),
        ("qdd", input.qdd.len(), nj),
        ("stance", input.stance.len(), nf),
        ("normals", input.normals.len(), nf),
    ] {
        if got != expected {
            return Err(DynamicsError::InputLength {
                slice,
                field,
                expected,
                got,
            });
        }
    }
    for (field, v) in [("q", &input.q), ("qd", &input.qd), ("qdd", &input.qdd)] {
        if let Some(j) = v.iter().position(|x| !x.is_finite()) {
            return Err(DynamicsError::NotFinite {
                slice,
                field: format!("{field} of {}", model.joints[j].name),
            });
        }
    }
    let t = &input.thorax;
    for (field, v) in [
        ("gravity", &input.gravity),
        ("thorax linear velocity", &t.linear_velocity),
        ("thorax angular velocity", &t.angular_velocity),
        ("thorax linear acceleration", &t.linear_acceleration),
        ("thorax angular acceleration", &t.angular_acceleration),
    ] {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(DynamicsError::NotFinite {
                slice,
                field: field.into(),
            });
        }
    }
    for (f, n) in model.feet.iter().zip(&input.normals) {
        if !n.iter().all(|x| x.is_finite()) || n.norm() == 0.0 {
            return Err(DynamicsError::ZeroNormal {
                slice,
                leg: f.leg.name().into(),
            });
        }
    }
    Ok(())
}
