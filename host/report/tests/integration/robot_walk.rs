//! The physics robot's walk animation (`walk.gif`, issue 17 item 5): a simulated pose (thorax pose
//! in the world and joint angles) is drawn where the thorax pose puts the planner's figure, and
//! the camera follows the thorax (issue 20): the robot keeps its place and size in the picture
//! however far it walks, while the axes move under it by exactly the distance walked.

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::plan;
use report::robot::{
    FRAME_SIZE, Frame, Ground, StickFigure, WalkPose, animate_walk, walk_figure, write_gif,
};

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

/// Columns of the foot colour's pixels in the top view (left third, above the legend):
/// (mean, leftmost, rightmost).
type FeetColumns = (f64, usize, usize);

fn top_view_feet_columns(frame: &[u8]) -> FeetColumns {
    let (w, h) = (FRAME_SIZE.0 as usize, FRAME_SIZE.1 as usize);
    let (mut n, mut sum, mut lo, mut hi) = (0usize, 0usize, usize::MAX, 0usize);
    for y in 0..h - LEGEND_H {
        for x in 0..w / 3 {
            let i = 4 * (y * w + x);
            if frame[i..i + 3] == FOOT {
                n += 1;
                sum += x;
                lo = lo.min(x);
                hi = hi.max(x);
            }
        }
    }
    assert!(n > 0, "no foot pixels in the top view");
    (sum as f64 / n as f64, lo, hi)
}

/// Writes a walk of the resting robot through `xs` (thorax x, m) and returns, per frame, the
/// delay and the top view's foot columns, with what `animate_walk` says it drew.
fn walk_gif(xs: &[f64]) -> (Vec<(u16, FeetColumns)>, report::robot::WalkGif) {
    let (m, q) = resting();
    let poses: Vec<WalkPose> = xs.iter().map(|&x| pose(x, 0.0, &q)).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("walk.gif");
    let drawn = animate_walk(&m, &poses, &path, 125).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
    let mut frames = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        frames.push((f.delay, top_view_feet_columns(&f.buffer)));
    }
    (frames, drawn)
}

#[test]
fn walk_gif_follows_the_thorax_and_the_axes_move_by_the_distance_walked() {
    let (frames, drawn) = walk_gif(&[0.0, 0.1, 0.2]);
    assert_eq!(frames.len(), 3);
    assert_eq!(drawn.figures.len(), 3);
    for (delay, _) in &frames {
        // 125 ms: 12.5 hundredths, rounded to the nearest.
        assert_eq!(*delay, 13);
    }
    // The robot stands still in the picture (to a pixel of rounding)...
    let cols: Vec<f64> = frames.iter().map(|f| f.1.0).collect();
    for c in &cols[1..] {
        assert!((c - cols[0]).abs() < 1.0, "the feet moved: {cols:?}");
    }
    // ... and the world moves under it: each view's horizontal range (mm) shifts by the 100 mm
    // walked in the top and side views, not at all in the front view (y), at one scale.
    let top_side_front = |f: usize| drawn.layouts[f].iter().map(|l| l.h_mm).collect::<Vec<_>>();
    for f in 1..3 {
        let (a, b) = (top_side_front(f - 1), top_side_front(f));
        for (v, (ra, rb)) in a.iter().zip(&b).enumerate() {
            let shift = if v < 2 { 100.0 } else { 0.0 };
            assert!(
                (rb.0 - ra.0 - shift).abs() < 1e-6,
                "view {v}: {ra:?} -> {rb:?}"
            );
            assert!(
                (rb.1 - ra.1 - shift).abs() < 1e-6,
                "view {v}: {ra:?} -> {rb:?}"
            );
        }
    }
}

#[test]
fn a_long_walk_draws_the_robot_as_large_as_a_short_one() {
    // 1.5 m is ten steps of the servo-safe gait: one box around the whole walk (the still
    // camera of `write_gif`) shrinks the robot; the following camera keeps a standing robot's scale.
    let xs: Vec<f64> = (0..16).map(|k| f64::from(k) * 0.1).collect();
    let (short, _) = walk_gif(&[0.0, 0.1]);
    let (long, drawn) = walk_gif(&xs);
    let span = |c: &FeetColumns| (c.2 - c.1) as f64;
    let (a, b) = (span(&short[0].1), span(&long[0].1));
    assert!((a - b).abs() <= 2.0, "short walk {a} px, long walk {b} px");
    let (l, _, r, _) = drawn.layouts[0][0].pixels;
    let width = f64::from(r - l);
    assert!(b > 0.4 * width, "the feet span {b} px of a {width} px view");

    let (m, q) = resting();
    let frames: Vec<Frame> = xs
        .iter()
        .map(|&x| Frame {
            figure: walk_figure(&m, &pose(x, 0.0, &q)).unwrap(),
            caption: String::new(),
        })
        .collect();
    let ground = Ground::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("still.gif");
    write_gif(&path, &frames, &ground, 125).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
    let still = span(&top_view_feet_columns(
        &dec.read_next_frame().unwrap().unwrap().buffer,
    ));
    assert!(b > 2.5 * still, "following {b} px, still camera {still} px");
}
