//! The model file's `[[gauge]]` entries (docs/strain.md): their schema, reading them into
//! [`Gauge`]s with validation that names the file, the gauge and the field, and writing them back.

use nalgebra::{Unit, Vector3};
use serde::{Deserialize, Serialize};

use super::error::{ModelError, field};
use super::{Gauge, GaugeDirection, Leg, Material, Model, Section};

/// A gauge as written in a model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaugeEntry {
    /// e.g. `LF_troch_axial`.
    pub name: String,
    pub leg: Leg,
    /// Name of the body the gauge is bonded to.
    pub segment: String,
    /// 0 at the segment's proximal joint, 1 at its distal end.
    pub position_fraction: f64,
    /// Outward normal of the gauge's face in the segment frame; need not be unit length, and is
    /// projected perpendicular to the segment axis on load (it must be at least 30 deg off it).
    pub face: [f64; 3],
    /// `axial`, `transverse`, `+45` or `-45`.
    pub direction: GaugeDirection,
    /// e.g. `{ shape = "circular_tube", outer_diameter_m = 0.02, wall_m = 0.002 }`.
    pub section: Section,
    pub material: Material,
    #[serde(default)]
    pub source: String,
}

/// Smallest sine of the angle between a face normal and the segment axis (30 deg).
const MIN_FACE_SINE: f64 = 0.5;

/// The gauges of `model` (its bodies, joints and feet already read) from the file's entries.
pub(crate) fn gauges_from_entries(
    entries: &[GaugeEntry],
    model: &Model,
    file: &str,
) -> Result<Vec<Gauge>, ModelError> {
    let mut out: Vec<Gauge> = Vec::with_capacity(entries.len());
    for e in entries {
        let place = format!("gauge {}", e.name);
        if e.name.trim().is_empty() {
            return Err(field(file, "gauge list", "name", "empty gauge name"));
        }
        if out.iter().any(|g| g.name == e.name) {
            return Err(field(file, &place, "name", "defined twice"));
        }
        let segment = model
            .bodies
            .iter()
            .position(|b| b.name == e.segment)
            .ok_or_else(|| ModelError::Unknown {
                file: file.to_string(),
                place: place.clone(),
                what: "segment",
                name: e.segment.clone(),
            })?;
        match model.body_leg(segment) {
            None => {
                return Err(field(
                    file,
                    &place,
                    "segment",
                    format!("`{}` is not a leg segment", e.segment),
                ));
            }
            Some(leg) if leg != e.leg => {
                return Err(field(
                    file,
                    &place,
                    "segment",
                    format!(
                        "`{}` belongs to leg {}, not {}",
                        e.segment,
                        leg.name(),
                        e.leg.name()
                    ),
                ));
            }
            Some(_) => {}
        }
        let span = model
            .segment_span(segment)
            .filter(|s| s.norm() > 1e-12)
            .ok_or_else(|| {
                field(
                    file,
                    &place,
                    "segment",
                    format!(
                        "`{}` has no single distal joint or foot to define its axis",
                        e.segment
                    ),
                )
            })?;
        let s = e.position_fraction;
        if !(s.is_finite() && (0.0..=1.0).contains(&s)) {
            return Err(field(
                file,
                &place,
                "position_fraction",
                format!(
                    "{s} is beyond the segment (0 = proximal joint, 1 = distal end; `{}` is {:.4} m long)",
                    e.segment,
                    span.norm()
                ),
            ));
        }
        let face = Vector3::from(e.face);
        let axis = span.normalize();
        let across = face - axis * face.dot(&axis);
        if !(face.iter().all(|x| x.is_finite()) && face.norm() > 0.0) {
            return Err(field(
                file,
                &place,
                "face",
                "must be a finite non-zero vector",
            ));
        }
        if across.norm() < MIN_FACE_SINE * face.norm() {
            return Err(field(
                file,
                &place,
                "face",
                format!(
                    "is within 30 deg of the segment axis ({:.3}, {:.3}, {:.3}); a face normal points across the segment",
                    axis.x, axis.y, axis.z
                ),
            ));
        }
        check_section(&e.section, file, &place)?;
        check_material(&e.material, file, &place)?;
        out.push(Gauge {
            name: e.name.clone(),
            leg: e.leg,
            segment,
            position: s,
            face: Unit::new_normalize(across),
            direction: e.direction,
            section: e.section,
            material: e.material,
        });
    }
    Ok(out)
}

fn check_section(section: &Section, file: &str, place: &str) -> Result<(), ModelError> {
    match *section {
        Section::CircularTube {
            outer_diameter_m: d,
            wall_m: w,
        } => {
            if !(d.is_finite() && d > 0.0) {
                return Err(field(
                    file,
                    place,
                    "section.outer_diameter_m",
                    format!("{d} m gives a zero section: the diameter must be > 0"),
                ));
            }
            if !(w.is_finite() && w > 0.0 && w <= d / 2.0) {
                return Err(field(
                    file,
                    place,
                    "section.wall_m",
                    format!(
                        "{w} m is not a wall of a {d} m tube (0 < wall <= {} m; zero is no section)",
                        d / 2.0
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn check_material(m: &Material, file: &str, place: &str) -> Result<(), ModelError> {
    let e = m.youngs_modulus_pa;
    if !(e.is_finite() && e > 0.0) {
        return Err(field(
            file,
            place,
            "material.youngs_modulus_pa",
            format!("{e} is not a modulus > 0"),
        ));
    }
    let nu = m.poisson_ratio;
    if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(field(
            file,
            place,
            "material.poisson_ratio",
            format!("{nu} is outside -1 < nu < 0.5"),
        ));
    }
    Ok(())
}

impl GaugeEntry {
    /// The file form of a gauge of `model`.
    pub fn from_gauge(g: &Gauge, model: &Model, source: String) -> GaugeEntry {
        GaugeEntry {
            name: g.name.clone(),
            leg: g.leg,
            segment: model.bodies[g.segment].name.clone(),
            position_fraction: g.position,
            face: g.face.into_inner().into(),
            direction: g.direction,
            section: g.section,
            material: g.material,
            source,
        }
    }
}
