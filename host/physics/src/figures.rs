//! What a walk did to the body, sampled once per bus cycle: distance, heading drift, thorax height
//! and tilt, slip per foot, and the joints that ran into their stall torque. These are the figures
//! a lab asks for before putting a gait on the robot; `Figures::verdict` names the joints when the
//! robot could not carry the gait.

use planner::model::Leg;

use crate::plant::Plant;

/// A foot carries weight above this normal force, N.
const LOADED_N: f64 = 1.0;
/// A servo counts as saturated at this fraction of its stall torque.
const SATURATED: f64 = 0.98;

/// Running figures of one robot since power-on (or the last [`Monitor::reset`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Figures {
    /// Simulated seconds sampled.
    pub seconds: f64,
    /// Thorax displacement since the start, world x (forward at the start) and y, m.
    pub forward_m: f64,
    pub lateral_m: f64,
    /// Change of heading (yaw) since the start, rad.
    pub heading_rad: f64,
    /// Thorax height at the start, its lowest and its last, m.
    pub height_start_m: f64,
    pub height_min_m: f64,
    pub height_end_m: f64,
    /// Largest tilt of the thorax (angle between its z axis and the world's), rad.
    pub tilt_max_rad: f64,
    /// Horizontal distance each foot moved while loaded (slip), m.
    pub slip_m: Vec<(Leg, f64)>,
    /// Per actuated joint: fraction of samples at the stall torque.
    pub saturated: Vec<(String, f64)>,
}

impl Figures {
    /// `None` when the robot carried itself; otherwise what went wrong, naming the saturated
    /// joints: it sagged (thorax more than `sag_m` below its start) or fell (tilted over 30
    /// degrees or lost half its height).
    pub fn verdict(&self, sag_m: f64) -> Option<String> {
        let fell =
            self.tilt_max_rad > 30f64.to_radians() || self.height_min_m < 0.5 * self.height_start_m;
        let sagged = self.height_start_m - self.height_min_m > sag_m;
        if !fell && !sagged {
            return None;
        }
        let mut joints: Vec<&(String, f64)> =
            self.saturated.iter().filter(|(_, f)| *f > 0.05).collect();
        joints.sort_by(|a, b| b.1.total_cmp(&a.1));
        let names: Vec<String> = joints
            .iter()
            .map(|(n, f)| format!("{n} ({:.0} % of the time at stall)", f * 100.0))
            .collect();
        Some(format!(
            "the robot {} (thorax {:.1} mm at the lowest, from {:.1} mm; tilt up to {:.1} deg); \
             servos at their stall torque: {}",
            if fell { "fell" } else { "sagged" },
            self.height_min_m * 1e3,
            self.height_start_m * 1e3,
            self.tilt_max_rad.to_degrees(),
            if names.is_empty() {
                "none".to_owned()
            } else {
                names.join(", ")
            }
        ))
    }
}

/// Samples a [`Plant`] into [`Figures`].
#[derive(Debug, Clone)]
pub struct Monitor {
    start: Option<([f64; 3], f64)>,
    samples: usize,
    saturated: Vec<usize>,
    feet: Vec<(Leg, Option<[f64; 3]>, f64)>,
    figures: Option<Figures>,
}

fn yaw(q: [f64; 4]) -> f64 {
    let [w, x, y, z] = q;
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

fn tilt(q: [f64; 4]) -> f64 {
    let [_, x, y, _] = q;
    // z axis of the body in the world: its z component is 1 - 2 (x^2 + y^2).
    (1.0 - 2.0 * (x * x + y * y)).clamp(-1.0, 1.0).acos()
}

impl Monitor {
    pub fn new() -> Self {
        Self {
            start: None,
            samples: 0,
            saturated: Vec::new(),
            feet: Vec::new(),
            figures: None,
        }
    }

    /// Starts afresh at the next sample.
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// Takes one sample of `plant`.
    pub fn sample(&mut self, plant: &Plant) {
        let (p, q) = plant.thorax_pose();
        let (start, yaw0) = *self.start.get_or_insert((p, yaw(q)));
        if self.saturated.len() != plant.joints().len() {
            self.saturated = vec![0; plant.joints().len()];
        }
        for (i, j) in plant.joints().iter().enumerate() {
            let (_, _, tau) = plant.joint_state(i);
            if tau.abs() >= SATURATED * j.stall {
                self.saturated[i] += 1;
            }
        }
        let forces = plant.foot_forces();
        let positions = plant.foot_positions();
        if self.feet.len() != positions.len() {
            self.feet = positions.iter().map(|&(leg, _)| (leg, None, 0.0)).collect();
        }
        for ((slot, (_, f)), (_, x)) in self.feet.iter_mut().zip(&forces).zip(&positions) {
            let loaded = f[2] > LOADED_N;
            if let (true, Some(prev)) = (loaded, slot.1) {
                slot.2 += ((x[0] - prev[0]).powi(2) + (x[1] - prev[1]).powi(2)).sqrt();
            }
            slot.1 = loaded.then_some(*x);
        }
        self.samples += 1;
        let f = self.figures.get_or_insert(Figures {
            seconds: 0.0,
            forward_m: 0.0,
            lateral_m: 0.0,
            heading_rad: 0.0,
            height_start_m: start[2],
            height_min_m: start[2],
            height_end_m: start[2],
            tilt_max_rad: 0.0,
            slip_m: Vec::new(),
            saturated: Vec::new(),
        });
        f.seconds = plant.time();
        f.forward_m = p[0] - start[0];
        f.lateral_m = p[1] - start[1];
        let dy = yaw(q) - yaw0;
        f.heading_rad = dy.sin().atan2(dy.cos());
        f.height_min_m = f.height_min_m.min(p[2]);
        f.height_end_m = p[2];
        f.tilt_max_rad = f.tilt_max_rad.max(tilt(q));
        f.slip_m = self.feet.iter().map(|&(leg, _, s)| (leg, s)).collect();
        let n = self.samples as f64;
        f.saturated = plant
            .joints()
            .iter()
            .zip(&self.saturated)
            .map(|(j, &c)| (j.name.clone(), c as f64 / n))
            .collect();
    }

    /// The figures so far (`None` before the first sample).
    pub fn figures(&self) -> Option<&Figures> {
        self.figures.as_ref()
    }
}

impl Default for Monitor {
    fn default() -> Self {
        Self::new()
    }
}
