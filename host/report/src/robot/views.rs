//! The three views of a stick figure (top, side, front) drawn side by side on one drawing area,
//! at one scale (mm per pixel equal in every view and both axes, so lengths and angles look true),
//! and the legend that names every element. The views report where they put the world, so tests
//! and callers can find a point in the picture.

use nalgebra::{Point3, Vector3};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::figure::{Part, StickFigure};
use super::view::{Chart, FOOT, GROUND, JOINT, THORAX, View};
use crate::style::{colour, register_font};

/// The ground under the robot, in the figure's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ground {
    /// A plane through `point` with normal `normal` (drawn as a line in the side and front views).
    Plane {
        point: Point3<f64>,
        normal: Vector3<f64>,
    },
    /// A ball (drawn as its outline in every view).
    Ball { centre: Point3<f64>, radius: f64 },
    /// Uneven ground, world frame (drawn by `blocks.rs`).
    Blocks(planner::terrain::Blocks),
    /// Nothing drawn.
    Nothing,
}

/// Where a view put the world: its plot rectangle in pixels and the mm it spans.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewLayout {
    pub view: View,
    /// Left, top, right and bottom edge of the plot area, pixels of the whole image (the low end
    /// of the horizontal range maps to the left edge, the low end of the vertical to the bottom).
    pub pixels: (i32, i32, i32, i32),
    /// Horizontal and vertical extent of the plot area, mm (low, high).
    pub h_mm: (f64, f64),
    pub v_mm: (f64, f64),
}

impl ViewLayout {
    /// Pixel of a point (m) in this view.
    pub fn pixel(&self, p: &Point3<f64>) -> (i32, i32) {
        let (h, v) = self.view.project(p);
        let (l, t, r, b) = self.pixels;
        let fx = (h * 1e3 - self.h_mm.0) / (self.h_mm.1 - self.h_mm.0);
        let fy = (v * 1e3 - self.v_mm.0) / (self.v_mm.1 - self.v_mm.0);
        (
            l + (fx * f64::from(r - l)).round() as i32,
            b + (fy * f64::from(t - b)).round() as i32,
        )
    }
}

/// The region every frame of a drawing shows, m (shared so that an animation does not jump).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub min: Point3<f64>,
    pub max: Point3<f64>,
}

impl Bounds {
    /// The box around every point of `figures` (and the ball of `ground`), with a margin.
    pub fn around<'a>(figures: impl IntoIterator<Item = &'a StickFigure>, ground: &Ground) -> Self {
        let (mut min, mut max) = (
            Point3::from(Vector3::repeat(f64::INFINITY)),
            Point3::from(Vector3::repeat(f64::NEG_INFINITY)),
        );
        for p in figures.into_iter().flat_map(|f| f.points()) {
            min = min.inf(p);
            max = max.sup(p);
        }
        if !min.x.is_finite() {
            (min, max) = (Point3::origin(), Point3::origin());
        }
        match ground {
            // Show the ground line with some room below it.
            Ground::Plane { point, .. } => {
                min.z = min.z.min(point.z);
            }
            // The top of the ball only: a ball many times the robot would shrink it to a dot.
            Ground::Ball { centre, radius } => min.z = min.z.min(centre.z + radius),
            Ground::Blocks(_) => min.z = min.z.min(0.0),
            Ground::Nothing => {}
        }
        let pad = (max - min).max() * 0.08 + 1e-6;
        Self {
            min: min - Vector3::repeat(pad),
            max: max + Vector3::repeat(pad),
        }
    }
}

impl Bounds {
    /// One box per frame for a camera that follows the robot: frame `i`'s box is centred on
    /// `centres[i]` (e.g. the thorax), and every box has the same size, the smallest that holds
    /// every frame's figure around its own centre (and the plane `ground` right under it), with
    /// the same margin as [`Bounds::around`]. The robot then keeps its place and size in the
    /// picture while the axes (the world) move under it.
    pub fn following(
        figures: &[&StickFigure],
        centres: &[Point3<f64>],
        ground: &Ground,
    ) -> Vec<Self> {
        let mut half = Vector3::zeros();
        for (f, c) in figures.iter().zip(centres) {
            let under = match ground {
                Ground::Plane { point, normal } if normal.z.abs() > 1e-9 => {
                    // The plane's point straight below (or above) the centre.
                    let z = point.z
                        - (normal.x * (c.x - point.x) + normal.y * (c.y - point.y)) / normal.z;
                    Some(Point3::new(c.x, c.y, z))
                }
                Ground::Ball { centre, radius } => Some(Point3::new(c.x, c.y, centre.z + radius)),
                Ground::Blocks(b) => Some(Point3::new(c.x, c.y, b.height_at(c.x, c.y))),
                Ground::Plane { .. } | Ground::Nothing => None,
            };
            for p in f.points().chain(under.as_ref()) {
                half = half.sup(&(p - c).abs());
            }
        }
        let pad = half.max() * 2.0 * 0.08 + 1e-6;
        let half = half + Vector3::repeat(pad);
        centres
            .iter()
            .map(|c| Self {
                min: c - half,
                max: c + half,
            })
            .collect()
    }
}

const FOOT_R: i32 = 5;

fn part_colour(p: Part) -> RGBColor {
    match p {
        Part::Thorax => THORAX,
        Part::LeftLeg => colour(0),
        Part::RightLeg => colour(1),
    }
}

type DrawResult<T> = Result<T, String>;

/// Draws the three views of `figure` side by side on `area`; `title` above them.
pub fn draw_views<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    figure: &StickFigure,
    ground: &Ground,
    bounds: &Bounds,
    title: &str,
) -> DrawResult<Vec<ViewLayout>> {
    register_font();
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let area = area.titled(title, ("sans-serif", 18)).map_err(|x| e(&x))?;
    let panels = area.split_evenly((1, 3));
    // One scale for all views: the largest that fits every view's extent into its plot area.
    let plot = plot_size(&panels[0])?;
    let ext = |v: View| {
        let (h0, v0) = v.project(&bounds.min);
        let (h1, v1) = v.project(&bounds.max);
        (
            (h1 - h0) * 1e3,
            (v1 - v0) * 1e3,
            (h0 + h1) * 5e2,
            (v0 + v1) * 5e2,
        )
    };
    let px_per_mm = View::ALL
        .iter()
        .map(|&v| {
            let (w, h, _, _) = ext(v);
            (f64::from(plot.0) / w).min(f64::from(plot.1) / h)
        })
        .fold(f64::INFINITY, f64::min);
    let mut layouts = Vec::new();
    for (panel, view) in panels.iter().zip(View::ALL) {
        let (_, _, hc, vc) = ext(view);
        let (hw, vh) = (
            f64::from(plot.0) / px_per_mm / 2.0,
            f64::from(plot.1) / px_per_mm / 2.0,
        );
        let (h_mm, v_mm) = ((hc - hw, hc + hw), (vc - vh, vc + vh));
        let mut chart = chart(panel, view, h_mm, v_mm)?;
        let (xs, ys) = chart.plotting_area().get_pixel_range();
        let layout = ViewLayout {
            view,
            pixels: (xs.start, ys.start, xs.end, ys.end),
            h_mm,
            v_mm,
        };
        let mm = |p: &Point3<f64>| {
            let (h, v) = view.project(p);
            (h * 1e3, v * 1e3)
        };
        draw_ground(&mut chart, view, ground, h_mm)?;
        for b in &figure.bones {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![mm(&b.from), mm(&b.to)],
                    part_colour(b.part).stroke_width(3),
                )))
                .map_err(|x| e(&x))?;
        }
        chart
            .draw_series(
                figure
                    .joints
                    .iter()
                    .map(|p| Circle::new(mm(p), 3, JOINT.filled())),
            )
            .map_err(|x| e(&x))?;
        for f in &figure.feet {
            let at = mm(&f.at);
            if f.stance {
                chart
                    .draw_series(std::iter::once(Circle::new(at, FOOT_R, FOOT.filled())))
                    .map_err(|x| e(&x))?;
            } else {
                chart
                    .draw_series([
                        Circle::new(at, FOOT_R, WHITE.filled()),
                        Circle::new(at, FOOT_R, FOOT.stroke_width(2)),
                    ])
                    .map_err(|x| e(&x))?;
            }
        }
        layouts.push(layout);
    }
    Ok(layouts)
}

/// The plot area's size in pixels of a chart on `panel` (every panel has the same size).
fn plot_size<DB: DrawingBackend>(panel: &DrawingArea<DB, Shift>) -> DrawResult<(u32, u32)> {
    let probe = ChartBuilder::on(panel)
        .margin(8)
        .caption(" ", ("sans-serif", 15))
        .x_label_area_size(34)
        .y_label_area_size(44)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)
        .map_err(|e| e.to_string())?;
    let (xs, ys) = probe.plotting_area().get_pixel_range();
    Ok(((xs.end - xs.start) as u32, (ys.end - ys.start) as u32))
}

fn chart<'a, DB: DrawingBackend>(
    panel: &'a DrawingArea<DB, Shift>,
    view: View,
    h: (f64, f64),
    v: (f64, f64),
) -> DrawResult<Chart<'a, DB>> {
    let mut chart = ChartBuilder::on(panel)
        .margin(8)
        .caption(view.title(), ("sans-serif", 15))
        .x_label_area_size(34)
        .y_label_area_size(44)
        .build_cartesian_2d(h.0..h.1, v.0..v.1)
        .map_err(|e| e.to_string())?;
    let (xd, yd) = view.axes();
    chart
        .configure_mesh()
        .x_desc(xd)
        .y_desc(yd)
        .x_labels(5)
        .y_labels(5)
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(235, 235, 235))
        .label_style(("sans-serif", 11))
        .axis_desc_style(("sans-serif", 12))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

fn draw_ground<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    view: View,
    ground: &Ground,
    h_mm: (f64, f64),
) -> DrawResult<()> {
    let style = GROUND.stroke_width(2);
    let line = |pts: Vec<(f64, f64)>| PathElement::new(pts, style);
    match (ground, view) {
        (Ground::Plane { point, normal }, View::Side | View::Front) => {
            let (ph, pv) = view.project(point);
            let (nh, nv) = match view {
                View::Side => (normal.x, normal.z),
                View::Top | View::Front => (normal.y, normal.z),
            };
            if nv.abs() < 1e-9 {
                return Ok(());
            }
            // n_h (h - p_h) + n_v (v - p_v) = 0 along the view's horizontal axis.
            let z = |h_mm: f64| (pv - nh / nv * (h_mm * 1e-3 - ph)) * 1e3;
            chart
                .draw_series(std::iter::once(line(vec![
                    (h_mm.0, z(h_mm.0)),
                    (h_mm.1, z(h_mm.1)),
                ])))
                .map_err(|e| e.to_string())?;
        }
        (Ground::Plane { .. }, View::Top) | (Ground::Nothing, _) => {}
        (Ground::Blocks(b), _) => super::blocks::draw_blocks(chart, view, b)?,
        (Ground::Ball { centre, radius }, _) => {
            let (ch, cv) = view.project(centre);
            let (x, y) = (chart.x_range(), chart.y_range());
            let inside = |p: &(f64, f64)| x.contains(&p.0) && y.contains(&p.1);
            // Only the arcs inside the plot: the rest of a big ball would be drawn on the margins.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for k in 0..=720 {
                let a = f64::from(k) / 720.0 * std::f64::consts::TAU;
                let p = ((ch + radius * a.cos()) * 1e3, (cv + radius * a.sin()) * 1e3);
                match (inside(&p), runs.last_mut()) {
                    (true, Some(run)) => run.push(p),
                    (false, Some(run)) if !run.is_empty() => runs.push(Vec::new()),
                    (false, _) | (true, None) => {}
                }
            }
            chart
                .draw_series(runs.into_iter().filter(|r| r.len() > 1).map(line))
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}

/// A legend strip naming every element of the drawing, drawn left to right on `area`.
pub fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> DrawResult<()> {
    register_font();
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    let (_, h) = area.dim_in_pixel();
    let y = h as i32 / 2;
    let mut x = 12;
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let item = |x: &mut i32, sym: &dyn Fn(i32) -> DrawResult<()>, text: &str| {
        sym(*x)?;
        area.draw(&Text::new(text.to_string(), (*x + 26, y - 8), font.clone()))
            .map_err(|x| e(&x))?;
        let (w, _) = area.estimate_text_size(text, &font).map_err(|x| e(&x))?;
        *x += 26 + w as i32 + 22;
        Ok::<(), String>(())
    };
    let seg = |c: RGBColor| {
        move |x: i32| {
            area.draw(&PathElement::new(
                vec![(x, y), (x + 20, y)],
                c.stroke_width(3),
            ))
            .map_err(|x| x.to_string())
        }
    };
    item(&mut x, &seg(THORAX), "thorax (first leg joints)")?;
    item(&mut x, &seg(colour(0)), "left legs")?;
    item(&mut x, &seg(colour(1)), "right legs")?;
    item(
        &mut x,
        &|x| {
            area.draw(&Circle::new((x + 10, y), 3, JOINT.filled()))
                .map_err(|x| x.to_string())
        },
        "joint",
    )?;
    item(
        &mut x,
        &|x| {
            area.draw(&Circle::new((x + 10, y), FOOT_R, FOOT.filled()))
                .map_err(|x| x.to_string())
        },
        "stance foot (on the ground)",
    )?;
    item(
        &mut x,
        &|x| {
            area.draw(&Circle::new((x + 10, y), FOOT_R, FOOT.stroke_width(2)))
                .map_err(|x| x.to_string())
        },
        "swing foot",
    )?;
    item(&mut x, &seg(GROUND), "ground")?;
    Ok(())
}
