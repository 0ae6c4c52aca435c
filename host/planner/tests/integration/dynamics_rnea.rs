//! Joint torques and joint wrenches agree with an independent rigid-body dynamics implementation
//! (spatial-vector recursive Newton-Euler) when the solved foot forces are applied to it, and the
//! thorax then needs no further support.

use crate::dynamics_support;
use dynamics_support::rnea::{BaseState, forward, rnea};
use dynamics_support::{standing_pose, toy_hexapod, trajectory, with_springs};
use nalgebra::Vector3;
use planner::dynamics::{DynamicsOptions, SliceInput, ThoraxMotion, solve_slice};

#[test]
fn torques_match_independent_rnea() {
    let model = with_springs(toy_hexapod(), 0.3, 0.2);
    let q0 = standing_pose(&model);
    let thorax = ThoraxMotion {
        linear_velocity: Vector3::new(0.1, 0.0, 0.0),
        angular_velocity: Vector3::new(0.05, 0.1, -0.2),
        linear_acceleration: Vector3::new(0.3, 0.1, -0.2),
        angular_acceleration: Vector3::new(0.2, -0.1, 0.3),
    };
    let weight = model.bodies.iter().map(|b| b.mass).sum::<f64>() * 9.81;
    for i in 0..10usize {
        let (q, qd, qdd) = trajectory(&model, &q0, 0.05 * i as f64);
        let mut input = SliceInput::still(&model, q.clone());
        input.qd = qd.clone();
        input.qdd = qdd.clone();
        input.thorax = thorax;
        input.stance = (0..6usize)
            .map(|f| i.is_multiple_of(2) || f.is_multiple_of(2))
            .collect();
        let s = solve_slice(&model, &input, &DynamicsOptions::default(), i).unwrap();
        let base = BaseState {
            omega: thorax.angular_velocity,
            alpha: thorax.angular_acceleration,
            velocity: thorax.linear_velocity,
            acceleration: thorax.linear_acceleration,
        };
        let k = forward(&model, &q, &qd, &qdd, base, input.gravity);
        let r = rnea(&model, &q, &k, &s.grf);
        let scale = weight * 0.3;
        for (j, joint) in model.joints.iter().enumerate() {
            let name = &joint.name;
            assert!(
                (r.tau[j] - s.axis_moment[j]).abs() < 1e-10 * scale,
                "slice {i} {name}: {} vs {}",
                r.tau[j],
                s.axis_moment[j]
            );
            // The actuator torque is the axis moment minus the spring's share.
            let spring = joint
                .spring
                .map_or(0.0, |sp| -sp.stiffness * (q[j] - sp.equilibrium));
            if joint.spring.is_some() {
                assert!((s.torque[j] - (r.tau[j] - spring)).abs() < 1e-10 * scale);
            }
            assert!(
                (r.force[j] - s.joint_force[j]).norm() < 1e-10 * weight,
                "slice {i} {name} force"
            );
            assert!(
                (r.moment[j] - s.joint_moment[j]).norm() < 1e-10 * scale,
                "slice {i} {name} moment"
            );
        }
        assert!(
            r.base.1.norm() < 1e-10 * weight,
            "slice {i}: thorax force residual {}",
            r.base.1
        );
        assert!(
            r.base.0.norm() < 1e-10 * scale,
            "slice {i}: thorax moment residual {}",
            r.base.0
        );
    }
}
