//! The physics robot's walk animation (`walk.gif`, issue 17 item 5): a simulated pose (thorax pose
//! in the world and joint angles) is drawn where the thorax pose puts the planner's figure, and a
//! thorax moved in equal steps moves across the GIF's frames in equal steps.

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::plan;
use report::robot::{FRAME_SIZE, StickFigure, WalkPose, animate_walk, walk_figure};

const FOOT: [u8; 3] = [214, 39, 40];
/// Height of the legend strip under the views (animation.rs).
const LEGEND_H: usize = 36;

fn resting() -> (planner::model::Model, Vec<f64>) {
    let m = builtin("drosophibot2").unwrap();
    let p = plan(&m, &StepParams::table1(&m.name)).unwrap();
    (m, p.posture.q.clone())
}

fn pose(x: f64, yaw: f64, q: &[f64]) -> WalkPose {
    let q_yaw = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw);
    let c = q_yaw.quaternion().coords;
    WalkPose {
        // nalgebra stores (i, j, k, w); the log's quaternion is (w, x, y, z).
        thorax: ([x, 0.0, 0.17], [c[3], c[0], c[1], c[2]]),
        q: q.to_vec(),
        stance: vec![true; 6],
        caption: format!("x = {x} m"),
    }
}

#[test]
fn a_simulated_pose_is_the_planners_figure_moved_by_the_thorax_pose() {
    let (m, q) = resting();
    let all = vec![true; m.feet.len()];
    let local = StickFigure::from_angles(&m, &q, &all).unwrap();
    // Yawed 90 degrees left and lifted: thorax-frame (x, y, z) lands at (x0 - y, x, z + 0.17).
    let moved = walk_figure(&m, &pose(0.3, std::f64::consts::FRAC_PI_2, &q)).unwrap();
    for (a, b) in local.feet.iter().zip(&moved.feet) {
        let expected = Point3::new(0.3 - a.at.y, a.at.x, a.at.z + 0.17);
        assert!(
            (b.at - expected).norm() < 1e-9,
            "{:?}: {} vs {expected}",
            a.leg,
            b.at
        );
    }
    for (a, b) in local.joints.iter().zip(&moved.joints) {
        assert!((b - Point3::new(0.3 - a.y, a.x, a.z + 0.17)).norm() < 1e-9);
    }
    let t = Isometry3::translation(0.3, 0.0, 0.17)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    assert!((moved.feet[0].at - t * local.feet[0].at).norm() < 1e-9);
}

/// Mean column of the foot colour's pixels in the top view (left third, above the legend).
fn top_view_feet_column(frame: &[u8]) -> f64 {
    let (w, h) = (FRAME_SIZE.0 as usize, FRAME_SIZE.1 as usize);
    let (mut n, mut sum) = (0usize, 0usize);
    for y in 0..h - LEGEND_H {
        for x in 0..w / 3 {
            let i = 4 * (y * w + x);
            if frame[i..i + 3] == FOOT {
                n += 1;
                sum += x;
            }
        }
    }
    assert!(n > 0, "no foot pixels in the top view");
    sum as f64 / n as f64
}

#[test]
fn walk_gif_has_a_frame_per_pose_and_the_thorax_moves_across_them() {
    let (m, q) = resting();
    let poses: Vec<WalkPose> = [0.0, 0.1, 0.2].iter().map(|&x| pose(x, 0.0, &q)).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("walk.gif");
    let figures = animate_walk(&m, &poses, &path, 125).unwrap();
    assert_eq!(figures.len(), 3);
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
    let mut cols = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        // 125 ms: 12.5 hundredths, rounded to the nearest.
        assert_eq!(f.delay, 13);
        cols.push(top_view_feet_column(&f.buffer));
    }
    assert_eq!(cols.len(), 3);
    // One scale for the whole animation: equal moves of the thorax, equal moves in the picture
    // (to a pixel of rounding), forward (to the right in the top view).
    let (d1, d2) = (cols[1] - cols[0], cols[2] - cols[1]);
    assert!(d1 > 10.0, "the feet moved {d1} px for 0.1 m");
    assert!((d1 - d2).abs() < 1.0, "{d1} px then {d2} px");
}
