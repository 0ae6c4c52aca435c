//! One view of the robot (top, side, front): its projection, title and axes, the chart every
//! view is drawn on, and the drawing's colours; shared by the views (`views`) and what is drawn
//! into them (`blocks`).

use nalgebra::Point3;
use plotters::prelude::*;

/// A direction to look at the robot from (REP-103 frame: x forward, y left, z up).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// From above: x to the right, y (left) up the page.
    Top,
    /// From the robot's right: x to the right, z up.
    Side,
    /// From the front: y (the robot's left) to the right, z up.
    Front,
}

impl View {
    pub const ALL: [View; 3] = [View::Top, View::Side, View::Front];

    /// Horizontal and vertical coordinate of `p` in this view, m.
    pub fn project(self, p: &Point3<f64>) -> (f64, f64) {
        match self {
            View::Top => (p.x, p.y),
            View::Side => (p.x, p.z),
            View::Front => (p.y, p.z),
        }
    }

    pub(super) fn title(self) -> &'static str {
        match self {
            View::Top => "top (from above)",
            View::Side => "side (from the right)",
            View::Front => "front",
        }
    }

    pub(super) fn axes(self) -> (&'static str, &'static str) {
        match self {
            View::Top => ("x forward (mm)", "y left (mm)"),
            View::Side => ("x forward (mm)", "z up (mm)"),
            View::Front => ("y left (mm)", "z up (mm)"),
        }
    }
}

pub(super) type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

pub(super) const THORAX: RGBColor = RGBColor(0, 0, 0);
pub(super) const GROUND: RGBColor = RGBColor(140, 110, 70);
/// Stance feet are filled with this; swing feet are white rings of it.
pub(super) const FOOT: RGBColor = RGBColor(214, 39, 40);
pub(super) const JOINT: RGBColor = RGBColor(90, 90, 90);
