//! Slice inputs of a planned step cycle: the plan's angles and their derivatives, stance per foot,
//! gravity of the terrain, contact normals (along the radius on a ball), thorax at the plan's
//! constant velocity.

use nalgebra::Vector3;

use super::{SliceInput, ThoraxMotion};
use crate::plan::Plan;

/// One [`SliceInput`] per slice of `plan`, feet in `plan.model.feet` order.
pub fn plan_inputs(plan: &Plan) -> Vec<SliceInput> {
    let model = &plan.model;
    let leg_index: Vec<Option<usize>> = model
        .feet
        .iter()
        .map(|f| plan.legs.iter().position(|l| *l == f.leg))
        .collect();
    (0..plan.slices())
        .map(|s| {
            let stance = leg_index
                .iter()
                .map(|li| li.is_some_and(|li| plan.stance[s][li]))
                .collect();
            let normals = leg_index
                .iter()
                .map(|li| match (plan.ball_centre, li) {
                    (Some(c), Some(li)) => {
                        let d = plan.feet[s][*li] - c;
                        if d.norm() > 0.0 {
                            d.normalize()
                        } else {
                            Vector3::z()
                        }
                    }
                    _ => Vector3::z(),
                })
                .collect();
            SliceInput {
                q: plan.q[s].clone(),
                qd: plan.qd[s].clone(),
                qdd: plan.qdd[s].clone(),
                stance,
                thorax: ThoraxMotion {
                    linear_velocity: plan.thorax_velocity,
                    angular_velocity: plan.thorax_angular_velocity,
                    ..ThoraxMotion::default()
                },
                gravity: plan.gravity,
                normals,
            }
        })
        .collect()
}
