//! The internal wrench across a gauge's cross-section in one solved slice, two ways: from the
//! distal free body (the main path) and from the segment's proximal joint (an independent check).
//!
//! The cut segment's own mass: spread uniformly along its axis as a slender rod of the segment's
//! length centred on its centre of mass, so a cut at fraction `s` leaves `(1 - s) m` distal, with
//! its centre of mass at `com + (s L / 2) a` and (an ESTIMATE of how the rotational inertia
//! splits, negligible at walking speeds) inertia `(1 - s) I_com`. The two parts add up to the
//! rigid body exactly; at `s = 0` the whole segment is distal and the section wrench is the
//! joint's, at `s = 1` only what hangs beyond the segment's distal end.
//!
//! Everything here is in the thorax frame of the slice, like the dynamics' outputs.

use nalgebra::{Matrix3, Vector3};

use super::StrainError;
use super::section::SectionWrench;
use crate::dynamics::SliceInput;
use crate::dynamics::motion::{BodyMotion, body_motions};
use crate::dynamics::wrench::required_wrenches;
use crate::model::{Gauge, Model};

/// A force and a moment, thorax frame.
pub type Wrench = (Vector3<f64>, Vector3<f64>);

/// The bodies' motion in a slice and what each needs from outside, as the dynamics computes them.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceBodies {
    pub motions: Vec<BodyMotion>,
    /// Per body `m (a - g)` and `I alpha + w x I w` (about its centre of mass).
    pub required: Vec<Wrench>,
    pub gravity: Vector3<f64>,
}

impl SliceBodies {
    /// The forward recursion and Newton-Euler of the inverse dynamics for one slice.
    pub fn of(model: &Model, input: &SliceInput) -> Self {
        let motions = body_motions(model, input);
        let required = required_wrenches(model, &motions, &input.gravity);
        Self {
            motions,
            required,
            gravity: input.gravity,
        }
    }
}

/// What a gauge's cut needs from the model, worked out once per gauge.
#[derive(Debug, Clone, PartialEq)]
pub struct Site {
    /// The segment (body index) and its proximal joint.
    pub segment: usize,
    pub joint: usize,
    /// Proximal joint to distal end, segment frame, m.
    pub span: Vector3<f64>,
    /// Position along the span, 0..=1.
    pub position: f64,
    /// Bodies strictly distal of the segment.
    pub distal_bodies: Vec<usize>,
    /// Feet (indices in `model.feet`) on the segment or distal of it.
    pub feet: Vec<usize>,
}

/// The gauge's section in a slice: centroid and the frame `(a, n, t)`, thorax frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionFrame {
    pub centroid: Vector3<f64>,
    pub axis: Vector3<f64>,
    pub normal: Vector3<f64>,
    pub side: Vector3<f64>,
}

impl Site {
    /// The cut of `gauge` in `model` (refused for a segment without a proximal joint or axis,
    /// which a model file's validation already rules out).
    pub fn of(model: &Model, gauge: &Gauge) -> Result<Self, StrainError> {
        let no_axis = || StrainError::NoAxis {
            gauge: gauge.name.clone(),
        };
        let joint = model.parent_joint(gauge.segment).ok_or_else(no_axis)?;
        let span = model
            .segment_span(gauge.segment)
            .filter(|s| s.norm() > 0.0)
            .ok_or_else(no_axis)?;
        let mut below = vec![false; model.bodies.len()];
        for j in &model.joints {
            below[j.child] = below[j.parent] || j.parent == gauge.segment;
        }
        let distal_bodies = (0..model.bodies.len()).filter(|&b| below[b]).collect();
        let feet = (0..model.feet.len())
            .filter(|&f| {
                let b = model.feet[f].body;
                b == gauge.segment || below[b]
            })
            .collect();
        Ok(Self {
            segment: gauge.segment,
            joint,
            span,
            position: gauge.position,
            distal_bodies,
            feet,
        })
    }

    /// The section's centroid and frame for the segment's motion `m`.
    pub fn frame(&self, gauge: &Gauge, m: &BodyMotion) -> SectionFrame {
        let axis = m.rotation * self.span.normalize();
        let normal = m.rotation * gauge.face.into_inner();
        SectionFrame {
            centroid: m.origin + m.rotation * (self.span * self.position),
            axis,
            normal,
            side: axis.cross(&normal),
        }
    }

    /// The cut segment's distal part: its required wrench `m (a - g)`, `I alpha + w x I w`
    /// (moment about its own centre of mass) and that centre of mass.
    fn distal_part(
        &self,
        model: &Model,
        m: &BodyMotion,
        gravity: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let body = &model.bodies[self.segment];
        let fraction = 1.0 - self.position;
        let local = body.com + self.span * (self.position / 2.0);
        let r = m.rotation * local;
        let accel = m.origin_acceleration + m.alpha.cross(&r) + m.omega.cross(&m.omega.cross(&r));
        let inertia: Matrix3<f64> = m.rotation * (body.inertia * fraction) * m.rotation.transpose();
        let force = body.mass * fraction * (accel - gravity);
        let moment = inertia * m.alpha + m.omega.cross(&(inertia * m.omega));
        (force, moment, m.origin + r)
    }
}

/// Main path: the distal free body (the distal part of the cut segment, every body beyond it and
/// the ground reaction forces on its feet). The proximal part must supply what that body needs,
/// `sum m (a - g)` and its moment, less the GRF; the section wrench (distal on proximal, about the
/// centroid) is the opposite.
pub fn distal_wrench(
    model: &Model,
    site: &Site,
    frame: &SectionFrame,
    bodies: &SliceBodies,
    grf: &[Vector3<f64>],
) -> Wrench {
    let (motions, required) = (&bodies.motions, &bodies.required);
    let p = frame.centroid;
    let (fd, md, cd) = site.distal_part(model, &motions[site.segment], &bodies.gravity);
    let mut force = fd;
    let mut moment = md + (cd - p).cross(&fd);
    for &b in &site.distal_bodies {
        let (f, m) = required[b];
        force += f;
        moment += m + (motions[b].com - p).cross(&f);
    }
    for &i in &site.feet {
        let foot = &model.feet[i];
        let mb = &motions[foot.body];
        let at = mb.origin + mb.rotation * foot.point;
        force -= grf[i];
        moment -= (at - p).cross(&grf[i]);
    }
    (-force, -moment)
}

/// Independent path: the proximal part of the cut segment as a free body, loaded by its proximal
/// joint's force and moment (parent on segment, about the joint origin, from the solution) and by
/// the section wrench; so the section wrench is the proximal part's required wrench (the whole
/// segment's minus the distal part's) less the joint's.
pub fn proximal_wrench(
    model: &Model,
    site: &Site,
    frame: &SectionFrame,
    bodies: &SliceBodies,
    joint_force: &[Vector3<f64>],
    joint_moment: &[Vector3<f64>],
) -> Wrench {
    let p = frame.centroid;
    let m = &bodies.motions[site.segment];
    let (fb, mb) = bodies.required[site.segment];
    let (fd, md, cd) = site.distal_part(model, m, &bodies.gravity);
    let (jf, jm) = (joint_force[site.joint], joint_moment[site.joint]);
    let force = fb - fd - jf;
    let moment = (mb + (m.com - p).cross(&fb))
        - (md + (cd - p).cross(&fd))
        - (jm + (m.origin - p).cross(&jf));
    (force, moment)
}

/// A thorax-frame wrench in the section frame `(a, n, t)`.
pub fn in_section_frame(frame: &SectionFrame, (f, m): &Wrench) -> SectionWrench {
    let to = |v: &Vector3<f64>| {
        Vector3::new(v.dot(&frame.axis), v.dot(&frame.normal), v.dot(&frame.side))
    };
    SectionWrench {
        force: to(f),
        moment: to(m),
    }
}
