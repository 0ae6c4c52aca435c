//! Overlay plots of two plans' common DoF (angles, and torques normalised by each plan's peak), used
//! by `dbot compare` and the paper's comparison ([`crate::paper_comparison`]).

use std::path::Path;

use board::files::write_atomically;
use planner::analysis::{ComparisonRow, DofTrace};
use planner::model::Leg;
use report::legs::{Panel, Trace, plot_leg_panels};

use crate::error::Result;

/// How a plan directory is named in the plots: its last component (`out/walk` -> `walk`).
pub fn folder_name(dir: &Path) -> String {
    dir.file_name().map_or_else(
        || dir.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Angle (deg) overlays and torque overlays normalised by each plan's peak torque, A solid, B
/// dashed, each named by its folder.
pub fn overlay(
    ta: &[DofTrace],
    tb: &[DofTrace],
    rows: &[ComparisonRow],
    out: &Path,
    names: [&str; 2],
) -> Result<()> {
    let n = ta
        .iter()
        .chain(tb)
        .map(|d| d.angle.len())
        .max()
        .unwrap_or(1);
    let peak = |t: &[DofTrace]| {
        t.iter()
            .flat_map(|d| &d.torque)
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE)
    };
    let (pa, pb) = (peak(ta), peak(tb));
    let phase: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
    for (file, torque) in [("compare_angles.png", false), ("compare_torques.png", true)] {
        let mut panels = Vec::new();
        for leg in Leg::ALL {
            let mut traces = Vec::new();
            for (k, r) in rows
                .iter()
                .filter(|r| r.leg == leg && r.summed_side.is_none())
                .enumerate()
            {
                for (side, (t, p)) in [(ta, pa), (tb, pb)].into_iter().enumerate() {
                    if let Some(d) = t.iter().find(|d| d.leg == leg && d.kind.name() == r.dof) {
                        let v = if torque { &d.torque } else { &d.angle };
                        let v = planner::analysis::resample_periodic(v, n);
                        let values = v
                            .iter()
                            .map(|x| if torque { x / p } else { x.to_degrees() })
                            .collect();
                        let label = format!("{} {}", r.dof, names[side]);
                        traces.push(Trace {
                            label,
                            values,
                            dashed: side == 1,
                            colour: k,
                        });
                    }
                }
            }
            let what = if torque { "torque / peak" } else { "angle" };
            panels.push(Panel {
                leg,
                title: format!(
                    "{} {what}: {} solid, {} dashed",
                    leg.name(),
                    names[0],
                    names[1]
                ),
                traces,
                stance: vec![],
            });
        }
        let y = if torque {
            "torque / plan's peak |torque|"
        } else {
            "angle (deg)"
        };
        write_atomically(&out.join(file), |p| {
            Ok(plot_leg_panels(
                p,
                &panels,
                &phase,
                "phase of the step cycle",
                y,
            )?)
        })?;
    }
    Ok(())
}
