//! CSV writers of the plan directory: `joints.csv` (one row per slice and joint) and `feet.csv` (one
//! row per slice and leg), headers from [`super::columns`]. Extra columns (torques, ground reaction
//! forces) are appended after the standard ones.

use super::columns::{FEET_BASE, JOINTS_BASE};
use crate::plan::Plan;
use std::io::Write;

use crate::number::{SIGNIFICANT, plain};

fn num(x: f64) -> String {
    plain(x, SIGNIFICANT)
}

/// An extra column: `values[slice][i]`, `i` over joints (model order) for joints.csv or over
/// legs ([`Plan::legs`] order) for feet.csv.
#[derive(Debug, Clone, Copy)]
pub struct ExtraColumn<'a> {
    pub name: &'a str,
    pub values: &'a [Vec<f64>],
}

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(
        "extra column `{name}`: expected {slices} x {per_slice} values, slice {slice} has {got}"
    )]
    Shape {
        name: String,
        slices: usize,
        per_slice: usize,
        slice: usize,
        got: usize,
    },
    #[error("CSV: {0}")]
    Csv(#[from] csv::Error),
    #[error("I/O: {0}")]
    Io(#[from] std::io::Error),
    #[error("plot: {0}")]
    Plot(String),
}

fn check(extra: &[ExtraColumn], slices: usize, per_slice: usize) -> Result<(), ReportError> {
    for c in extra {
        let bad = if c.values.len() != slices {
            Some((c.values.len().min(slices), c.values.len()))
        } else {
            c.values
                .iter()
                .position(|v| v.len() != per_slice)
                .map(|s| (s, c.values[s].len()))
        };
        if let Some((slice, got)) = bad {
            return Err(ReportError::Shape {
                name: c.name.to_string(),
                slices,
                per_slice,
                slice,
                got,
            });
        }
    }
    Ok(())
}

/// `slice,time_s,leg,joint,angle_rad,velocity_rad_s,accel_rad_s2,stance[,extra...]`, every model
/// joint (fixed ones too) for every slice; `stance` is 1 while the joint's leg is in stance.
pub fn write_joints_csv<W: Write>(
    w: W,
    plan: &Plan,
    extra: &[ExtraColumn],
) -> Result<(), ReportError> {
    let model = &plan.model;
    check(extra, plan.slices(), model.joints.len())?;
    let mut out = csv::Writer::from_writer(w);
    let mut header: Vec<&str> = JOINTS_BASE.to_vec();
    header.extend(extra.iter().map(|c| c.name));
    out.write_record(&header)?;
    for s in 0..plan.slices() {
        for (j, joint) in model.joints.iter().enumerate() {
            let li = plan.legs.iter().position(|l| *l == joint.leg);
            let stance = li.is_some_and(|li| plan.stance[s][li]);
            let mut rec = vec![
                s.to_string(),
                num(plan.time(s)),
                joint.leg.name().to_string(),
                joint.kind.name().to_string(),
                num(plan.q[s][j]),
                num(plan.qd[s][j]),
                num(plan.qdd[s][j]),
                u8::from(stance).to_string(),
            ];
            rec.extend(extra.iter().map(|c| num(c.values[s][j])));
            out.write_record(&rec)?;
        }
    }
    out.flush()?;
    Ok(())
}

/// `slice,time_s,leg,x_m,y_m,z_m,stance[,extra...]`: foot positions in the thorax frame (REP-103).
pub fn write_feet_csv<W: Write>(
    w: W,
    plan: &Plan,
    extra: &[ExtraColumn],
) -> Result<(), ReportError> {
    check(extra, plan.slices(), plan.legs.len())?;
    let mut out = csv::Writer::from_writer(w);
    let mut header: Vec<&str> = FEET_BASE.to_vec();
    header.extend(extra.iter().map(|c| c.name));
    out.write_record(&header)?;
    for s in 0..plan.slices() {
        for (li, leg) in plan.legs.iter().enumerate() {
            let p = plan.feet[s][li];
            let mut rec = vec![
                s.to_string(),
                num(plan.time(s)),
                leg.name().to_string(),
                num(p.x),
                num(p.y),
                num(p.z),
                u8::from(plan.stance[s][li]).to_string(),
            ];
            rec.extend(extra.iter().map(|c| num(c.values[s][li])));
            out.write_record(&rec)?;
        }
    }
    out.flush()?;
    Ok(())
}
