//! The synthetic gait: a 22-joint table built with the protocol's builder, and its expected goals
//! computed in f64 straight from the physics, independent of the firmware's fixed-point path.

use std::f64::consts::PI;
use std::vec::Vec;

use protocol::gait::{GaitTableBuilder, JointSpec, ServoModel, Sign};

/// Joints of Drosophibot II.
pub const JOINTS: usize = 22;
/// Stiffness of every joint's servo in the synthetic gait, N m/rad (the MX-28 of the original
/// solver's actuator file).
pub const STIFFNESS: f64 = 8.4;

/// The synthetic gait: joint j has servo ID j + 1, zero at 2048 (+-100 ticks), every other servo
/// mounted reversed; angle(s) = 0.4 sin(2 pi s / slices + 0.5 j) rad, torque = 0.3 cos(same) N m.
#[derive(Debug, Clone)]
pub struct SyntheticGait {
    pub slices: usize,
    pub period_s: f64,
    pub joints: Vec<JointSpec>,
}

impl SyntheticGait {
    pub fn new(slices: usize, period_s: f64) -> Self {
        let joints = (0..JOINTS)
            .map(|j| JointSpec {
                name: std::format!("J{j}"),
                servo_id: j as u8 + 1,
                // The chain's layout (dynamixel's one copy of the robot's map, tested against
                // drosophibot2.toml in host/board/tests/integration/servo_map.rs): MX-64 on the CTr joints.
                model: if dynamixel::sim::DROSOPHIBOT_CTR_IDS.contains(&(j as u8 + 1)) {
                    ServoModel::Mx64
                } else {
                    ServoModel::Mx28
                },
                sign: if j % 2 == 0 {
                    Sign::Positive
                } else {
                    Sign::Negative
                },
                zero_offset: (2048 + (j as i32 * 37 % 201) - 100) as u16,
                min_rad: -1.5,
                max_rad: 1.5,
                stiffness_nm_per_rad: STIFFNESS,
                leg: None,
            })
            .collect();
        Self {
            slices,
            period_s,
            joints,
        }
    }

    pub fn angle(&self, slice: usize, joint: usize) -> f64 {
        0.4 * (2.0 * PI * slice as f64 / self.slices as f64 + 0.5 * joint as f64).sin()
    }

    pub fn torque(&self, slice: usize, joint: usize) -> f64 {
        0.3 * (2.0 * PI * slice as f64 / self.slices as f64 + 0.5 * joint as f64).cos()
    }

    /// The table bytes, named "synthetic".
    pub fn build(&self) -> Vec<u8> {
        self.build_named("synthetic")
    }

    /// The table bytes with the gait name `name` in the header (tests that tell gaits apart).
    pub fn build_named(&self, name: &str) -> Vec<u8> {
        let mut b = GaitTableBuilder::new(name, self.period_s, 0.5, self.joints.clone());
        for s in 0..self.slices {
            let angles: Vec<f64> = (0..JOINTS).map(|j| self.angle(s, j)).collect();
            let torques: Vec<f64> = (0..JOINTS).map(|j| self.torque(s, j)).collect();
            // Tripod: LF, LH, RM in stance for the first half, the others for the second.
            let stance = if s < self.slices / 2 {
                0b010_101
            } else {
                0b101_010
            };
            b.slice(stance, &angles, &torques);
        }
        b.build().expect("the synthetic gait is valid")
    }

    /// Expected goal of `joint` at fractional slice position `pos` (0..slices), in ticks before
    /// rounding: zero + sign (angle + torque / k) 4096 / 2 pi, angle and torque linearly interpolated
    /// between the table's values, which are rounded to 1e-4 rad and 1 mN m.
    pub fn goal(&self, pos: f64, joint: usize, stiffness: f64) -> f64 {
        self.goal_of(
            pos,
            joint,
            stiffness,
            |s| stored_angle(self.angle(s, joint)),
            |s| stored_torque(self.torque(s, joint)),
        )
    }

    /// The same for a table of this gait's joints, slices and period whose stored samples of
    /// `joint` are `angle(slice)` rad and `torque(slice)` N m (a variant of the synthetic gait).
    pub fn goal_of(
        &self,
        pos: f64,
        joint: usize,
        stiffness: f64,
        angle: impl Fn(usize) -> f64,
        torque: impl Fn(usize) -> f64,
    ) -> f64 {
        let i = pos.floor() as usize % self.slices;
        let next = (i + 1) % self.slices;
        let f = pos - pos.floor();
        let a = angle(i) * (1.0 - f) + angle(next) * f;
        let t = torque(i) * (1.0 - f) + torque(next) * f;
        let spec = &self.joints[joint];
        let sign = match spec.sign {
            Sign::Positive => 1.0,
            Sign::Negative => -1.0,
        };
        let bias = if stiffness > 0.0 { t / stiffness } else { 0.0 };
        spec.zero_offset as f64 + sign * (a + bias) * 4096.0 / (2.0 * PI)
    }
}

/// An angle as a table stores it: rounded to 1e-4 rad.
pub fn stored_angle(rad: f64) -> f64 {
    (rad * 1e4).round() / 1e4
}

/// A torque as a table stores it: rounded to 1 mN m.
pub fn stored_torque(nm: f64) -> f64 {
    (nm * 1e3).round() / 1e3
}
