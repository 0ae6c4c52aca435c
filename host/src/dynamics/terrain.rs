//! Terrains as the dynamics sees them: the gravity vector and the contact normal at each foot,
//! both in the thorax frame.

use nalgebra::{Rotation3, Vector3};

/// m/s^2.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The ground under the organism.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Terrain {
    /// Level ground; normal +z.
    Flat,
    /// A plane rising ahead at `angle` rad (the thorax pitched nose-up with it): gravity is
    /// rotated by -angle about y in the thorax frame, the normal stays +z.
    Incline { angle: f64 },
    /// A sphere of `radius` m centred at `centre` (thorax frame); the normal at a foot points
    /// from the centre to the foot.
    Ball { centre: Vector3<f64>, radius: f64 },
}

impl Terrain {
    /// Gravity in the thorax frame.
    pub fn gravity(&self) -> Vector3<f64> {
        let g = Vector3::new(0.0, 0.0, -STANDARD_GRAVITY);
        match self {
            Terrain::Incline { angle } => {
                Rotation3::from_axis_angle(&Vector3::y_axis(), -angle) * g
            }
            _ => g,
        }
    }

    /// Unit contact normal at a foot position (thorax frame).
    pub fn normal_at(&self, foot: &Vector3<f64>) -> Vector3<f64> {
        match self {
            Terrain::Ball { centre, .. } => {
                let d = foot - centre;
                if d.norm() > 0.0 {
                    d.normalize()
                } else {
                    Vector3::z()
                }
            }
            _ => Vector3::z(),
        }
    }
}
