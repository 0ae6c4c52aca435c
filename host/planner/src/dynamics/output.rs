//! Outputs of a solved cycle for the plan reports: per-slice columns for joints.csv and feet.csv,
//! the joint_forces.csv table and servo commands with the torque bias (the plan.json summary is
//! [`super::summary`]).

use std::io::Write;

use super::CycleSolution;
use crate::model::{Actuation, Leg, Model};
use crate::number::{SIGNIFICANT, plain};

/// `torque_nm[slice][joint]` (model joint order).
pub fn torque_rows(cycle: &CycleSolution) -> Vec<Vec<f64>> {
    cycle.slices.iter().map(|s| s.torque.clone()).collect()
}

/// GRF components `[x, y, z][slice][leg]` with legs in the order `legs` (N).
pub fn grf_rows(model: &Model, legs: &[Leg], cycle: &CycleSolution) -> [Vec<Vec<f64>>; 3] {
    let foot_of: Vec<Option<usize>> = legs
        .iter()
        .map(|l| model.feet.iter().position(|f| f.leg == *l))
        .collect();
    std::array::from_fn(|axis| {
        cycle
            .slices
            .iter()
            .map(|s| {
                foot_of
                    .iter()
                    .map(|f| f.map_or(0.0, |f| s.grf[f][axis]))
                    .collect()
            })
            .collect()
    })
}

/// Servo command angles with the paper's torque bias (section 2.5): q + T / k_servo for
/// actuated joints (k_servo = the actuator's proportional stiffness, without the parallel spring,
/// because the spring does not move with the command), q for fixed joints.
pub fn biased_commands(model: &Model, q: &[f64], torque: &[f64]) -> Vec<f64> {
    model
        .joints
        .iter()
        .zip(q.iter().zip(torque))
        .map(|(j, (&q, &t))| match j.actuation {
            Actuation::Actuated { stiffness, .. } if stiffness > 0.0 => q + t / stiffness,
            _ => q,
        })
        .collect()
}

/// `slice,time_s,leg,joint,fx_n,fy_n,fz_n,mx_nm,my_nm,mz_nm,axis_moment_nm,spring_nm`: the force
/// and moment (about the joint origin) the parent exerts on the child, thorax frame.
pub fn write_joint_forces_csv<W: Write>(
    w: W,
    model: &Model,
    dt: f64,
    cycle: &CycleSolution,
) -> Result<(), csv::Error> {
    let mut out = csv::Writer::from_writer(w);
    out.write_record([
        "slice",
        "time_s",
        "leg",
        "joint",
        "fx_n",
        "fy_n",
        "fz_n",
        "mx_nm",
        "my_nm",
        "mz_nm",
        "axis_moment_nm",
        "spring_nm",
    ])?;
    for (s, sol) in cycle.slices.iter().enumerate() {
        for (j, joint) in model.joints.iter().enumerate() {
            let (f, m) = (sol.joint_force[j], sol.joint_moment[j]);
            let mut rec = vec![
                s.to_string(),
                plain(s as f64 * dt, SIGNIFICANT),
                joint.leg.name().into(),
                joint.kind.name().to_string(),
            ];
            rec.extend(
                [
                    f.x,
                    f.y,
                    f.z,
                    m.x,
                    m.y,
                    m.z,
                    sol.axis_moment[j],
                    sol.spring_torque[j],
                ]
                .iter()
                .map(|v| plain(*v, SIGNIFICANT)),
            );
            out.write_record(&rec)?;
        }
    }
    out.flush()?;
    Ok(())
}
