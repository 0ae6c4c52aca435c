//! Beam theory at one gauge against hand calculations: a cantilever with a tip load (M = F L,
//! sigma = M c / I, strain = sigma / E), pure torsion on the 45 deg gauges, a pull, and the
//! transverse shear of a solid rod (tau = 4 V / 3 A at the neutral axis).
//!
//! Section for all but the rod: tube of outer radius R = 10 mm, inner r = 8 mm, so by hand
//! I = pi (R^4 - r^4) / 4 = 4.636991e-9 m^4, J = 2 I, A = pi (R^2 - r^2) = 1.130973e-4 m^2;
//! E = 2.4 GPa, nu = 0.39, G = E / (2 (1 + nu)) = 0.863309 GPa.

use nalgebra::Vector3;
use planner::model::{GaugeDirection, Material, Section};
use planner::strain::{SectionWrench, gauge_strain};

const TUBE: Section = Section::CircularTube {
    outer_diameter_m: 0.02,
    wall_m: 0.002,
};
const ONYX: Material = Material {
    youngs_modulus_pa: 2.4e9,
    poisson_ratio: 0.39,
};

fn micro(direction: GaugeDirection, section: &Section, w: &SectionWrench) -> f64 {
    1e6 * gauge_strain(direction, section, &ONYX, w)
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-6 * want.abs().max(1.0),
        "{what}: {got} microstrain, by hand {want}"
    );
}

/// Cantilever along a = +x, gauge on the top face (n = +z, so t = a x n = -y), tip load P = 2 N
/// downwards L = 0.1 m beyond the section. The distal part pulls the proximal part's face
/// down (V_n = -P) and, about t, with M_t = -P L = -0.2 N m (hogging: the top is stretched).
/// By hand sigma = M c / I = 0.2 * 0.01 / 4.636991e-9 = 431314 Pa, strain = sigma / E
/// = 179.714 microstrain; the transverse gauge -nu times that = -70.089.
#[test]
fn cantilever_tip_load_stretches_the_top_face_by_m_c_over_e_i() {
    let w = SectionWrench {
        force: Vector3::new(0.0, -2.0, 0.0),
        moment: Vector3::new(0.0, 0.0, -0.2),
    };
    close(
        micro(GaugeDirection::Axial, &TUBE, &w),
        179.714_254,
        "axial",
    );
    close(
        micro(GaugeDirection::Transverse, &TUBE, &w),
        -70.088_559,
        "transverse",
    );
    // No torsion, no shear along the face: both 45 deg gauges read half the membrane strain,
    // (1 - nu) sigma / 2 E = 54.813.
    let half = (1.0 - 0.39) * 179.714_254 / 2.0;
    close(micro(GaugeDirection::Plus45, &TUBE, &w), half, "+45");
    close(micro(GaugeDirection::Minus45, &TUBE, &w), half, "-45");
    // The bottom face (n = -z: t = +y, M_t = +0.2) is compressed by as much.
    let bottom = SectionWrench {
        force: Vector3::new(0.0, 2.0, 0.0),
        moment: Vector3::new(0.0, 0.0, 0.2),
    };
    close(
        micro(GaugeDirection::Axial, &TUBE, &bottom),
        -179.714_254,
        "bottom",
    );
}

/// Torque T = 0.5 N m about the axis: tau = T R / J = 0.005 / 9.273982e-9 = 539142 Pa,
/// gamma = tau / G = 6.245070e-4; a gauge at +45 deg reads gamma / 2 = 312.254 microstrain,
/// at -45 deg the opposite; axial and transverse gauges read nothing.
#[test]
fn torsion_reads_half_the_shear_strain_on_the_45_degree_gauges() {
    let w = SectionWrench {
        force: Vector3::zeros(),
        moment: Vector3::new(0.5, 0.0, 0.0),
    };
    close(micro(GaugeDirection::Plus45, &TUBE, &w), 312.253_516, "+45");
    close(
        micro(GaugeDirection::Minus45, &TUBE, &w),
        -312.253_516,
        "-45",
    );
    close(micro(GaugeDirection::Axial, &TUBE, &w), 0.0, "axial");
    close(
        micro(GaugeDirection::Transverse, &TUBE, &w),
        0.0,
        "transverse",
    );
}

/// A 100 N pull: sigma = N / A = 884194 Pa, 368.414 microstrain axially; a 45 deg gauge reads
/// (1 - nu) / 2 of it = 112.366.
#[test]
fn a_pull_reads_n_over_e_a() {
    let w = SectionWrench {
        force: Vector3::new(100.0, 0.0, 0.0),
        moment: Vector3::zeros(),
    };
    close(
        micro(GaugeDirection::Axial, &TUBE, &w),
        368.414_220,
        "axial",
    );
    close(micro(GaugeDirection::Plus45, &TUBE, &w), 112.366_337, "+45");
    close(
        micro(GaugeDirection::Minus45, &TUBE, &w),
        112.366_337,
        "-45",
    );
}

/// A solid rod of radius 10 mm (wall = radius) under a 50 N shear force along t: at the
/// neutral axis, where the gauge on the face n sits, tau = 4 V / (3 A) = 212207 Pa; the +45
/// gauge reads gamma / 2 = (1 + nu) tau / E = 122.903 microstrain. A shear along the face
/// normal leaves the free surface unstressed.
#[test]
fn transverse_shear_of_a_rod_is_four_thirds_v_over_a_at_the_neutral_axis() {
    let rod = Section::CircularTube {
        outer_diameter_m: 0.02,
        wall_m: 0.01,
    };
    let along_face = SectionWrench {
        force: Vector3::new(0.0, 0.0, 50.0),
        moment: Vector3::zeros(),
    };
    close(
        micro(GaugeDirection::Plus45, &rod, &along_face),
        122.902_984,
        "+45",
    );
    let along_normal = SectionWrench {
        force: Vector3::new(0.0, 50.0, 0.0),
        moment: Vector3::zeros(),
    };
    close(
        micro(GaugeDirection::Plus45, &rod, &along_normal),
        0.0,
        "normal shear",
    );
}
