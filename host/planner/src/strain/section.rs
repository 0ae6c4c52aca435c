//! Classical beam theory at one gauge: a section wrench, in the gauge's section frame, turned into
//! the strain the gauge reads.
//!
//! Section frame `(a, n, t)`: `a` the segment axis (distal), `n` the outward normal of the
//! gauge's face, `t = a x n`. The wrench is the one the distal part exerts on the proximal part
//! across the cut, about the section's centroid (the stress resultant of the face whose outward
//! normal is `+a`): force `(N, V_n, V_t)`, moment `(T, M_n, M_t)`.
//!
//! At the gauge (the outer surface, distance `c` from the centroid along `n`, on the line `t = 0`)
//! the surface is free (`sigma_nn = 0`) and only two stresses act in its plane:
//!
//! - normal stress along the axis `sigma = N / A - M_t c / I` (from `M_t = -int n sigma dA`;
//!   `M_n` bends about `n` and its stress vanishes at `t = 0`),
//! - in-plane shear `tau = T c / J + V_t Q / (I b)` (torsion, and the transverse shear force
//!   parallel to the face with `Q` the first moment of the half section about the `n` axis and
//!   `b` the wall cut at the neutral axis; `V_n`'s shear vanishes at the free surface).
//!
//! Hooke's law in plane stress (`G = E / (2 (1 + nu))`): `eps_a = sigma / E`,
//! `eps_t = -nu sigma / E`, `gamma = tau / G`. A gauge at angle `theta` from `a` towards `t` reads
//! `eps = eps_a cos^2 + eps_t sin^2 + gamma sin cos`, so
//!
//! - axial: `eps_a`; transverse: `-nu eps_a`;
//! - +-45 deg: `(eps_a + eps_t) / 2 +- gamma / 2 = (1 - nu) sigma / (2 E) +- (1 + nu) tau / E`.

use nalgebra::Vector3;

use crate::model::{GaugeDirection, Material, Section};

/// A section wrench in the gauge's section frame `(a, n, t)`: the distal part on the proximal.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SectionWrench {
    /// `(N, V_n, V_t)`, N: axial force (tension positive), shear along the face normal, shear
    /// along `t`.
    pub force: Vector3<f64>,
    /// `(T, M_n, M_t)`, N m: torsion about the axis, bending about the face normal, bending
    /// about `t` (the one that strains the face).
    pub moment: Vector3<f64>,
}

/// The geometric properties of a section that beam theory needs at the gauge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionProperties {
    /// Area, m^2.
    pub area: f64,
    /// Second moment of area about `t` (and, the section being round, about `n`), m^4.
    pub second_moment: f64,
    /// Torsion constant, m^4.
    pub torsion_constant: f64,
    /// Distance from the centroid to the gauge's face, m.
    pub face_distance: f64,
    /// `Q / (I b)` for the transverse shear at the gauge, 1/m^2.
    pub shear_factor: f64,
}

impl SectionProperties {
    /// Closed forms of the section (its outer radius `R`, inner radius `r`):
    /// `A = pi (R^2 - r^2)`, `I = pi (R^4 - r^4) / 4`, `J = 2 I`, `c = R`, and at the neutral
    /// axis `Q = 2 (R^3 - r^3) / 3`, `b = 2 (R - r)` (so `4 V / 3 A` for a rod, `2 V / A` for a
    /// thin tube).
    pub fn of(section: &Section) -> Self {
        match *section {
            Section::CircularTube {
                outer_diameter_m,
                wall_m,
            } => {
                let r_out = outer_diameter_m / 2.0;
                let r_in = (r_out - wall_m).max(0.0);
                let pi = std::f64::consts::PI;
                let second_moment = pi * (r_out.powi(4) - r_in.powi(4)) / 4.0;
                let q = 2.0 * (r_out.powi(3) - r_in.powi(3)) / 3.0;
                Self {
                    area: pi * (r_out * r_out - r_in * r_in),
                    second_moment,
                    torsion_constant: 2.0 * second_moment,
                    face_distance: r_out,
                    shear_factor: q / (second_moment * 2.0 * (r_out - r_in)),
                }
            }
        }
    }

    /// Axial normal stress and in-plane shear stress at the gauge, Pa.
    pub fn stresses(&self, w: &SectionWrench) -> (f64, f64) {
        let c = self.face_distance;
        let sigma = w.force.x / self.area - w.moment.z * c / self.second_moment;
        let tau = w.moment.x * c / self.torsion_constant + w.force.z * self.shear_factor;
        (sigma, tau)
    }
}

/// The strain (dimensionless) a gauge of `direction` reads under the section wrench `w`.
pub fn gauge_strain(
    direction: GaugeDirection,
    section: &Section,
    material: &Material,
    w: &SectionWrench,
) -> f64 {
    let (sigma, tau) = SectionProperties::of(section).stresses(w);
    let (e, nu) = (material.youngs_modulus_pa, material.poisson_ratio);
    let membrane = (1.0 - nu) * sigma / (2.0 * e);
    let half_gamma = (1.0 + nu) * tau / e;
    match direction {
        GaugeDirection::Axial => sigma / e,
        GaugeDirection::Transverse => -nu * sigma / e,
        GaugeDirection::Plus45 => membrane + half_gamma,
        GaugeDirection::Minus45 => membrane - half_gamma,
    }
}
