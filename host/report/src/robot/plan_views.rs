//! The robot of a plan: `robot.png` (the resting posture and a few phases of the step, each in
//! three views) and `step.gif` (one step cycle), both in the thorax frame, so the body stays and
//! the feet move back under it during stance.

use std::path::Path;

use nalgebra::{Point3, Vector3};
use plotters::prelude::*;

use super::animation::{Frame, LEGEND_H, write_gif};
use super::figure::{FigureError, StickFigure};
use super::views::{Bounds, Ground, ViewLayout, draw_legend, draw_views};
use planner::plan::Plan;
use planner::terrain::Terrain;

/// Phases of the step drawn in `robot.png` after the resting posture, fractions of the cycle.
pub const PHASES: [f64; 4] = [0.0, 0.25, 0.5, 0.75];
/// Most frames of `step.gif` (slices are skipped evenly beyond this).
pub const MAX_FRAMES: usize = 40;

/// The ground under a plan's robot, thorax frame: the plane the resting feet stand on (level in
/// the thorax frame on an incline too: the thorax stays parallel to it), or the ball.
pub fn plan_ground(plan: &Plan) -> Ground {
    match plan.terrain {
        Terrain::Flat | Terrain::Incline { .. } => {
            let z = plan
                .posture
                .feet
                .iter()
                .map(|(_, p)| p.z)
                .fold(f64::INFINITY, f64::min);
            if z.is_finite() {
                Ground::Plane {
                    point: Point3::new(0.0, 0.0, z),
                    normal: Vector3::z(),
                }
            } else {
                Ground::Nothing
            }
        }
        Terrain::Ball { radius_m, .. } => match plan.ball_centre {
            Some(c) => Ground::Ball {
                centre: Point3::from(c),
                radius: radius_m,
            },
            None => Ground::Nothing,
        },
    }
}

/// Stance flags in [`planner::model::Model::feet`] order at slice `s`.
fn stance_of(plan: &Plan, s: usize) -> Vec<bool> {
    plan.model
        .feet
        .iter()
        .map(|f| {
            plan.legs
                .iter()
                .position(|l| *l == f.leg)
                .is_some_and(|li| plan.stance[s][li])
        })
        .collect()
}

/// The slice nearest to `phase` (fraction of the cycle).
fn slice_at(plan: &Plan, phase: f64) -> usize {
    ((phase * plan.slices() as f64).round() as usize) % plan.slices().max(1)
}

/// Figure of slice `s` and its caption.
fn slice_frame(plan: &Plan, s: usize) -> Result<Frame, FigureError> {
    Ok(Frame {
        figure: StickFigure::from_angles(&plan.model, &plan.q[s], &stance_of(plan, s))?,
        caption: format!(
            "phase {:.2} of the step (slice {s}, t = {:.3} s of {:.3} s)",
            s as f64 / plan.slices() as f64,
            plan.time(s),
            plan.period_s
        ),
    })
}

/// `robot.png`: one row per pose (resting posture, then [`PHASES`]), three views each, the legend
/// at the bottom. Returns the views of every row (resting first), for finding points in the image.
pub fn plot_robot(plan: &Plan, path: &Path) -> Result<Vec<Vec<ViewLayout>>, FigureError> {
    let err = |reason: String| FigureError::Draw {
        path: path.display().to_string(),
        reason,
    };
    let resting = Frame {
        figure: StickFigure::from_angles(
            &plan.model,
            &plan.posture.q,
            &vec![true; plan.model.feet.len()],
        )?,
        caption: format!("{}: resting posture (every foot down)", plan.model.name),
    };
    let mut rows = vec![resting];
    for p in PHASES {
        rows.push(slice_frame(plan, slice_at(plan, p))?);
    }
    let ground = plan_ground(plan);
    let bounds = Bounds::around(rows.iter().map(|r| &r.figure), &ground);
    let row_h = 340u32;
    let (w, h) = (1200u32, row_h * rows.len() as u32 + LEGEND_H);
    let root = crate::Bitmap::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
    let (body, legend) = root.split_vertically(h - LEGEND_H);
    let mut layouts = Vec::new();
    for (area, row) in body.split_evenly((rows.len(), 1)).iter().zip(&rows) {
        layouts.push(draw_views(area, &row.figure, &ground, &bounds, &row.caption).map_err(err)?);
    }
    draw_legend(&legend).map_err(err)?;
    root.present().map_err(|e| err(e.to_string()))?;
    Ok(layouts)
}

/// `step.gif`: one step cycle in real time (at most [`MAX_FRAMES`] frames). Returns the number
/// of frames.
pub fn animate_step(plan: &Plan, path: &Path) -> Result<usize, FigureError> {
    let n = plan.slices();
    let every = n.div_ceil(MAX_FRAMES).max(1);
    let frames = (0..n)
        .step_by(every)
        .map(|s| slice_frame(plan, s))
        .collect::<Result<Vec<_>, _>>()?;
    let delay_ms = (plan.dt * every as f64 * 1e3).round() as u32;
    write_gif(path, &frames, &plan_ground(plan), delay_ms)?;
    Ok(frames.len())
}
