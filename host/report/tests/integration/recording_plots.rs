//! The recording's plots (torque per phase, angles over time) name what they draw in a legend
//! strip between the title and the panels, and shade the stance of each joint's leg (issue 20
//! item 7). A hand-made two-joint table fixes the truth: `LF_ThC1`'s leg is in stance for the
//! first half of the step, `RF_ThC1`'s for the second; the recording stands for 0.5 s with torque
//! off, then walks two 1 s steps. The image is read back pixel by pixel.

use board::record::{JointMeta, Row, joints_of_table};
use protocol::gait::{GaitTableBuilder, JointSpec, ServoModel, Sign};
use report::legend::{ROW_H, STANCE};
use report::recording::{BAND, plot_angles, plot_torques};

const SLICES: usize = 20;
/// Bus cycles per second of the synthetic recording.
const HZ: usize = 100;
const STAND_S: f64 = 0.5;
const STEPS: usize = 2;

/// Stance bits of slice `s`: LF (bit 0 of Leg::ALL) for the first half, RF (bit 3) after.
fn stance_bits(s: usize) -> u8 {
    if s < SLICES / 2 { 1 << 0 } else { 1 << 3 }
}

fn joints() -> Vec<JointMeta> {
    let spec = |name: &str, id| JointSpec {
        name: name.into(),
        servo_id: id,
        model: ServoModel::Mx28,
        sign: Sign::Positive,
        zero_offset: 2048,
        min_rad: -1.0,
        max_rad: 1.0,
        stiffness_nm_per_rad: 5.0,
        leg: None,
    };
    let mut b = GaitTableBuilder::new(
        "legend",
        1.0,
        0.5,
        vec![spec("LF_ThC1", 1), spec("RF_ThC1", 2)],
    );
    for s in 0..SLICES {
        let a = 0.3 * (2.0 * std::f64::consts::PI * s as f64 / SLICES as f64).sin();
        b.slice(stance_bits(s), &[a, -a], &[0.1, -0.1]);
    }
    let bytes = b.build().unwrap();
    let table = protocol::GaitTable::parse(&bytes).unwrap();
    let names = ["LF_ThC1".to_string(), "RF_ThC1".to_string()];
    joints_of_table(&table, &names)
}

/// Standing at slice 0 with torque off, then two steps walked; one row per joint and cycle.
fn rows() -> Vec<Row> {
    let mut out = Vec::new();
    let stand = (STAND_S * HZ as f64) as usize;
    for c in 0..stand + STEPS * HZ {
        let walking = c >= stand;
        let k = c.saturating_sub(stand);
        let (step, slice) = if walking {
            (k / HZ, (k % HZ) * SLICES / HZ)
        } else {
            (0, 0)
        };
        for joint in 0..2 {
            let sign = if joint == 0 { 1.0 } else { -1.0 };
            let a = sign * 0.3 * (2.0 * std::f64::consts::PI * slice as f64 / SLICES as f64).sin();
            out.push(Row {
                time_s: c as f64 / HZ as f64,
                cycle: c as u32,
                step: step as u32,
                slice: slice as u16,
                joint,
                planned_rad: Some(a),
                commanded_rad: if walking { a + 0.02 } else { -3.0 },
                present_rad: a,
                velocity_rad_s: 0.0,
                load_raw: 0,
                torque_estimate_nm: walking.then_some(sign * 0.1 + 0.01 * (c % 3) as f64),
                modelled_nm: Some(sign * 0.1),
                error: 0,
                flags: if walking {
                    0
                } else {
                    protocol::feedback_flags::TORQUE_OFF
                },
                bus_cycle_us: 5000,
                platform_goal_ticks: None,
                platform_present_ticks: None,
                state: None,
                temperature_c: None,
                input_voltage_v: None,
            });
        }
    }
    out
}

struct Image {
    w: u32,
    h: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn read(path: &std::path::Path) -> Self {
        let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut rd = dec.read_info().unwrap();
        let mut rgb = vec![0; rd.output_buffer_size()];
        let info = rd.next_frame(&mut rgb).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        Self {
            w: info.width,
            h: info.height,
            rgb,
        }
    }

    fn px(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * self.w + x) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Pixels of colour `c` in the rectangle `xs` x `ys`.
    fn count(&self, c: [u8; 3], xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> usize {
        xs.flat_map(|x| ys.clone().map(move |y| (x, y)))
            .filter(|&(x, y)| self.px(x, y) == c)
            .count()
    }
}

const fn rgb(c: plotters::style::RGBColor) -> [u8; 3] {
    [c.0, c.1, c.2]
}
const BLACK: [u8; 3] = [0, 0, 0];
const BLUE: [u8; 3] = [0, 0, 255];
const RED: [u8; 3] = [255, 0, 0];
const GREY: [u8; 3] = rgb(STANCE);

/// Panels are 420 x 260 px; a chart's plotting area spans x from 6 (margin) + 48 (y labels) to
/// 420 - 6, so a fraction f of the x axis is at 54 + 360 f (to within a pixel of rounding).
fn panel_x(panel: u32, f: f64) -> u32 {
    420 * panel + 54 + (360.0 * f).round() as u32
}

/// The stance grey in a 3-px-wide column at fraction `f` of panel `panel`'s x axis, over the
/// panel's middle rows (clear of caption and labels).
fn grey_at(img: &Image, head: u32, panel: u32, f: f64) -> usize {
    let x = panel_x(panel, f);
    img.count(GREY, x - 1..x + 2, head + 60..head + 200)
}

#[test]
fn the_torque_plot_names_every_series_and_the_stance_above_the_panels() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("torque.png");
    let rows: Vec<Row> = rows().into_iter().filter(|r| r.flags == 0).collect();
    plot_torques(&path, &rows, &joints(), SLICES).unwrap();
    let img = Image::read(&path);
    let head = 60 + ROW_H;
    assert_eq!((img.w, img.h), (4 * 420, 260 + head));
    // The legend strip: a swatch for the modelled line, the measured mean, its band and stance.
    let strip = |c| img.count(c, 0..img.w, 60..head);
    for (what, c) in [
        ("modelled", BLACK),
        ("measured mean", BLUE),
        ("+-1 SD band", rgb(BAND)),
        ("stance", GREY),
    ] {
        assert!(strip(c) >= 20, "no {what} swatch in the legend strip");
    }
    // LF's panel (0) shaded over the first half of the phase, RF's (1) over the second.
    assert!(
        grey_at(&img, head, 0, 0.25) > 100,
        "LF stance at phase 0.25"
    );
    assert_eq!(grey_at(&img, head, 0, 0.75), 0, "LF swings at phase 0.75");
    assert_eq!(grey_at(&img, head, 1, 0.25), 0, "RF swings at phase 0.25");
    assert!(
        grey_at(&img, head, 1, 0.75) > 100,
        "RF stance at phase 0.75"
    );
    // Panels 2 and 3 hold no joint: nothing drawn there.
    assert_eq!(img.count(GREY, 840..1680, head..img.h), 0);
}

#[test]
fn the_angle_plot_names_every_series_and_shades_stance_only_while_walking() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("angles.png");
    let rows = rows();
    let t_end = rows.last().unwrap().time_s;
    plot_angles(&path, &rows, &joints()).unwrap();
    let img = Image::read(&path);
    let head = 40 + ROW_H;
    assert_eq!((img.w, img.h), (4 * 420, 260 + head));
    let strip = |c| img.count(c, 0..img.w, 40..head);
    for (what, c) in [("commanded", RED), ("present", BLUE), ("stance", GREY)] {
        assert!(strip(c) >= 20, "no {what} swatch in the legend strip");
    }
    let f = |t: f64| t / t_end;
    // Standing at slice 0 (LF's stance slice) shades nothing; walking shades LF's first
    // half-steps: 0.5..1.0 s and 1.5..2.0 s; RF's the second halves.
    assert_eq!(grey_at(&img, head, 0, f(0.25)), 0, "LF while standing");
    assert!(grey_at(&img, head, 0, f(0.75)) > 100, "LF stance, step 1");
    assert_eq!(grey_at(&img, head, 0, f(1.25)), 0, "LF swing, step 1");
    assert!(grey_at(&img, head, 0, f(1.75)) > 100, "LF stance, step 2");
    assert!(grey_at(&img, head, 1, f(1.25)) > 100, "RF stance, step 1");
    assert_eq!(grey_at(&img, head, 1, f(0.75)), 0, "RF swing, step 1");
    // The goal is not drawn while torque is off (a placeholder of -3 rad would be off the chart).
    let x = panel_x(0, f(0.25));
    assert_eq!(img.count(RED, x - 3..x + 4, head..head + 260), 0);
    let x = panel_x(0, f(0.9));
    assert!(img.count(RED, x - 3..x + 4, head..head + 260) > 0);
}
