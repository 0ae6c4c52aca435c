//! Forward recursion from the thorax to the feet: pose, angular velocity and acceleration of every
//! body (paper eqs. 3 and 4) and the velocity and acceleration of its CoM (eqs. 5 and 6, here
//! analytic). Everything is expressed in the thorax frame of the slice.

use nalgebra::{Matrix3, Rotation3, Vector3};

use super::SliceInput;
use crate::model::Model;

/// Kinematic state of one body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMotion {
    /// Orientation of the body frame.
    pub rotation: Matrix3<f64>,
    /// Origin of the body frame (its proximal joint), m.
    pub origin: Vector3<f64>,
    /// Joint axis of the proximal joint (unit; zero for the thorax).
    pub axis: Vector3<f64>,
    pub omega: Vector3<f64>,
    pub alpha: Vector3<f64>,
    /// Velocity and acceleration of the frame origin.
    pub origin_velocity: Vector3<f64>,
    pub origin_acceleration: Vector3<f64>,
    /// CoM position, velocity and acceleration.
    pub com: Vector3<f64>,
    pub com_velocity: Vector3<f64>,
    pub com_acceleration: Vector3<f64>,
}

impl BodyMotion {
    fn at(rotation: Matrix3<f64>, origin: Vector3<f64>) -> Self {
        let z = Vector3::zeros();
        Self {
            rotation,
            origin,
            axis: z,
            omega: z,
            alpha: z,
            origin_velocity: z,
            origin_acceleration: z,
            com: origin,
            com_velocity: z,
            com_acceleration: z,
        }
    }

    fn finish_com(&mut self, com_local: &Vector3<f64>) {
        let r = self.rotation * com_local;
        self.com = self.origin + r;
        self.com_velocity = self.origin_velocity + self.omega.cross(&r);
        self.com_acceleration = self.origin_acceleration
            + self.alpha.cross(&r)
            + self.omega.cross(&self.omega.cross(&r));
    }
}

/// Motion of every body of `model` (indexed like `model.bodies`). Assumes the inputs were
/// validated (lengths, joint order).
pub fn body_motions(model: &Model, input: &SliceInput) -> Vec<BodyMotion> {
    let mut out = vec![BodyMotion::at(Matrix3::identity(), Vector3::zeros()); model.bodies.len()];
    let th = &input.thorax;
    let root = &mut out[0];
    root.omega = th.angular_velocity;
    root.alpha = th.angular_acceleration;
    root.origin_velocity = th.linear_velocity;
    root.origin_acceleration = th.linear_acceleration;
    root.finish_com(&model.bodies[0].com);
    for (j, joint) in model.joints.iter().enumerate() {
        let p = out[joint.parent];
        let rotation = p.rotation
            * joint.origin.rotation.to_rotation_matrix().matrix()
            * Rotation3::from_axis_angle(&joint.axis, input.q[j]).matrix();
        let r = p.rotation * joint.origin.translation.vector;
        let axis = rotation * joint.axis.into_inner();
        let spin = axis * input.qd[j];
        let mut c = BodyMotion::at(rotation, p.origin + r);
        c.axis = axis;
        c.omega = p.omega + spin;
        c.alpha = p.alpha + axis * input.qdd[j] + p.omega.cross(&spin);
        c.origin_velocity = p.origin_velocity + p.omega.cross(&r);
        c.origin_acceleration =
            p.origin_acceleration + p.alpha.cross(&r) + p.omega.cross(&p.omega.cross(&r));
        c.finish_com(&model.bodies[joint.child].com);
        out[joint.child] = c;
    }
    out
}
