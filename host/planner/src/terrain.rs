//! Terrains the planner walks on, in the thorax frame (REP-103), and the gravity vector each gives.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

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

/// A terrain description could not be understood.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("terrain `{text}`: {problem} (expected flat, ball[:RADIUS_M[:OFFSET_M]] or incline:DEG)")]
pub struct TerrainError {
    pub text: String,
    pub problem: String,
}

impl Terrain {
    /// Parses `flat`, `ball`, `ball:R`, `ball:R:OFFSET` (metres) or `incline:DEG`. A bare ball gets
    /// `default_radius` and `default_offset`.
    pub fn parse(
        text: &str,
        default_radius: f64,
        default_offset: f64,
    ) -> Result<Terrain, TerrainError> {
        let err = |p: &str| TerrainError {
            text: text.to_string(),
            problem: p.to_string(),
        };
        let mut parts = text.split(':');
        let num = |s: Option<&str>, what: &str| -> Result<Option<f64>, TerrainError> {
            match s {
                None => Ok(None),
                Some(s) => s
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .map(Some)
                    .ok_or_else(|| err(&format!("{what} `{s}` is not a number"))),
            }
        };
        let t = match parts.next().unwrap_or("").trim() {
            "flat" => Terrain::Flat,
            "ball" => {
                let r = num(parts.next(), "radius")?.unwrap_or(default_radius);
                let off = num(parts.next(), "offset")?.unwrap_or(default_offset);
                if r <= 0.0 {
                    return Err(err("ball radius must be > 0"));
                }
                Terrain::Ball {
                    radius_m: r,
                    offset_m: off,
                }
            }
            "incline" => {
                let deg = num(parts.next(), "angle")?
                    .ok_or_else(|| err("incline needs an angle in degrees"))?;
                if deg.abs() >= 90.0 {
                    return Err(err("incline angle must be within (-90, 90) degrees"));
                }
                Terrain::Incline {
                    angle_rad: deg.to_radians(),
                }
            }
            other => return Err(err(&format!("unknown terrain `{other}`"))),
        };
        if parts.next().is_some() {
            return Err(err("too many `:` fields"));
        }
        Ok(t)
    }

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
