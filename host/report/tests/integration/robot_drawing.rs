//! The robot drawing (issue 20 item 8): robot.png and step.gif are produced with the expected
//! size and frames, and the figure puts each foot where the planner placed it (the planner's foot
//! targets, which the IK meets to its tolerance), stance feet filled, swing feet open, the ground
//! line at the resting feet's height, one scale in every view, and a legend naming each element.

use nalgebra::{Isometry3, Point3};
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::{Plan, plan};
use plotters::prelude::*;
use report::robot::{
    Bounds, FRAME_SIZE, FigureError, Ground, StickFigure, View, ViewLayout, animate_step,
    draw_legend, draw_views, plan_ground, plot_robot,
};

const FOOT: [u8; 3] = [214, 39, 40];
const GROUND: [u8; 3] = [140, 110, 70];
const LEFT: [u8; 3] = [31, 119, 180];
const RIGHT: [u8; 3] = [255, 127, 14];

fn robot_plan(slices: usize) -> Plan {
    let m = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1(&m.name);
    p.slices = slices;
    plan(&m, &p).unwrap()
}

/// An RGB image drawn in memory.
struct Image {
    w: u32,
    h: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn at(&self, x: i32, y: i32) -> [u8; 3] {
        assert!(x >= 0 && y >= 0 && (x as u32) < self.w && (y as u32) < self.h);
        let i = 3 * (y as usize * self.w as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
    /// Whether colour `c` is within `r` pixels of (x, y).
    fn near(&self, (x, y): (i32, i32), r: i32, c: [u8; 3]) -> bool {
        (-r..=r).any(|dx| (-r..=r).any(|dy| self.at(x + dx, y + dy) == c))
    }
    fn count(&self, c: [u8; 3]) -> usize {
        self.rgb.chunks_exact(3).filter(|p| *p == c).count()
    }
}

/// Draws `figure` as robot.png and step.gif draw a row (three views, then the legend below).
fn draw(figure: &StickFigure, ground: &Ground) -> (Image, Vec<ViewLayout>) {
    let (w, h) = (1200u32, 380u32);
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    let layouts = {
        let root = report::Bitmap::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).unwrap();
        let (views, legend) = root.split_vertically(h - 36);
        let bounds = Bounds::around([figure], ground);
        let l = draw_views(&views, figure, ground, &bounds, "test").unwrap();
        draw_legend(&legend).unwrap();
        root.present().unwrap();
        l
    };
    (Image { w, h, rgb }, layouts)
}

fn stance_of(plan: &Plan, s: usize) -> Vec<bool> {
    plan.model
        .feet
        .iter()
        .map(|f| plan.stance[s][plan.legs.iter().position(|l| *l == f.leg).unwrap()])
        .collect()
}

#[test]
fn resting_feet_are_drawn_where_the_planner_put_them() {
    let plan = robot_plan(40);
    let fig = StickFigure::from_angles(&plan.model, &plan.posture.q, &[true; 6]).unwrap();
    let ground = plan_ground(&plan);
    let (img, layouts) = draw(&fig, &ground);
    assert_eq!(
        layouts.iter().map(|l| l.view).collect::<Vec<_>>(),
        View::ALL
    );
    for l in &layouts {
        // True proportions: the same mm per pixel along both axes of every view.
        let (left, top, right, bottom) = l.pixels;
        let sx = f64::from(right - left) / (l.h_mm.1 - l.h_mm.0);
        let sy = f64::from(bottom - top) / (l.v_mm.1 - l.v_mm.0);
        let s0 = f64::from(layouts[0].pixels.2 - layouts[0].pixels.0)
            / (layouts[0].h_mm.1 - layouts[0].h_mm.0);
        assert!((sx / sy - 1.0).abs() < 1e-9 && (sx / s0 - 1.0).abs() < 1e-9);
        for (leg, target) in &plan.posture.feet {
            // Pixel of the planner's foot target, mapped here from the plot's edges and range.
            let (h, v) = l.view.project(&Point3::from(*target));
            let px = left + ((h * 1e3 - l.h_mm.0) * sx).round() as i32;
            let py = bottom - ((v * 1e3 - l.v_mm.0) * sy).round() as i32;
            assert!(
                img.near((px, py), 2, FOOT),
                "{leg:?} foot not drawn at ({px}, {py}) in the {:?} view",
                l.view
            );
        }
    }
    // Ground line at the resting feet's height, in the side and front views, at the plot's left.
    let z = plan
        .posture
        .feet
        .iter()
        .map(|(_, p)| p.z)
        .fold(f64::MAX, f64::min);
    for l in &layouts[1..] {
        let (left, _, _, _) = l.pixels;
        let y = l.pixel(&Point3::new(0.0, 0.0, z)).1;
        assert!(
            img.near((left + 4, y), 1, GROUND),
            "{:?} view: no ground",
            l.view
        );
    }
    // The top view draws no ground; left legs blue and right legs orange in every view.
    let (left, top, right, bottom) = layouts[0].pixels;
    let mut ground_in_top = 0;
    for y in top..bottom {
        for x in left..right {
            ground_in_top += usize::from(img.at(x, y) == GROUND);
        }
    }
    assert_eq!(ground_in_top, 0);
    assert!(img.count(LEFT) > 500 && img.count(RIGHT) > 500);
}

#[test]
fn swing_feet_are_open_and_stance_feet_filled() {
    let plan = robot_plan(40);
    // A slice where some legs swing and some stand (tripod: three and three).
    let s = (0..plan.slices())
        .find(|&s| plan.stance[s].iter().filter(|&&st| st).count() == 3)
        .unwrap();
    let stance = stance_of(&plan, s);
    let fig = StickFigure::from_angles(&plan.model, &plan.q[s], &stance).unwrap();
    let (img, layouts) = draw(&fig, &plan_ground(&plan));
    let top = &layouts[0];
    for (f, foot) in plan.model.feet.iter().enumerate() {
        let li = plan.legs.iter().position(|l| *l == foot.leg).unwrap();
        let c = top.pixel(&Point3::from(plan.feet[s][li]));
        if stance[f] {
            assert!(
                img.near(c, 1, FOOT),
                "{:?}: stance foot not filled",
                foot.leg
            );
        } else {
            assert!(
                img.near(c, 1, [255, 255, 255]),
                "{:?}: swing foot filled",
                foot.leg
            );
            assert!(img.near((c.0 + 5, c.1), 1, FOOT), "{:?}: no ring", foot.leg);
        }
    }
}

#[test]
fn robot_png_and_step_gif_have_their_size_and_frames() {
    let plan = robot_plan(40);
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("robot.png");
    let rows = plot_robot(&plan, &png).unwrap();
    // Resting posture and four phases, three views each.
    assert_eq!(rows.len(), 5);
    assert!(rows.iter().all(|r| r.len() == 3));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (1200, 5 * 340 + 36));

    let gif_path = dir.path().join("step.gif");
    assert_eq!(animate_step(&plan, &gif_path).unwrap(), 40);
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts
        .read_info(std::fs::File::open(&gif_path).unwrap())
        .unwrap();
    assert_eq!(
        (u32::from(dec.width()), u32::from(dec.height())),
        FRAME_SIZE
    );
    let mut frames = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        // One slice per frame in real time: dt in hundredths of a second.
        let ms = (plan.dt * 1e3).round() as u32;
        assert_eq!(u32::from(f.delay), (ms + 5) / 10);
        frames.push(f.buffer.to_vec());
    }
    assert_eq!(frames.len(), 40);
    // The fixed palette keeps the figure's colours exact; the legs move between frames.
    let has = |f: &[u8], c: [u8; 3]| f.chunks_exact(4).any(|p| p[..3] == c);
    assert!(has(&frames[0], FOOT) && has(&frames[0], LEFT) && has(&frames[0], GROUND));
    assert_ne!(frames[0], frames[10]);
}

#[test]
fn a_pose_that_does_not_fit_the_model_is_named() {
    let m = builtin("drosophibot2").unwrap();
    let e = StickFigure::from_bodies(&m, &[Isometry3::identity(); 2], &[true; 6]).unwrap_err();
    assert_eq!(
        e,
        FigureError::BodyCount {
            model: m.name.clone(),
            expected: m.bodies.len(),
            got: 2
        }
    );
    assert!(e.to_string().contains("2 body poses"), "{e}");
    let bodies = vec![Isometry3::identity(); m.bodies.len()];
    let e = StickFigure::from_bodies(&m, &bodies, &[true; 5]).unwrap_err();
    assert!(e.to_string().contains("5 stance flags"), "{e}");
}
