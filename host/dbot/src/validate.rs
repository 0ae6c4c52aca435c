//! `dbot validate`: regenerates the numbers of docs/validation.md. The document's prose stays hand
//! written; every figure it quotes from a run sits in a block between `<!-- generated: NAME -->`
//! and `<!-- end generated -->`, which `--write` fills and `--check` compares (a test runs
//! `--check`, so the document cannot drift from the code).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::{Actuation, JointKind, Leg, builtin};
use planner::plan::feasibility;

/// Regenerate (or check) the run results quoted in docs/validation.md.
///
/// Plans and solves the built-in models (table 1 parameters), the 15 degree incline, the servo
/// feasibility at two swing durations and the paper's comparison (`dbot compare --paper`, 50
/// slices per step to keep the check quick), and fills the document's generated blocks.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Fill the generated blocks of this file in place.
    #[arg(long, group = "mode")]
    write: Option<PathBuf>,
    /// Fail (listing the blocks) if this file's generated blocks differ from a fresh run.
    #[arg(long, group = "mode")]
    check: Option<PathBuf>,
    /// Keep the comparison's plots (`dbot compare --paper` layout) in this directory.
    #[arg(long)]
    plots: Option<PathBuf>,
}

const OPEN: &str = "<!-- generated: ";
const CLOSE: &str = "<!-- end generated -->";

impl Args {
    pub fn run(self) -> Result<()> {
        let (path, write) = match (&self.write, &self.check) {
            (Some(p), None) => (p, true),
            (None, Some(p)) => (p, false),
            _ => bail!("give --write FILE or --check FILE"),
        };
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        // The comparison's plots (megabytes) go to --plots, else to a scratch directory.
        let scratch = std::env::temp_dir().join(format!("dbot-validate-{}", std::process::id()));
        let generated = blocks(self.plots.as_ref().unwrap_or(&scratch));
        let _ = std::fs::remove_dir_all(&scratch);
        let blocks = generated?;
        let (new, stale) = fill(&text, &blocks).with_context(|| path.display().to_string())?;
        if write {
            crate::common::output::replace_file(path, |p| Ok(std::fs::write(p, &new)?))?;
            println!(
                "{}: {} generated blocks ({} changed)",
                path.display(),
                blocks.len(),
                stale.len()
            );
        } else if !stale.is_empty() {
            bail!(
                "{} has drifted from the code in block(s) {}: run `dbot validate --write {}`",
                path.display(),
                stale.join(", "),
                path.display()
            );
        } else {
            println!(
                "{}: all {} generated blocks match",
                path.display(),
                blocks.len()
            );
        }
        Ok(())
    }
}

/// Replaces every block's body; returns the new text and the names of blocks whose body changed.
fn fill(text: &str, blocks: &BTreeMap<&str, String>) -> Result<(String, Vec<String>)> {
    let mut out = String::new();
    let mut rest = text;
    let mut seen = Vec::new();
    let mut stale = Vec::new();
    while let Some(i) = rest.find(OPEN) {
        let after = &rest[i + OPEN.len()..];
        let end_name = after
            .find("-->")
            .context("unterminated generated-block marker")?;
        let name = after[..end_name].trim().to_string();
        let body_start = i + OPEN.len() + end_name + 3;
        let close = rest[body_start..]
            .find(CLOSE)
            .with_context(|| format!("block `{name}` has no `{CLOSE}`"))?;
        let old = &rest[body_start..body_start + close];
        let fresh = blocks
            .get(name.as_str())
            .with_context(|| format!("block `{name}` is not one dbot validate generates"))?;
        let fresh = format!("\n{}\n", fresh.trim_end());
        if old != fresh {
            stale.push(name.clone());
        }
        out += &rest[..body_start];
        out += &fresh;
        out += CLOSE;
        rest = &rest[body_start + close + CLOSE.len()..];
        seen.push(name);
    }
    out += rest;
    for name in blocks.keys() {
        if !seen.iter().any(|s| s == name) {
            bail!("block `{name}` is missing (add `{OPEN}{name} -->` ... `{CLOSE}`)");
        }
    }
    Ok((out, stale))
}

/// Every generated block by name.
fn blocks(plots: &std::path::Path) -> Result<BTreeMap<&'static str, String>> {
    let mut b = BTreeMap::new();
    let robot = builtin("drosophibot2")?;
    let fly = builtin("scale-drosophila")?;
    let plan_of = |m: &planner::model::Model, f: &dyn Fn(&mut StepParams)| {
        let mut p = StepParams::table1(&m.name);
        f(&mut p);
        planner::plan::plan(m, &p).with_context(|| format!("planning {}", m.name))
    };
    let solve = |plan: &planner::plan::Plan| {
        solve_cycle(&plan.model, &plan_inputs(plan), &DynamicsOptions::default())
            .with_context(|| format!("inverse dynamics of {}", plan.model.name))
    };

    // Weight against the solved vertical GRF; the fly's friction need on flat ground.
    let rp = plan_of(&robot, &|_| {})?;
    let rc = solve(&rp)?;
    let fp = plan_of(&fly, &|_| {})?;
    let fc = solve(&fp)?;
    let mut s = String::new();
    for (name, plan, cycle) in [("Drosophibot II", &rp, &rc), ("Scale-Drosophila", &fp, &fc)] {
        let mass = plan.model.total_mass();
        let g = plan.gravity.norm();
        let fz: Vec<f64> = cycle
            .slices
            .iter()
            .map(|s| s.grf.iter().map(|f| f.z).sum())
            .collect();
        let mean = fz.iter().sum::<f64>() / fz.len() as f64;
        let (mut worst, mut sum, mut n) = (0.0f64, 0.0, 0usize);
        for (sl, st) in cycle.slices.iter().zip(&plan.stance) {
            for (li, leg) in plan.legs.iter().enumerate() {
                let Some(fi) = plan.model.feet.iter().position(|f| f.leg == *leg) else {
                    continue;
                };
                let f = sl.grf[fi];
                if st[li] && f.z > 0.0 {
                    let mu = (f.x * f.x + f.y * f.y).sqrt() / f.z;
                    worst = worst.max(mu);
                    sum += mu;
                    n += 1;
                }
            }
        }
        writeln!(
            s,
            "- {name}: mass {} kg, weight {} N; total vertical GRF {} N on average over the cycle (min {}, max {}: the thorax's inertia is zero, the legs' is not); stance feet need a friction coefficient |F_t| / F_n of {:.2} on average, up to {:.2}.",
            sig(mass),
            sig(mass * g),
            sig(mean),
            sig(fz.iter().cloned().fold(f64::INFINITY, f64::min)),
            sig(fz.iter().cloned().fold(f64::NEG_INFINITY, f64::max)),
            sum / n.max(1) as f64,
            worst
        )?;
    }
    b.insert("weight", s);

    // Peak actuated torque per leg pair and joint, robot, flat.
    let kinds = [
        JointKind::ThC1,
        JointKind::ThC3,
        JointKind::CTr,
        JointKind::TrF1,
        JointKind::FTi,
    ];
    let mut s =
        String::from("| pair | ThC1 | ThC3 | CTr | TrF | FTi |\n|---|---|---|---|---|---|\n");
    for (pair, legs) in [
        ("front", [Leg::LF, Leg::RF]),
        ("middle", [Leg::LM, Leg::RM]),
        ("hind", [Leg::LH, Leg::RH]),
    ] {
        let cells: Vec<String> = kinds
            .iter()
            .map(|k| {
                let js: Vec<usize> = (0..robot.joints.len())
                    .filter(|&j| legs.contains(&robot.joints[j].leg) && robot.joints[j].kind == *k)
                    .collect();
                let fixed = js
                    .iter()
                    .all(|&j| matches!(robot.joints[j].actuation, Actuation::Fixed { .. }));
                let peak = rc
                    .slices
                    .iter()
                    .flat_map(|sl| js.iter().map(|&j| sl.torque[j].abs()))
                    .fold(0.0f64, f64::max);
                if fixed {
                    format!("fixed ({peak:.2})")
                } else {
                    format!("{peak:.2}")
                }
            })
            .collect();
        writeln!(s, "| {pair} | {} |", cells.join(" | "))?;
    }
    b.insert("robot-peaks", s);

    // Feasibility at table 1's 0.5 s swing and at 0.8 s.
    let mut s = String::new();
    for (swing, terrain) in [(0.5, "flat"), (0.5, "ball"), (0.8, "flat"), (0.8, "ball")] {
        let p = plan_of(&robot, &|p| {
            p.swing_s = swing;
            p.terrain = terrain.into();
        })?;
        let c = solve(&p)?;
        let t = planner::dynamics::output::torque_rows(&c);
        let f = feasibility::check(&p.model, &p.q, Some(&t), p.dt);
        writeln!(
            s,
            "- swing {swing} s ({terrain}): {}",
            if f.is_feasible() {
                "feasible".to_string()
            } else {
                f.violations
                    .iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join("; ")
            }
        )?;
    }
    let p = plan_of(&fly, &|p| p.terrain = "ball".into())?;
    let f = feasibility::check(&p.model, &p.q, None, p.dt);
    writeln!(
        s,
        "- Scale-Drosophila on the ball (table 1): {}",
        f.violations
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join("; ")
    )?;
    b.insert("feasibility", s);

    // The 15 degree incline with push-only feet.
    let p = plan_of(&robot, &|p| p.terrain = "incline:15".into())?;
    let opts = DynamicsOptions {
        push_only: true,
        ..Default::default()
    };
    let s = match solve_cycle(&p.model, &plan_inputs(&p), &opts) {
        Ok(_) => "(feasible)".to_string(),
        Err(e) => format!("> {e}"),
    };
    b.insert("incline", s);

    // Resting posture: ThC -> foot offsets of table 1's placement and the physical-robot preset
    // against the original solver's figure (solver.md; ThC z of that figure: hind and middle
    // -0.0246 m, front 0.0377 m).
    let original = [
        ("hind", Leg::LH, [-0.150, 0.130, -0.175 + 0.0246]),
        ("middle", Leg::LM, [-0.025, 0.200, -0.190 + 0.0246]),
        ("front", Leg::LF, [0.114, 0.065, -0.165 - 0.0377]),
    ];
    let mut s = String::from(
        "| pair | original ThC -> foot (x, y, z) m | table1 (ours) | off by | physical-robot preset | off by |\n|---|---|---|---|---|---|\n",
    );
    let physical = StepParams::preset("physical-robot", "drosophibot2").context("preset")?;
    let pp = planner::plan::plan(&robot, &physical)?;
    for (pair, leg, o) in original {
        let thc = robot.joints[robot.leg_chain(leg)[0]]
            .origin
            .translation
            .vector;
        let o = nalgebra::Vector3::from(o);
        let offset = |plan: &planner::plan::Plan| {
            let f = plan.posture.foot(leg).unwrap_or_default();
            f - thc
        };
        let cell = |v: nalgebra::Vector3<f64>| format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z);
        let (a, b) = (offset(&rp), offset(&pp));
        writeln!(
            s,
            "| {pair} | {} | {} | {:.0} % | {} | {:.0} % |",
            cell(o),
            cell(a),
            100.0 * (a - o).norm() / o.norm(),
            cell(b),
            100.0 * (b - o).norm() / o.norm()
        )?;
    }
    b.insert("posture", s);

    // The paper's comparison.
    std::fs::create_dir_all(plots).with_context(|| format!("creating {}", plots.display()))?;
    let c = crate::compare_paper::run_paper(plots, 50)?;
    b.insert("paper", c.markdown);
    Ok(b)
}

/// Four significant digits: decimals for robot-sized values, exponent form for fly-sized ones.
fn sig(x: f64) -> String {
    if (1e-2..1e4).contains(&x.abs()) {
        let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}
