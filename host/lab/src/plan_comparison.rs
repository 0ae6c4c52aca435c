//! Comparing plans: per common DoF of two plan directories (or trial folders, measured angles and
//! load torques averaged per slice: `trial_traces`) the R^2 of a linear regression of
//! the angles and of the torques (`planner::analysis::compare`, tables S2 to S8 of the paper) with
//! `compare.csv` and the overlay plots, and a speed sweep of one model over swing durations
//! (`sweep.csv`). `dbot compare` prints what these return.

use std::collections::BTreeMap;
use std::path::Path;

use board::files::write_bytes_atomically;
use planner::analysis::{
    ComparisonRow, DofTrace, SweepPoint, SweepRegime, classify_sweep, compare,
};
use planner::model::{JointKind, Leg, Model};
use planner::plan_dir;

use crate::bail;
use crate::error::{Context, Result};
use crate::overlay::{folder_name, overlay};

/// DoF traces of a plan directory (torques required): one per model joint, keyed by leg and kind.
pub fn read_traces(dir: &Path) -> Result<Vec<DofTrace>> {
    let plan = plan_dir::read(dir)?;
    let torque = plan.torques("the comparison")?;
    let mut map: BTreeMap<(Leg, JointKind), (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for (angles, torques) in plan.angle.iter().zip(torque) {
        for (joint, (a, t)) in plan.model.joints.iter().zip(angles.iter().zip(torques)) {
            let e = map.entry((joint.leg, joint.kind)).or_default();
            e.0.push(*a);
            e.1.push(*t);
        }
    }
    Ok(map
        .into_iter()
        .map(|((leg, kind), (angle, torque))| {
            let (lo, hi) = angle
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| {
                    (l.min(*a), h.max(*a))
                });
            DofTrace {
                leg,
                kind,
                mobile: hi - lo > 1e-9,
                angle,
                torque,
            }
        })
        .collect())
}

/// The DoF traces of a plan directory or, when it holds trial.json, of a trial folder.
pub fn traces_of(dir: &Path) -> Result<Vec<DofTrace>> {
    if crate::trial_traces::is_trial(dir) {
        crate::trial_traces::trial_traces(dir)
    } else {
        read_traces(dir)
    }
}

/// An R^2 as written: three decimals, or `-` where there is none.
pub fn r2_cell(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

/// Which plan a summed DoF is summed in: `A`, `B` or empty.
pub fn summed_in(r: &ComparisonRow) -> &'static str {
    match r.summed_side {
        Some(0) => "A",
        Some(_) => "B",
        None => "",
    }
}

/// The rows as the markdown table `dbot compare` prints.
pub fn table(rows: &[ComparisonRow]) -> String {
    crate::markdown::table(
        &["leg", "DoF", "R^2 angle", "R^2 torque"],
        rows.iter().map(|r| {
            let summed = summed_in(r);
            let label = if summed.is_empty() {
                r.dof.clone()
            } else {
                format!("{} (sum in {summed})", r.dof)
            };
            vec![
                r.leg.name().to_owned(),
                label,
                r2_cell(r.r2_angle),
                r2_cell(r.r2_torque),
            ]
        }),
    )
}

/// Compares `a` and `b` (plan directories or trial folders) DoF by DoF; writes `compare.csv`,
/// `compare_angles.png` and `compare_torques.png` into `out` and returns the rows.
pub fn compare_dirs(a: &Path, b: &Path, out: &Path) -> Result<Vec<ComparisonRow>> {
    let (ta, tb) = (traces_of(a)?, traces_of(b)?);
    let rows = compare(&ta, &tb);
    if rows.is_empty() {
        bail!("{} and {} have no DoF in common", a.display(), b.display());
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(["leg", "dof", "summed_in", "r2_angle", "r2_torque"])?;
    for r in &rows {
        w.write_record([
            r.leg.name(),
            &r.dof,
            summed_in(r),
            &r2_cell(r.r2_angle),
            &r2_cell(r.r2_torque),
        ])?;
    }
    let bytes = w.into_inner().context("building compare.csv")?;
    write_bytes_atomically(&out.join("compare.csv"), &bytes)?;
    overlay(&ta, &tb, &rows, out, [&folder_name(a), &folder_name(b)])?;
    Ok(rows)
}

/// A speed sweep: `model` planned at table 1 with each swing duration of `swings` (calling
/// `on_point` after each); writes `sweep.csv` into `out` and returns the points and the regime
/// they show.
pub fn sweep(
    model: &Model,
    swings: &[f64],
    out: &Path,
    mut on_point: impl FnMut(),
) -> Result<(Vec<SweepPoint>, Option<SweepRegime>)> {
    let mut points = Vec::new();
    for &sw in swings {
        if !(sw > 0.0 && sw.is_finite()) {
            bail!("swing {sw}: swing durations must be positive seconds");
        }
        let mut p = planner::gait::StepParams::table1(&model.name);
        p.swing_s = sw;
        points.push(planner::analysis::sweep_point(model, &p)?);
        on_point();
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "period_s",
        "peak_torque_nm",
        "peak_inertial_torque_nm",
        "inertial_share",
    ])?;
    for p in &points {
        w.write_record(
            [
                p.period,
                p.peak_torque,
                p.peak_inertial_torque,
                inertial_share(p),
            ]
            .map(|v| planner::number::plain(v, 7)),
        )?;
    }
    let bytes = w.into_inner().context("building sweep.csv")?;
    write_bytes_atomically(&out.join("sweep.csv"), &bytes)?;
    let regime = classify_sweep(&points);
    Ok((points, regime))
}

/// The inertial part's share of a sweep point's peak torque.
pub fn inertial_share(p: &SweepPoint) -> f64 {
    p.peak_inertial_torque / p.peak_torque
}

/// The speed sweep as a Markdown table, and the regime its points show, as `dbot compare --sweep`
/// prints them.
pub fn sweep_table(points: &[SweepPoint], regime: Option<&SweepRegime>) -> String {
    let mut s = crate::markdown::table(
        &[
            "period (s)",
            "peak torque (N m)",
            "inertial part (N m)",
            "share",
        ],
        points.iter().map(|p| {
            vec![
                format!("{:.3}", p.period),
                format!("{:.4e}", p.peak_torque),
                format!("{:.4e}", p.peak_inertial_torque),
                format!("{:.3}", inertial_share(p)),
            ]
        }),
    );
    if let Some(r) = regime {
        s.push_str(&format!(
            "inertial torque ~ T^{:.2} (-2 for pure inertia); quasi-static where the inertial share is below ~0.1\n",
            r.inertial_exponent
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweep_table_gives_each_points_share_and_the_regime() {
        // By hand: 0.5 N m of a 2 N m peak is a share of 0.25; at twice the period a quarter of
        // the inertial torque (T^-2) is 0.125 N m of 1.5 N m, 0.083.
        let points = [
            SweepPoint {
                period: 1.0,
                peak_torque: 2.0,
                peak_inertial_torque: 0.5,
            },
            SweepPoint {
                period: 2.0,
                peak_torque: 1.5,
                peak_inertial_torque: 0.125,
            },
        ];
        let regime = classify_sweep(&points).unwrap();
        assert!((regime.inertial_exponent + 2.0).abs() < 1e-12);
        let t = sweep_table(&points, Some(&regime));
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[2], "| 1.000 | 2.0000e0 | 5.0000e-1 | 0.250 |");
        assert_eq!(lines[3], "| 2.000 | 1.5000e0 | 1.2500e-1 | 0.083 |");
        assert!(lines[4].starts_with("inertial torque ~ T^-2.00 (-2 for pure inertia)"));
        assert_eq!(sweep_table(&points, None).lines().count(), 4);
    }
}
