//! The physics robot's walk as a GIF (`walk.gif`): the simulated body in the world frame, one
//! frame per logged pose (thorax pose and joint angles, drawn through the model's forward
//! kinematics), on the ground plane z = 0. The camera follows the thorax at one scale for the
//! whole walk, so the robot stays large however far it walks, and the axes (the world, in mm)
//! move under it.

use std::path::Path;

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

use planner::kinematics::forward;
use planner::model::Model;

use super::animation::{Frame, write_gif_following};
use super::figure::{FigureError, StickFigure};
use super::views::{Ground, ViewLayout};

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

/// What [`animate_walk`] drew.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkGif {
    /// One figure per frame, world frame.
    pub figures: Vec<StickFigure>,
    /// Where each frame's three views put the world (they move with the thorax).
    pub layouts: Vec<Vec<ViewLayout>>,
}

/// Writes `poses` of `model` as a looping GIF, each frame shown `delay_ms`, seen by a camera
/// that follows the thorax; the ground is the plane z = 0.
pub fn animate_walk(
    model: &Model,
    poses: &[WalkPose],
    path: &Path,
    delay_ms: u32,
) -> Result<WalkGif, FigureError> {
    let ground = Ground::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    animate_walk_on(model, poses, path, delay_ms, &ground)
}

/// As [`animate_walk`], on `ground` (world frame: e.g. blocks).
pub fn animate_walk_on(
    model: &Model,
    poses: &[WalkPose],
    path: &Path,
    delay_ms: u32,
    ground: &Ground,
) -> Result<WalkGif, FigureError> {
    let frames = poses
        .iter()
        .map(|p| {
            Ok(Frame {
                figure: walk_figure(model, p)?,
                caption: p.caption.clone(),
            })
        })
        .collect::<Result<Vec<_>, FigureError>>()?;
    let centres: Vec<Point3<f64>> = poses.iter().map(|p| Point3::from(p.thorax.0)).collect();
    let layouts = write_gif_following(path, &frames, &centres, ground, delay_ms)?;
    Ok(WalkGif {
        figures: frames.into_iter().map(|f| f.figure).collect(),
        layouts,
    })
}
