//! Uneven ground in the walk drawing: seen from above, every block is shaded by its height, so in
//! the GIF the pixels at the centres of high blocks are darker than those at low blocks (checked
//! against the seeded field itself, `planner::terrain::Blocks`).

use nalgebra::Point3;
use planner::gait::StepParams;
use planner::model::builtin;
use planner::plan::plan;
use planner::terrain::Blocks;
use report::robot::{FRAME_SIZE, Ground, View, WalkPose, animate_walk_on};

#[test]
fn from_above_high_blocks_are_darker_than_low_ones() {
    let m = builtin("drosophibot2").unwrap();
    let q = plan(&m, &StepParams::table1(&m.name)).unwrap().posture.q;
    let b = Blocks {
        seed: 11,
        ..Blocks::DEFAULT
    };
    let pose = WalkPose {
        thorax: ([0.4, 0.0, 0.18], [1.0, 0.0, 0.0, 0.0]),
        q,
        stance: vec![true; 6],
        caption: "blocks".into(),
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("walk.gif");
    let drawn = animate_walk_on(&m, &[pose], &path, 100, &Ground::Blocks(b)).unwrap();
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(std::fs::File::open(&path).unwrap()).unwrap();
    let frame = dec.read_next_frame().unwrap().unwrap().buffer.to_vec();
    let top = drawn.layouts[0]
        .iter()
        .find(|l| l.view == View::Top)
        .unwrap();
    let w = FRAME_SIZE.0 as i32;
    let brightness = |px: (i32, i32)| {
        let i = 4 * (px.1 * w + px.0) as usize;
        frame[i..i + 3].iter().map(|&c| f64::from(c)).sum::<f64>()
    };
    let (l, t, r, bot) = top.pixels;
    let (mut high, mut low) = (Vec::new(), Vec::new());
    for c in b.cells() {
        let px = top.pixel(&Point3::new(c.centre_xy_m[0], c.centre_xy_m[1], 0.0));
        if px.0 <= l + 2 || px.0 >= r - 2 || px.1 <= t + 2 || px.1 >= bot - 2 {
            continue;
        }
        let h = c.top_m.unwrap() / b.max_height_m;
        if h > 0.8 {
            high.push(brightness(px));
        } else if h < 0.2 {
            low.push(brightness(px));
        }
    }
    assert!(
        high.len() >= 5 && low.len() >= 5,
        "{} high, {} low in view",
        high.len(),
        low.len()
    );
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // Shades: a low top is 25 % of the way from white to the ground colour, a high one 80-100 %
    // (the robot's bones cover a few centres, hence means and a margin).
    assert!(
        mean(&low) - mean(&high) > 150.0,
        "low {:.0}, high {:.0}",
        mean(&low),
        mean(&high)
    );
}
