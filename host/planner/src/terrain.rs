//! Terrains the planner walks on, in the thorax frame (REP-103), and the gravity vector each gives;
//! the ground a user names ([`Ground`], parsed only there) and uneven ground ([`Blocks`]).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

mod blocks;
mod ground;
pub use blocks::{Blocks, Cell, FIELD_X_M, FIELD_Y_M, GAP_DEPTH_M, splitmix64};
pub use ground::{BallMount, GROUND_SYNTAX, Ground};

/// Standard gravity, m/s^2.
pub const G: f64 = 9.81;

/// The ground under the organism.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Terrain {
    /// Level ground; the thorax moves over it.
    Flat,
    /// A ball under a fixed thorax (the tethered-fly setup): the ball turns under the feet. Its
    /// centre lies `offset_m` below the body's centre of mass (in the resting posture).
    Ball { radius_m: f64, offset_m: f64 },
    /// A plane rising forward at `angle_rad`; the thorax stays parallel to it, so the kinematics
    /// equal the flat case and gravity tilts in the thorax frame.
    Incline { angle_rad: f64 },
}

/// A terrain description could not be understood (`syntax`: the forms it may take), or the
/// planner cannot plan for it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("terrain `{text}`: {problem}{}", if *.syntax { format!(" (expected {GROUND_SYNTAX})") } else { String::new() })]
pub struct TerrainError {
    pub text: String,
    pub problem: String,
    /// Whether the text was not understood (the message then lists the forms).
    pub syntax: bool,
}

impl Terrain {
    /// Gravity in the thorax frame, m/s^2.
    pub fn gravity(&self) -> Vector3<f64> {
        match self {
            Terrain::Incline { angle_rad } => {
                Vector3::new(-angle_rad.sin(), 0.0, -angle_rad.cos()) * G
            }
            Terrain::Flat | Terrain::Ball { .. } => Vector3::new(0.0, 0.0, -G),
        }
    }
}
