//! `dbot compare --paper`: the paper's robot-versus-fly comparison in one run (section 3.1 and
//! 3.2; tables S2 to S8, figures 4A/4B, S7A/S7B and the ball-versus-flat GRF of figure S9), our
//! R^2 counts beside the paper's. Conditions and their sources: [`planner::analysis::paper`].

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Context, Result};
use planner::analysis::paper::{self, Quantity, TABLES, TRIPOD};
use planner::analysis::{ComparisonRow, DofTrace, compare};
use planner::dynamics::{CycleSolution, DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::{EquilibriumSource, Leg, SpringSpec, builtin};
use planner::plan::Plan;

use board::files::write_bytes_atomically;

/// One organism planned and solved under one condition.
#[derive(Debug)]
pub struct Run {
    pub plan: Plan,
    pub cycle: CycleSolution,
    pub traces: Vec<DofTrace>,
}

/// `model` planned (table 1 at `swing`, on `terrain`) and solved with `spring` on every actuated
/// joint, the equilibrium at the resting posture (the comparison's condition).
fn run(model: &str, swing: f64, terrain: &str, spring: SpringSpec, slices: usize) -> Result<Run> {
    run_from(
        model,
        swing,
        terrain,
        spring,
        EquilibriumSource::RestingPosture,
        slices,
    )
}

/// As [`run`], the springs' equilibrium from `from`.
pub fn run_from(
    model: &str,
    swing: f64,
    terrain: &str,
    spring: SpringSpec,
    from: EquilibriumSource,
    slices: usize,
) -> Result<Run> {
    let m = spring.apply(&builtin(model)?, from)?;
    let mut p = StepParams::table1(model);
    p.swing_s = swing;
    p.terrain = planner::terrain::Ground::parse(terrain)?;
    p.slices = slices;
    let what = || format!("{model} on {terrain} ({spring}, equilibrium at {from})");
    let plan = planner::plan::plan(&m, &p).with_context(|| format!("planning {}", what()))?;
    let cycle = solve_cycle(
        &plan.model,
        &plan_inputs(&plan),
        &DynamicsOptions::default(),
    )
    .with_context(|| format!("inverse dynamics of {}", what()))?;
    let traces = paper::traces(&plan, &cycle);
    Ok(Run {
        plan,
        cycle,
        traces,
    })
}

/// Everything the comparison found, as markdown (also the body of docs/validation.md's section).
#[derive(Debug)]
pub struct PaperComparison {
    pub markdown: String,
}

/// Runs the comparison with `slices` per step, writes tables.md, tables.csv and the overlay plots
/// under `out`, and returns the markdown.
pub fn run_paper(out: &Path, slices: usize) -> Result<PaperComparison> {
    let springs = [("none", SpringSpec::None), ("springs", SpringSpec::Paper)];
    let mut rows: Vec<(&str, &str, Vec<ComparisonRow>)> = Vec::new();
    let mut fly_sprung = Vec::new();
    let mut grf = Vec::new();
    for terrain in ["flat", "ball"] {
        for (tag, spring) in springs {
            let robot = run(
                "drosophibot2",
                paper::ROBOT_SWING_S,
                terrain,
                spring,
                slices,
            )?;
            let fly = run(
                "scale-drosophila",
                paper::FLY_SWING_S,
                terrain,
                spring,
                slices,
            )?;
            let r = compare(&robot.traces, &fly.traces);
            let dir = out.join(format!("{terrain}-{tag}"));
            std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
            crate::overlay::overlay(&robot.traces, &fly.traces, &r, &dir, ["robot", "fly"])?;
            rows.push((terrain, tag, r));
            grf.push((terrain, tag, mean_grf(&robot), mean_grf(&fly)));
            if tag == "springs" {
                fly_sprung.push(fly);
            }
        }
    }
    let fly_terrains = compare(&fly_sprung[0].traces, &fly_sprung[1].traces);
    let dir = out.join("fly-flat-vs-ball");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    crate::overlay::overlay(
        &fly_sprung[0].traces,
        &fly_sprung[1].traces,
        &fly_terrains,
        &dir,
        ["fly flat", "fly ball"],
    )?;

    let find = |terrain: &str, tag: &str| {
        rows.iter()
            .find(|(t, g, _)| *t == terrain && *g == tag)
            .map(|(_, _, r)| r.as_slice())
            .unwrap_or(&[])
    };
    let sources: [&[ComparisonRow]; 8] = [
        find("flat", "none"),
        find("ball", "none"),
        find("flat", "none"),
        find("flat", "springs"),
        find("ball", "none"),
        find("ball", "springs"),
        &fly_terrains,
        &fly_terrains,
    ];
    let mut md = String::new();
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record(["table", "leg", "dof", "r2"])?;
    writeln!(
        md,
        "Robot: Drosophibot II, table 1, swing {} s, period {} s. Fly: Scale-Drosophila, table 1, swing {} s, period {} s. Tripod {}; {} slices per step; springs: 1 N m/rad (robot), 3.8e-8 N m/rad (fly), equilibrium = resting posture.\n",
        paper::ROBOT_SWING_S,
        paper::ROBOT_SWING_S / 0.4,
        paper::FLY_SWING_S,
        paper::FLY_SWING_S / 0.4,
        TRIPOD.map(Leg::name).join(" "),
        slices
    )?;
    md += "| table | compares | paper | ours |\n|---|---|---|---|\n";
    for (t, src) in TABLES.iter().zip(sources) {
        let r2 = paper::r2_of(src, &TRIPOD, t.quantity);
        let claims = t.claims;
        let theirs: Vec<String> = claims
            .iter()
            .map(|c| format!("{} of {} > {}", c.count, c.of, c.above))
            .collect();
        let ours = our_counts(&r2, claims);
        writeln!(
            md,
            "| {} | {} | {} | {} |",
            t.id,
            t.what,
            theirs.join(", "),
            ours.join(", ")
        )?;
        for r in src
            .iter()
            .filter(|r| TRIPOD.contains(&r.leg) && r.summed_side.is_none())
        {
            let v = match t.quantity {
                Quantity::Angle => r.r2_angle,
                Quantity::Torque => r.r2_torque,
            };
            csv.write_record([
                t.id,
                r.leg.name(),
                &r.dof,
                &v.map_or("-".into(), |v| format!("{v:.3}")),
            ])?;
        }
    }
    md += "\nPer DoF of the tripod (R^2; angle tables S2, S3, S7 and torque tables S4 to S6, S8):\n\n";
    md += "| leg | DoF | S2 angle flat | S3 angle ball | S4 torque flat | S4 springs | S5 torque ball | S6 ball springs |\n|---|---|---|---|---|---|---|---|\n";
    let f = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.3}"));
    for r in find("flat", "none")
        .iter()
        .filter(|r| TRIPOD.contains(&r.leg))
    {
        let pick = |terrain: &str, tag: &str, q: Quantity| {
            find(terrain, tag)
                .iter()
                .find(|o| o.leg == r.leg && o.dof == r.dof)
                .and_then(|o| match q {
                    Quantity::Angle => o.r2_angle,
                    Quantity::Torque => o.r2_torque,
                })
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.leg.name(),
            r.dof,
            f(pick("flat", "none", Quantity::Angle)),
            f(pick("ball", "none", Quantity::Angle)),
            f(pick("flat", "none", Quantity::Torque)),
            f(pick("flat", "springs", Quantity::Torque)),
            f(pick("ball", "none", Quantity::Torque)),
            f(pick("ball", "springs", Quantity::Torque)),
        )?;
    }
    md += "\nGround reaction force, ball / flat (mean |GRF| over each leg's stance, in brackets the largest slice-by-slice ratio; figure S9, fly with springs, has up to about 2x, most in the front legs):\n\n| model | springs | LF | LM | LH | RF | RM | RH |\n|---|---|---|---|---|---|---|---|\n";
    for (k, name) in ["Drosophibot II", "Scale-Drosophila"].iter().enumerate() {
        for (tag, _) in springs {
            let get = |terrain: &str| {
                grf.iter()
                    .find(|g| g.0 == terrain && g.1 == tag)
                    .map(|g| if k == 0 { g.2.clone() } else { g.3.clone() })
                    .unwrap_or_default()
            };
            let (flat, ball) = (get("flat"), get("ball"));
            let cells: Vec<String> = flat
                .iter()
                .zip(&ball)
                .map(|(f, b)| {
                    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
                    // Slice by slice (same phase on both terrains), over slices loaded on both.
                    let floor = 0.05 * mean(f);
                    let most = f
                        .iter()
                        .zip(b)
                        .filter(|(f, _)| **f > floor)
                        .map(|(f, b)| b / f)
                        .fold(0.0f64, f64::max);
                    format!("{:.2} ({most:.2})", mean(b) / mean(f))
                })
                .collect();
            writeln!(md, "| {name} | {tag} | {} |", cells.join(" | "))?;
        }
    }
    let bytes = csv.into_inner().context("building tables.csv")?;
    write_bytes_atomically(&out.join("tables.csv"), &bytes)?;
    write_bytes_atomically(&out.join("tables.md"), md.as_bytes())?;
    Ok(PaperComparison { markdown: md })
}

/// |GRF| over each leg's stance slices, N, per leg in [`Leg::ALL`] order.
pub fn mean_grf(r: &Run) -> Vec<Vec<f64>> {
    Leg::ALL
        .iter()
        .map(|leg| {
            let li = r.plan.legs.iter().position(|l| l == leg);
            let fi = r.plan.model.feet.iter().position(|f| f.leg == *leg);
            let (Some(li), Some(fi)) = (li, fi) else {
                return vec![];
            };
            let v: Vec<f64> = r
                .cycle
                .slices
                .iter()
                .zip(&r.plan.stance)
                .filter(|(_, st)| st[li])
                .map(|(s, _)| s.grf[fi].norm())
                .collect();
            v
        })
        .collect()
}

/// Largest |spring torque| over the largest |axis moment| (actuator + spring), over the tripod's
/// actuated joints.
pub fn spring_share(r: &Run) -> f64 {
    let (mut spring, mut total) = (0.0f64, 0.0f64);
    for sl in &r.cycle.slices {
        for (j, joint) in r.plan.model.joints.iter().enumerate() {
            if TRIPOD.contains(&joint.leg) {
                spring = spring.max(sl.spring_torque[j].abs());
                total = total.max((sl.torque[j] + sl.spring_torque[j]).abs());
            }
        }
    }
    spring / total
}

/// Our R^2 counts for each of the paper's claims: "N of M > threshold".
pub fn our_counts(r2: &[f64], claims: &[paper::Claim]) -> Vec<String> {
    claims
        .iter()
        .map(|c| {
            format!(
                "{} of {} > {}",
                paper::count_above(r2, c.above),
                r2.len(),
                c.above
            )
        })
        .collect()
}
