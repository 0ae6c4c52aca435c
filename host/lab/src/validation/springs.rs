//! docs/validation.md's parallel-spring blocks: the robot's spring stiffness swept on flat ground
//! (table S4 with springs) and on the ball (table S6) with the fly at the paper's 3.8e-8 N m/rad,
//! where the paper's counts fall in the sweep, a plot of each DoF's R^2 against the stiffness,
//! and both organisms with the newly-dead-fly equilibrium proxy instead of the resting posture.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Context, Result};
use planner::analysis::paper::{self, Claim, Quantity, TABLES, TRIPOD};
use planner::analysis::{ComparisonRow, compare};
use planner::model::{EquilibriumSource, JointKind, Leg, SpringSpec};
use report::legs::{Panel, Trace, plot_leg_panels};

use crate::paper_comparison::{Run, mean_grf, our_counts, run_from, spring_share};

/// Robot parallel stiffnesses of the sweep, N m/rad (the paper's is 1).
const STIFFNESS: [f64; 5] = [1.0, 2.0, 3.0, 5.0, 10.0];

/// The generated blocks and the plot.
#[derive(Debug)]
pub struct SpringBlocks {
    /// Table S4 with springs (flat) against the robot's stiffness.
    pub flat: String,
    /// Table S6 (ball) against the robot's stiffness.
    pub ball: String,
    /// Tables S4 springs and S6 with the dead-fly equilibrium proxy.
    pub dead_fly: String,
    /// PNG: R^2 of each tripod DoF's torque against the robot's stiffness, flat and ball.
    pub plot: Vec<u8>,
}

fn claims(id: &str) -> Result<&'static [Claim]> {
    Ok(TABLES
        .iter()
        .find(|t| t.id == id)
        .with_context(|| format!("table {id}"))?
        .claims)
}

fn paper_counts(claims: &[Claim]) -> Vec<String> {
    claims
        .iter()
        .map(|c| format!("{} of {} > {}", c.count, c.of, c.above))
        .collect()
}

fn organism(
    model: &str,
    terrain: &str,
    spring: SpringSpec,
    from: EquilibriumSource,
) -> Result<Run> {
    let swing = if model == "scale-drosophila" {
        paper::FLY_SWING_S
    } else {
        paper::ROBOT_SWING_S
    };
    run_from(model, swing, terrain, spring, from, SLICES)
}

/// Slices per step (as the comparison block's).
const SLICES: usize = 50;

/// Every spring block; the plot is written to `plots_dir` and read back.
pub fn spring_blocks(plots_dir: &Path) -> Result<SpringBlocks> {
    let rest = EquilibriumSource::RestingPosture;
    let mut sweeps = Vec::new();
    let mut blocks = Vec::new();
    for (terrain, id) in [("flat", "S4 springs"), ("ball", "S6")] {
        let fly = organism("scale-drosophila", terrain, SpringSpec::Paper, rest)?;
        let claims = claims(id)?;
        let mut md = format!(
            "| robot stiffness (N m/rad) | robot: peak spring torque / peak axis moment | fly: the same | {id}, ours | paper |\n|---|---|---|---|---|\n"
        );
        let mut counts = Vec::new();
        let mut rows = Vec::new();
        for k in STIFFNESS {
            let robot = organism("drosophibot2", terrain, SpringSpec::Stiffness(k), rest)?;
            let r = compare(&robot.traces, &fly.traces);
            let r2 = paper::r2_of(&r, &TRIPOD, Quantity::Torque);
            writeln!(
                md,
                "| {k} | {:.2} | {:.2} | {} | {} |",
                spring_share(&robot),
                spring_share(&fly),
                our_counts(&r2, claims).join(", "),
                paper_counts(claims).join(", ")
            )?;
            counts.push(
                claims
                    .iter()
                    .map(|c| paper::count_above(&r2, c.above))
                    .collect::<Vec<_>>(),
            );
            rows.push(r);
        }
        writeln!(md, "\n{}", where_paper_falls(id, claims, &counts))?;
        blocks.push(md);
        sweeps.push(rows);
    }
    let plot = plot_sweep(plots_dir, &sweeps[0], &sweeps[1])?;
    let ball = blocks.pop().unwrap_or_default();
    let flat = blocks.pop().unwrap_or_default();
    Ok(SpringBlocks {
        flat,
        ball,
        dead_fly: dead_fly()?,
        plot,
    })
}

/// Where each of the paper's counts lies among ours over [`STIFFNESS`]; `counts[k][c]` is our
/// count for claim c at stiffness k.
fn where_paper_falls(id: &str, claims: &[Claim], counts: &[Vec<usize>]) -> String {
    let parts: Vec<String> = claims
        .iter()
        .enumerate()
        .map(|(c, claim)| {
            let ours: Vec<usize> = counts.iter().map(|k| k[c]).collect();
            let what = format!(
                "{id}, the paper's {} of {} > {},",
                claim.count, claim.of, claim.above
            );
            let at: Vec<String> = STIFFNESS
                .iter()
                .zip(&ours)
                .filter(|&(_, &n)| n == claim.count)
                .map(|(k, _)| k.to_string())
                .collect();
            if !at.is_empty() {
                return format!("{what} is matched at {} N m/rad", at.join(" and "));
            }
            let between = (1..ours.len()).find(|&i| {
                let (a, b) = (ours[i - 1], ours[i]);
                a.min(b) < claim.count && claim.count < a.max(b)
            });
            match between {
                Some(i) => format!(
                    "{what} lies between {} N m/rad ({}) and {} N m/rad ({})",
                    STIFFNESS[i - 1],
                    ours[i - 1],
                    STIFFNESS[i],
                    ours[i]
                ),
                None if ours.iter().all(|&n| n < claim.count) => format!(
                    "{what} is above every count of the sweep (at most {})",
                    ours.iter().max().copied().unwrap_or(0)
                ),
                None => format!(
                    "{what} is below every count of the sweep (at least {})",
                    ours.iter().min().copied().unwrap_or(0)
                ),
            }
        })
        .collect();
    format!("Where the paper's count falls: {}.", parts.join("; "))
}

/// R^2 of each tripod DoF's torque (robot vs fly) against log10 of the robot's stiffness: flat
/// solid, ball dashed, one panel per tripod leg.
fn plot_sweep(
    dir: &Path,
    flat: &[Vec<ComparisonRow>],
    ball: &[Vec<ComparisonRow>],
) -> Result<Vec<u8>> {
    let x: Vec<f64> = STIFFNESS.iter().map(|k| k.log10()).collect();
    let mut panels = Vec::new();
    for leg in TRIPOD {
        let mut traces = Vec::new();
        let dofs: Vec<String> = flat[0]
            .iter()
            .filter(|r| r.leg == leg && r.summed_side.is_none())
            .map(|r| r.dof.clone())
            .collect();
        for (colour, dof) in dofs.iter().enumerate() {
            for (terrain, sweep, dashed) in [("flat", flat, false), ("ball", ball, true)] {
                let values = sweep
                    .iter()
                    .map(|rows| {
                        rows.iter()
                            .find(|r| r.leg == leg && &r.dof == dof && r.summed_side.is_none())
                            .and_then(|r| r.r2_torque)
                            .unwrap_or(f64::NAN)
                    })
                    .collect();
                traces.push(Trace {
                    label: format!("{dof} {terrain}"),
                    values,
                    dashed,
                    colour,
                });
            }
        }
        panels.push(Panel {
            leg,
            title: format!(
                "{} torque R^2, robot vs fly (fly 3.8e-8 N m/rad)",
                leg.name()
            ),
            traces,
            stance: vec![],
        });
    }
    let f = dir.join("spring_stiffness_r2.png");
    plot_leg_panels(
        &f,
        &panels,
        &x,
        "log10 robot parallel stiffness (N m/rad)",
        "R^2",
    )?;
    std::fs::read(&f).with_context(|| f.display().to_string())
}

/// Tables S4 springs and S6 at the paper's stiffnesses, equilibrium at the resting posture and
/// at the dead-fly proxy, with the proxy's CTr and FTi angles on the tripod's legs.
fn dead_fly() -> Result<String> {
    let mut md = String::from(
        "Equilibria of the dead-fly proxy (deg): CTr -35; FTi 20 below its smallest angle over the step; every other joint the middle of its range over the step.\n\n| organism | terrain | leg | CTr | FTi | FTi range over the step |\n|---|---|---|---|---|---|\n",
    );
    let mut counts = String::from(
        "| table | paper | ours, equilibrium = resting posture | ours, dead-fly proxy | peak spring torque / peak axis moment, robot / fly (rest; dead fly) |\n|---|---|---|---|---|\n",
    );
    // The fly's mean |GRF| over stance per leg with the dead-fly springs, flat then ball.
    let mut fly_grf = Vec::new();
    for (terrain, id) in [("flat", "S4 springs"), ("ball", "S6")] {
        let claims = claims(id)?;
        let mut cells = Vec::new();
        let mut shares = Vec::new();
        for from in [
            EquilibriumSource::RestingPosture,
            EquilibriumSource::DeadFly,
        ] {
            let robot = organism("drosophibot2", terrain, SpringSpec::Paper, from)?;
            let fly = organism("scale-drosophila", terrain, SpringSpec::Paper, from)?;
            let r = compare(&robot.traces, &fly.traces);
            let r2 = paper::r2_of(&r, &TRIPOD, Quantity::Torque);
            cells.push(our_counts(&r2, claims).join(", "));
            shares.push(format!(
                "{:.2} / {:.2}",
                spring_share(&robot),
                spring_share(&fly)
            ));
            if from == EquilibriumSource::DeadFly {
                fly_grf.push(mean_grf(&fly));
                for (name, o) in [("Drosophibot II", &robot), ("Scale-Drosophila", &fly)] {
                    for leg in TRIPOD {
                        let eq = |kind: JointKind| {
                            o.plan.model.joints.iter().enumerate().find_map(|(j, jt)| {
                                (jt.leg == leg && jt.kind == kind)
                                    .then(|| jt.spring.map(|s| (j, s.equilibrium)))
                                    .flatten()
                            })
                        };
                        let (Some((_, ctr)), Some((fti, fti_eq))) =
                            (eq(JointKind::CTr), eq(JointKind::FTi))
                        else {
                            continue;
                        };
                        let (lo, hi) = o
                            .plan
                            .q
                            .iter()
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
                                (l.min(q[fti]), h.max(q[fti]))
                            });
                        writeln!(
                            md,
                            "| {name} | {terrain} | {} | {:.1} | {:.1} | {:.1} to {:.1} |",
                            leg.name(),
                            ctr.to_degrees(),
                            fti_eq.to_degrees(),
                            lo.to_degrees(),
                            hi.to_degrees()
                        )?;
                    }
                }
            }
        }
        writeln!(
            counts,
            "| {id} | {} | {} | {} | {} |",
            paper_counts(claims).join(", "),
            cells[0],
            cells[1],
            shares.join("; ")
        )?;
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let ratios: Vec<String> = Leg::ALL
        .iter()
        .zip(fly_grf[0].iter().zip(&fly_grf[1]))
        .map(|(leg, (f, b))| format!("{} {:.2}", leg.name(), mean(b) / mean(f)))
        .collect();
    writeln!(
        counts,
        "\nScale-Drosophila's GRF on the ball / flat with the dead-fly springs (mean |GRF| over each leg's stance; figure S9: up to about 2x, most in the front legs): {}.",
        ratios.join(", ")
    )?;
    Ok(format!("{md}\n{counts}"))
}
