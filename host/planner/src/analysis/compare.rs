//! Per-DoF comparison of two organisms walking the same footpaths.

use super::fit::regression_r2;
use super::resample_periodic;
use crate::model::{JointKind, Leg};

/// Angle and torque of one joint of one organism over a step cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct DofTrace {
    pub leg: Leg,
    pub kind: JointKind,
    /// Whether the joint moves (fixed joints are not DoF).
    pub mobile: bool,
    /// rad, per slice.
    pub angle: Vec<f64>,
    /// N m, per slice.
    pub torque: Vec<f64>,
}

/// One row of a comparison table.
#[derive(Debug, Clone, PartialEq)]
pub struct ComparisonRow {
    pub leg: Leg,
    /// DoF label, e.g. `CTr` or `ThC2+CTr` (the sum on the side that has both).
    pub dof: String,
    /// Which side was summed: `None`, `Some(0)` for A, `Some(1)` for B.
    pub summed_side: Option<usize>,
    pub r2_angle: Option<f64>,
    pub r2_torque: Option<f64>,
}

/// Joints that move the leg in the same plane; when one organism has several of them and the
/// other only the last, the sum is compared (paper section 3.1.1: ThC2 + CTr elevate the leg).
const SAME_PLANE: [(&[JointKind], JointKind); 1] =
    [(&[JointKind::ThC2, JointKind::CTr], JointKind::CTr)];

fn find(t: &[DofTrace], leg: Leg, kind: JointKind) -> Option<&DofTrace> {
    t.iter()
        .find(|d| d.leg == leg && d.kind == kind && d.mobile)
}

fn summed(t: &[DofTrace], leg: Leg, kinds: &[JointKind], n: usize) -> Option<(Vec<f64>, Vec<f64>)> {
    let parts: Vec<&DofTrace> = kinds
        .iter()
        .map(|k| find(t, leg, *k))
        .collect::<Option<_>>()?;
    let mut angle = vec![0.0; n];
    let mut torque = vec![0.0; n];
    for p in parts {
        for (acc, v) in angle.iter_mut().zip(resample_periodic(&p.angle, n)) {
            *acc += v;
        }
        for (acc, v) in torque.iter_mut().zip(resample_periodic(&p.torque, n)) {
            *acc += v;
        }
    }
    Some((angle, torque))
}

/// Rows for every DoF mobile in both `a` and `b` (per leg), plus summed-plane rows. Traces of
/// different lengths are resampled to the longer one.
pub fn compare(a: &[DofTrace], b: &[DofTrace]) -> Vec<ComparisonRow> {
    let n = a.iter().chain(b).map(|d| d.angle.len()).max().unwrap_or(0);
    let mut rows = Vec::new();
    for leg in Leg::ALL {
        for da in a.iter().filter(|d| d.leg == leg && d.mobile) {
            if let Some(db) = find(b, leg, da.kind) {
                let (aa, ab) = (
                    resample_periodic(&da.angle, n),
                    resample_periodic(&db.angle, n),
                );
                let (ta, tb) = (
                    resample_periodic(&da.torque, n),
                    resample_periodic(&db.torque, n),
                );
                rows.push(ComparisonRow {
                    leg,
                    dof: da.kind.name().to_string(),
                    summed_side: None,
                    r2_angle: regression_r2(&aa, &ab),
                    r2_torque: regression_r2(&ta, &tb),
                });
            }
        }
        for (kinds, single) in SAME_PLANE {
            for (side, (many, one)) in [(a, b), (b, a)].into_iter().enumerate() {
                let other_has_all = kinds.iter().all(|k| find(one, leg, *k).is_some());
                let Some(s) = find(one, leg, single) else {
                    continue;
                };
                if other_has_all {
                    continue;
                }
                if let Some((angle, torque)) = summed(many, leg, kinds, n) {
                    let (sa, st) = (
                        resample_periodic(&s.angle, n),
                        resample_periodic(&s.torque, n),
                    );
                    let label = kinds
                        .iter()
                        .map(|k| k.name().to_string())
                        .collect::<Vec<_>>()
                        .join("+");
                    let (r2_angle, r2_torque) =
                        (regression_r2(&angle, &sa), regression_r2(&torque, &st));
                    rows.push(ComparisonRow {
                        leg,
                        dof: label,
                        summed_side: Some(side),
                        r2_angle,
                        r2_torque,
                    });
                }
            }
        }
    }
    rows
}
