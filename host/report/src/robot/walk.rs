//! The physics robot's walk as a GIF (`walk.gif`): the simulated body in the world frame, one
//! frame per logged pose (thorax pose and joint angles, drawn through the model's forward
//! kinematics), on the ground plane z = 0, so the robot is seen to move across the views.

use std::path::Path;

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

use planner::kinematics::forward;
use planner::model::Model;

use super::animation::{Frame, write_gif};
use super::figure::{FigureError, StickFigure};
use super::views::Ground;

/// One pose of a simulated walk.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkPose {
    /// Thorax position (m) and orientation (quaternion w, x, y, z), world frame.
    pub thorax: ([f64; 3], [f64; 4]),
    /// One angle per model joint (fixed joints' entries ignored), rad.
    pub q: Vec<f64>,
    /// Whether each foot ([`Model::feet`] order) carries load.
    pub stance: Vec<bool>,
    pub caption: String,
}

/// The figure of `model` at `pose`, world frame.
pub fn walk_figure(model: &Model, pose: &WalkPose) -> Result<StickFigure, FigureError> {
    let ([x, y, z], [w, qx, qy, qz]) = pose.thorax;
    let thorax = Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_quaternion(Quaternion::new(w, qx, qy, qz)),
    );
    let bodies: Vec<Isometry3<f64>> = forward(model, &pose.q)
        .bodies
        .iter()
        .map(|b| thorax * b)
        .collect();
    StickFigure::from_bodies(model, &bodies, &pose.stance)
}

/// Writes `poses` of `model` as a looping GIF, each frame shown `delay_ms`; the ground is the
/// plane z = 0. Returns the figures drawn (one per frame, world frame).
pub fn animate_walk(
    model: &Model,
    poses: &[WalkPose],
    path: &Path,
    delay_ms: u32,
) -> Result<Vec<StickFigure>, FigureError> {
    let frames = poses
        .iter()
        .map(|p| {
            Ok(Frame {
                figure: walk_figure(model, p)?,
                caption: p.caption.clone(),
            })
        })
        .collect::<Result<Vec<_>, FigureError>>()?;
    let ground = Ground::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    write_gif(path, &frames, &ground, delay_ms)?;
    Ok(frames.into_iter().map(|f| f.figure).collect())
}
