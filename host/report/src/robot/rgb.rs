//! One picture of the robot as RGB pixels (a Gymnasium `rgb_array` frame): the walk drawing's
//! three views of one simulated pose on its ground, legend below, [`FRAME_SIZE`] pixels, seen by
//! a camera centred on the thorax. The caller fixes the camera's half-extent so a sequence of
//! frames keeps one scale (the robot stays its size, the axes move under it).

use nalgebra::{Point3, Vector3};
use plotters::prelude::*;

use planner::model::Model;

use super::animation::{FRAME_SIZE, LEGEND_H};
use super::figure::FigureError;
use super::views::{Bounds, Ground, draw_legend, draw_views};
use super::walk::{WalkPose, walk_figure};

/// The camera's half-extent that holds `pose`'s figure around its thorax (and the ground right
/// under it), m, with the drawing's margin: pass it to [`pose_rgb`] for every frame of a run.
pub fn camera_half_extent(
    model: &Model,
    pose: &WalkPose,
    ground: &Ground,
) -> Result<[f64; 3], FigureError> {
    let fig = walk_figure(model, pose)?;
    let c = Point3::from(pose.thorax.0);
    let b = Bounds::following(&[&fig], &[c], ground)[0];
    let h = (b.max - b.min) / 2.0;
    Ok([h.x, h.y, h.z])
}

/// `pose` of `model` on `ground` as `FRAME_SIZE.1` rows of `FRAME_SIZE.0` RGB pixels, the camera
/// centred on the thorax with half-extent `half_m` (m).
pub fn pose_rgb(
    model: &Model,
    pose: &WalkPose,
    ground: &Ground,
    half_m: [f64; 3],
) -> Result<Vec<u8>, FigureError> {
    let err = |reason: String| FigureError::Draw {
        path: "an rgb frame".into(),
        reason,
    };
    let fig = walk_figure(model, pose)?;
    let c = Point3::from(pose.thorax.0);
    let half = Vector3::from(half_m);
    let bounds = Bounds {
        min: c - half,
        max: c + half,
    };
    let (w, h) = FRAME_SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = crate::Bitmap::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let (views, legend) = root.split_vertically(h - LEGEND_H);
        draw_views(&views, &fig, ground, &bounds, &pose.caption).map_err(err)?;
        draw_legend(&legend).map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(rgb)
}

/// What the drawing shows of the physics robot's ground, world frame: the plane z = 0 for flat
/// ground and an incline (the physics world keeps its ground level and tilts gravity), the
/// blocks themselves, nothing for a ball (its centre is the MJCF export's, not drawn here).
pub fn scene_ground(scene: &planner::terrain::Ground) -> Ground {
    use planner::terrain::Ground as G;
    match scene {
        G::Flat | G::Incline { .. } => Ground::Plane {
            point: Point3::origin(),
            normal: Vector3::z(),
        },
        G::Blocks(b) => Ground::Blocks(*b),
        G::Ball { .. } => Ground::Nothing,
    }
}
