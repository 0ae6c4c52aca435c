//! Forward kinematics of the whole body tree and leg Jacobians.

use crate::model::{Actuation, Leg, Model};
use nalgebra::{Isometry3, Matrix3xX, Point3, Unit, UnitQuaternion, Vector3};

/// Poses of every body and joint for one joint vector, in the thorax frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Poses {
    /// Pose of each body's frame (index as [`Model::bodies`]); body 0 is the identity.
    pub bodies: Vec<Isometry3<f64>>,
    /// Position of each joint (index as [`Model::joints`]).
    pub joint_positions: Vec<Point3<f64>>,
    /// Rotation axis of each joint, unit length.
    pub joint_axes: Vec<Unit<Vector3<f64>>>,
    /// Foot contact points in [`Model::feet`] order.
    pub feet: Vec<Point3<f64>>,
}

/// The angle a joint actually takes: `q[j]`, or the fixed angle of a fixed joint.
pub fn joint_angle(model: &Model, j: usize, q: &[f64]) -> f64 {
    match model.joints[j].actuation {
        Actuation::Fixed { angle } => angle,
        Actuation::Actuated { .. } => q[j],
    }
}

/// Forward kinematics. `q` holds one angle per joint in model order (entries of fixed joints are
/// ignored). Panics if `q.len() != model.joints.len()` (a programming error, not input).
pub fn forward(model: &Model, q: &[f64]) -> Poses {
    assert_eq!(q.len(), model.joints.len(), "one angle per model joint");
    let mut bodies = vec![Isometry3::identity(); model.bodies.len()];
    let mut joint_positions = Vec::with_capacity(model.joints.len());
    let mut joint_axes = Vec::with_capacity(model.joints.len());
    for (j, joint) in model.joints.iter().enumerate() {
        let frame = bodies[joint.parent] * joint.origin;
        joint_positions.push(Point3::from(frame.translation.vector));
        joint_axes.push(Unit::new_unchecked(
            frame.rotation * joint.axis.into_inner(),
        ));
        bodies[joint.child] =
            frame * UnitQuaternion::from_axis_angle(&joint.axis, joint_angle(model, j, q));
    }
    let feet = model
        .feet
        .iter()
        .map(|f| bodies[f.body] * Point3::from(f.point))
        .collect();
    Poses {
        bodies,
        joint_positions,
        joint_axes,
        feet,
    }
}

/// Position Jacobian of a leg's foot with respect to its actuated joints (proximal first), in the
/// thorax frame: column k is `axis_k x (foot - joint_k)`. Returns the joint indices and the matrix.
pub fn leg_jacobian(model: &Model, poses: &Poses, leg: Leg) -> (Vec<usize>, Matrix3xX<f64>) {
    let Some(fi) = model.feet.iter().position(|f| f.leg == leg) else {
        return (Vec::new(), Matrix3xX::zeros(0));
    };
    let p = poses.feet[fi];
    let joints: Vec<usize> = model
        .leg_chain(leg)
        .into_iter()
        .filter(|&j| model.is_actuated(j))
        .collect();
    let mut jac = Matrix3xX::zeros(joints.len());
    for (k, &j) in joints.iter().enumerate() {
        jac.set_column(
            k,
            &poses.joint_axes[j].cross(&(p - poses.joint_positions[j])),
        );
    }
    (joints, jac)
}
