//! Strain gauges bonded to leg segments (the robot's campaniform-sensilla analogues): where each
//! sits, which way it reads, and the section and material that turn a section load into strain.
//! Read from the model file's `[[gauge]]` entries by [`super::gauge_file`]; the strain itself is
//! computed by [`crate::strain`].
//!
//! Geometry: a segment's axis runs from its proximal joint (the body frame's origin) to its distal
//! end (the origin of its one distal joint, or its foot point); a gauge sits at a fraction of that
//! length, on the face whose outward normal is `face` (perpendicular to the axis). The gauge's
//! section frame is `(a, n, t)`: `a` the axis (distal), `n` the face normal, `t = a x n`; a +45 deg
//! gauge is turned from `a` towards `t` (counter-clockwise seen from outside the face).

use nalgebra::{Unit, Vector3};
use serde::{Deserialize, Serialize};

use super::{Leg, Model};

/// Which way a gauge's grid runs on its face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum GaugeDirection {
    /// Along the segment axis: axial force and bending in the plane of the face normal.
    #[serde(rename = "axial")]
    Axial,
    /// Across the axis in the face: the Poisson contraction of the axial strain.
    #[serde(rename = "transverse")]
    Transverse,
    /// 45 deg from the axis towards `t = a x n`: torsion and in-face shear plus half the
    /// membrane strain.
    #[serde(rename = "+45")]
    Plus45,
    /// 45 deg from the axis away from `t`.
    #[serde(rename = "-45")]
    Minus45,
}

impl GaugeDirection {
    /// The name used in the model file and in strain.csv's `kind` column.
    pub fn name(self) -> &'static str {
        match self {
            GaugeDirection::Axial => "axial",
            GaugeDirection::Transverse => "transverse",
            GaugeDirection::Plus45 => "+45",
            GaugeDirection::Minus45 => "-45",
        }
    }
}

/// The cross-section of the segment at a gauge, for beam theory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Section {
    /// A circular tube (a solid rod when `wall_m` is half the diameter): the one section whose
    /// torsion, bending and shear stresses at the face all have closed forms to check by hand.
    CircularTube {
        /// Outer diameter, m; the gauge sits on the outer surface.
        outer_diameter_m: f64,
        /// Wall thickness, m (0 < wall <= outer diameter / 2).
        wall_m: f64,
    },
}

/// Linear-elastic, isotropic material of the segment at the gauge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio (-1 < nu < 0.5).
    pub poisson_ratio: f64,
}

/// One strain gauge of a model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gauge {
    /// e.g. `LF_troch_axial`; the column name in recordings and strain.csv.
    pub name: String,
    pub leg: Leg,
    /// Index in [`Model::bodies`] of the segment the gauge is bonded to.
    pub segment: usize,
    /// Position along the segment axis: 0 at the proximal joint, 1 at the distal end.
    pub position: f64,
    /// Outward normal of the face the gauge is bonded to, in the segment's frame, perpendicular
    /// to the segment axis.
    pub face: Unit<Vector3<f64>>,
    pub direction: GaugeDirection,
    pub section: Section,
    pub material: Material,
}

impl Model {
    /// The vector from `body`'s proximal joint to its distal end, in its own frame: the origin
    /// of its one distal joint, else its foot point. `None` for a body with no distal end or
    /// with more than one distal joint (the thorax).
    pub fn segment_span(&self, body: usize) -> Option<Vector3<f64>> {
        let mut distal = self.joints.iter().filter(|j| j.parent == body);
        match (distal.next(), distal.next()) {
            (Some(j), None) => Some(j.origin.translation.vector),
            (Some(_), Some(_)) => None,
            (None, _) => self.feet.iter().find(|f| f.body == body).map(|f| f.point),
        }
    }

    /// The leg a body belongs to (that of its proximal joint); `None` for the thorax.
    pub fn body_leg(&self, body: usize) -> Option<Leg> {
        self.parent_joint(body).map(|j| self.joints[j].leg)
    }

    /// Index of a gauge by name.
    pub fn gauge_index(&self, name: &str) -> Option<usize> {
        self.gauges.iter().position(|g| g.name == name)
    }
}
