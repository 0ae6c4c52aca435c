//! The plots name everything they draw beside the data (issue 20 item 7): the joint-angle plot's
//! legend column holds one swatch per joint and one for the stance shading, in its own area right
//! of the chart (so it cannot cover a curve).

use planner::gait::StepParams;
use planner::model::builtin;
use report::legend::COLUMN_W;
use report::plan::plot_joint_angles;
use report::style::colour;

fn read_png(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut rd = dec.read_info().unwrap();
    let mut buf = vec![0; rd.output_buffer_size()];
    let info = rd.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    (info.width, info.height, buf)
}

#[test]
fn joint_angle_legend_names_joints_and_stance_beside_the_chart() {
    let m = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1(&m.name);
    p.slices = 20;
    let plan = planner::plan::plan(&m, &p).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("joint_angles.png");
    plot_joint_angles(&plan, &path).unwrap();
    let (w, h, rgb) = read_png(&path);
    assert_eq!((w, h), (1400, 1100));
    let px = |x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        [rgb[i], rgb[i + 1], rgb[i + 2]]
    };
    // The top-left panel (LF): 700 px wide, its legend the rightmost COLUMN_W px.
    let key_x = 700 - COLUMN_W;
    let count = |c: [u8; 3], xs: std::ops::Range<u32>| {
        xs.flat_map(|x| (0..360).map(move |y| (x, y)))
            .filter(|&(x, y)| px(x, y) == c)
            .count()
    };
    let joints = m
        .leg_chain(planner::model::Leg::LF)
        .into_iter()
        .filter(|&j| m.is_actuated(j))
        .count();
    assert!(joints >= 4);
    for k in 0..joints {
        let c = colour(k);
        let c = [c.0, c.1, c.2];
        assert!(
            count(c, key_x..700) >= 20,
            "joint {k}: no swatch in the legend column"
        );
    }
    assert!(
        count([225, 225, 225], key_x..700) >= 100,
        "no stance swatch"
    );
}
