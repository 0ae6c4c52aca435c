//! The run results of docs/validation.md's generated blocks: the built-in models at table 1's
//! parameters (weight, peak torques, plots), the servo feasibility and the choice of the default
//! swing, the IK's continuity on the fly's ball walk, the 15 degree incline, the resting posture,
//! the speed sweep, the paper's comparison and curves walked on the physics robot.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Context, Result};
use planner::analysis::{SweepPoint, classify_sweep, sweep_point};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::{Actuation, JointKind, Leg, builtin};
use planner::plan::feasibility;

/// The generated blocks by name, and the plots (file name, PNG bytes) the document shows.
#[derive(Debug)]
pub struct Generated {
    pub blocks: BTreeMap<&'static str, String>,
    pub plots: Vec<(&'static str, Vec<u8>)>,
}

/// The parts of the run results. Each part's blocks and plots need nothing from another part, so
/// a check can run the parts side by side (`dbot validate --check FILE --part NAME`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// The built-in models at table 1: weight, peak torques, feasibility, the swing's choice, the
    /// IK's continuity, the incline, the resting posture; their plots.
    Plans,
    /// The paper's comparison and the parallel springs; their plots.
    Paper,
    /// The speed sweep.
    Sweep,
    /// Strain standing and walking; its plot.
    Strain,
    /// Turning and the steering blend.
    Steering,
    /// The timings.
    Timing,
    /// Substrates and the perturbation; its plot.
    Trials,
}

impl Part {
    pub const ALL: [Part; 7] = [
        Part::Plans,
        Part::Paper,
        Part::Sweep,
        Part::Strain,
        Part::Steering,
        Part::Timing,
        Part::Trials,
    ];

    /// The part's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Part::Plans => "plans",
            Part::Paper => "paper",
            Part::Sweep => "sweep",
            Part::Strain => "strain",
            Part::Steering => "steering",
            Part::Timing => "timing",
            Part::Trials => "trials",
        }
    }

    /// The part of this name.
    pub fn from_name(name: &str) -> Option<Part> {
        Part::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The names of the part's blocks (what [`generate_part`] fills, checked there).
    pub fn blocks(self) -> &'static [&'static str] {
        match self {
            Part::Plans => &[
                "weight",
                "robot-peaks",
                "feasibility",
                "swing-choice",
                "ik-continuity",
                "incline",
                "posture",
            ],
            Part::Paper => &[
                "paper",
                "spring-stiffness",
                "spring-stiffness-ball",
                "dead-fly",
            ],
            Part::Sweep => &["sweep"],
            Part::Strain => &["strain", "strain_walking"],
            Part::Steering => &["turning", "steer-blend"],
            Part::Timing => &["performance"],
            Part::Trials => &["substrates", "perturbation"],
        }
    }

    /// The part that generates the block of this name.
    pub fn of_block(name: &str) -> Option<Part> {
        Part::ALL.into_iter().find(|p| p.blocks().contains(&name))
    }
}

/// Every generated block by name, and every plot.
pub fn generate(plots_dir: &Path) -> Result<Generated> {
    let mut all = Generated {
        blocks: BTreeMap::new(),
        plots: Vec::new(),
    };
    for part in Part::ALL {
        let g = generate_part(part, plots_dir)?;
        all.blocks.extend(g.blocks);
        all.plots.extend(g.plots);
    }
    Ok(all)
}

/// The blocks and plots of one part.
pub fn generate_part(part: Part, plots_dir: &Path) -> Result<Generated> {
    std::fs::create_dir_all(plots_dir)
        .with_context(|| format!("creating {}", plots_dir.display()))?;
    let mut b = BTreeMap::new();
    let mut plots = Vec::new();
    match part {
        Part::Plans => plans(&mut b, &mut plots, plots_dir)?,
        Part::Paper => paper(&mut b, &mut plots, plots_dir)?,
        Part::Sweep => {
            b.insert("sweep", sweep()?);
        }
        Part::Strain => {
            b.insert("strain", super::strain::block()?);
            let (walks, png) = super::strain_walking::walks(plots_dir)?;
            b.insert("strain_walking", super::strain_walking::block(&walks)?);
            plots.push(("strain_walking.png", png));
        }
        Part::Steering => {
            b.insert("turning", super::turning::turning()?);
            b.insert("steer-blend", crate::steer_blend::block()?);
        }
        Part::Timing => {
            b.insert("performance", super::timing::performance()?);
        }
        Part::Trials => {
            b.insert("substrates", super::trials::substrates()?);
            let (perturbation, png) = super::trials::perturbation(plots_dir)?;
            b.insert("perturbation", perturbation);
            plots.push(("perturbation_load.png", png));
        }
    }
    let made: Vec<&str> = b.keys().copied().collect();
    let mut listed = part.blocks().to_vec();
    listed.sort_unstable();
    if made != listed {
        crate::bail!(
            "validation part `{}` generated blocks {made:?} but lists {listed:?}",
            part.name()
        );
    }
    Ok(Generated { blocks: b, plots })
}

type Blocks = BTreeMap<&'static str, String>;
type Plots = Vec<(&'static str, Vec<u8>)>;

/// [`Part::Plans`].
fn plans(b: &mut Blocks, plots: &mut Plots, plots_dir: &Path) -> Result<()> {
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

    // Feasibility of the default (servo-safe) walk and of the original solver's 0.5 s swing.
    let mut s = String::new();
    for (preset, terrain) in [
        ("servo-safe", "flat"),
        ("servo-safe", "ball"),
        ("table1", "flat"),
        ("table1", "ball"),
    ] {
        let mut params = StepParams::preset(preset, &robot.name).context("preset")?;
        params.terrain = planner::terrain::Ground::parse(terrain)?;
        let p = planner::plan::plan(&robot, &params)?;
        let c = solve(&p)?;
        let t = planner::dynamics::output::torque_rows(&c);
        let f = feasibility::check(&p.model, &p.q, Some(&t), p.dt);
        let verdict = if f.is_feasible() {
            let (share, fast) = fastest(&f);
            let margin = f
                .joints
                .iter()
                .filter_map(|j| j.torque_speed_margin.map(|m| (m.value, &j.joint)))
                .fold((f64::INFINITY, None), |a, (m, j)| {
                    if m < a.0 { (m, Some(j)) } else { a }
                });
            format!(
                "feasible: the fastest joint, {fast}, turns at {:.0} % of its servo's no-load speed; the smallest margin under the torque-speed line is {:.2} N m ({})",
                100.0 * share,
                margin.0,
                margin.1.map_or("-", |j| j.as_str())
            )
        } else {
            f.violations
                .iter()
                .map(|v| v.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        };
        // Saturation: the largest |torque| as a share of its servo's stall torque.
        let (stall, at) = f
            .joints
            .iter()
            .filter_map(|j| Some((j.torque?.value / j.limits?.stall_torque, j.joint.as_str())))
            .fold((0.0f64, "-"), |a, b| if b.0 > a.0 { b } else { a });
        writeln!(
            s,
            "- {preset}, swing {:.1} s ({terrain}): {verdict}; the largest torque is {:.0} % of its servo's stall torque ({at})",
            params.swing_s,
            100.0 * stall
        )?;
    }
    b.insert("feasibility", s);

    // Why 1.0 s: the fastest joint's share of its no-load speed against the swing duration.
    let mut s = String::from(
        "| swing (s) | period (s) | fastest joint, flat | share of no-load speed | fastest joint, ball | share of no-load speed |\n|---|---|---|---|---|---|\n",
    );
    // The shortest swing whose fastest joint keeps this share of its no-load speed in reserve.
    const RESERVE: f64 = 0.25;
    let mut shortest = None;
    for swing in [0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.6] {
        let mut cells = Vec::new();
        let mut period = 0.0;
        let mut worst = 0.0f64;
        for terrain in ["flat", "ball"] {
            let ground = planner::terrain::Ground::parse(terrain)?;
            let p = plan_of(&robot, &|p| {
                p.swing_s = swing;
                p.terrain = ground;
            })?;
            period = p.period_s;
            let (share, fast) = fastest(&feasibility::check(&p.model, &p.q, None, p.dt));
            worst = worst.max(share);
            cells.push(format!("{fast} | {:.0} %", 100.0 * share));
        }
        if worst <= 1.0 - RESERVE && shortest.is_none() {
            shortest = Some(swing);
        }
        writeln!(s, "| {swing} | {} | {} |", short(period), cells.join(" | "))?;
    }
    writeln!(
        s,
        "\nThe shortest swing in this list at which every joint keeps at least {:.0} % of its no-load speed in reserve on both terrains: {}; `servo-safe` uses {} s.",
        100.0 * RESERVE,
        shortest.map_or("none".to_string(), |x| format!("{x} s")),
        planner::gait::SERVO_SAFE_SWING_S
    )?;
    b.insert("swing-choice", s);

    // The IK's continuity on the fly's ball walk (its front CTr used to jump 0.47 rad).
    let p = plan_of(&fly, &|p| p.terrain = planner::terrain::Ground::BALL)?;
    let n = p.slices();
    // (step, joint, slice, allowance) of the largest step relative to its allowance.
    let mut worst = (0.0f64, 0usize, 0usize, f64::INFINITY);
    for j in 0..p.model.joints.len() {
        let bound = planner::plan::continuity::speed_limit(&p.model, j, p.params.swing_s) * p.dt;
        for sl in 0..n {
            let step = (p.q[(sl + 1) % n][j] - p.q[sl][j]).abs();
            if step / bound > worst.0 / worst.3 {
                worst = (step, j, sl, bound);
            }
        }
    }
    let f = feasibility::check(&p.model, &p.q, None, p.dt);
    let jumps = f
        .violations
        .iter()
        .filter(|v| matches!(v, feasibility::Violation::Jump { .. }))
        .count();
    let s = format!(
        "Scale-Drosophila on the ball (table 1): {} step(s) over a joint's allowance reported by the IK; the largest step relative to its allowance is {}'s {:.3} rad between slices {} and {}, against the {:.3} rad that one turn per swing (2 pi / {} s = {:.1} rad/s) allows in one {} ms slice; the feasibility check finds {jumps} inverse-kinematics jump(s).",
        p.ik_gaps.len(),
        p.model.joints[worst.1].name,
        worst.0,
        worst.2,
        (worst.2 + 1) % n,
        worst.3,
        p.params.swing_s,
        worst.3 / p.dt,
        p.dt * 1e3
    );
    b.insert("ik-continuity", s);

    // The 15 degree incline with push-only feet.
    let p = plan_of(&robot, &|p| {
        p.terrain = planner::terrain::Ground::Incline { angle_deg: 15.0 }
    })?;
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
    let farthest = original
        .iter()
        .map(|(pair, leg, o)| {
            let thc = robot.joints[robot.leg_chain(*leg)[0]]
                .origin
                .translation
                .vector;
            let o = nalgebra::Vector3::from(*o);
            let a = rp.posture.foot(*leg).unwrap_or_default() - thc;
            ((a - o).norm() / o.norm(), *pair)
        })
        .fold((0.0, ""), |a, b| if b.0 > a.0 { b } else { a });
    writeln!(
        s,
        "\nTable 1's placement is farthest from the original's at the {} legs ({:.0} % of the ThC-to-foot distance).",
        farthest.1,
        100.0 * farthest.0
    )?;
    // The physical-robot preset on both terrains: does it plan, and can the servos follow it?
    for terrain in ["flat", "ball"] {
        let mut params = physical.clone();
        params.terrain = planner::terrain::Ground::parse(terrain)?;
        let verdict = match planner::plan::plan(&robot, &params) {
            Err(e) => format!("does not plan: {e}"),
            Ok(p) => {
                let c = solve(&p)?;
                let t = planner::dynamics::output::torque_rows(&c);
                let f = feasibility::check(&p.model, &p.q, Some(&t), p.dt);
                let (share, fast) = fastest(&f);
                if f.is_feasible() {
                    format!(
                        "feasible for the servos (the fastest joint, {fast}, at {:.0} % of its no-load speed)",
                        100.0 * share
                    )
                } else {
                    format!("plans, but not for the servos: {}", f.violations[0])
                }
            }
        };
        writeln!(s, "- physical-robot preset, {terrain}: {verdict}")?;
    }
    b.insert("posture", s);

    // Plots of the built-in models at table 1.
    for (name, plan, cycle, what) in [
        ("robot_flat_torques.png", &rp, &rc, "torques"),
        ("robot_flat_grf.png", &rp, &rc, "grf"),
        ("fly_flat_torques.png", &fp, &fc, "torques"),
    ] {
        let f = plots_dir.join(name);
        match what {
            "torques" => report::dynamics::plot_torques(plan, cycle, &f)?,
            _ => report::dynamics::plot_grf(plan, cycle, &f)?,
        }
        plots.push((
            name,
            std::fs::read(&f).with_context(|| f.display().to_string())?,
        ));
    }
    Ok(())
}

/// [`Part::Paper`]: the paper's comparison and the parallel springs.
fn paper(b: &mut Blocks, plots: &mut Plots, plots_dir: &Path) -> Result<()> {
    let c = crate::paper_comparison::run_paper(plots_dir, 50)?;
    b.insert("paper", c.markdown);
    let springs = super::springs::spring_blocks(plots_dir)?;
    b.insert("spring-stiffness", springs.flat);
    b.insert("spring-stiffness-ball", springs.ball);
    b.insert("dead-fly", springs.dead_fly);
    plots.push(("spring_stiffness_r2.png", springs.plot));
    for (name, from) in [
        ("fig4b_flat_springs_torques.png", "flat-springs"),
        ("figS7b_ball_springs_torques.png", "ball-springs"),
    ] {
        let f = plots_dir.join(from).join("compare_torques.png");
        plots.push((
            name,
            std::fs::read(&f).with_context(|| f.display().to_string())?,
        ));
    }
    Ok(())
}

/// The fastest joint's share of its servo's no-load speed, and its name.
fn fastest(f: &feasibility::Feasibility) -> (f64, String) {
    f.joints
        .iter()
        .filter_map(|j| {
            j.limits
                .map(|l| (j.speed.value / l.no_load_speed, j.joint.clone()))
        })
        .fold((0.0, String::new()), |a, b| if b.0 > a.0 { b } else { a })
}

/// Peak torque with and without gravity over the step period (duty 0.6), both models.
fn sweep() -> Result<String> {
    let mut s = String::from(
        "| model | period (s) | peak torque | inertial part | share |\n|---|---|---|---|---|\n",
    );
    let mut notes = Vec::new();
    for (model, swings, unit, scale) in [
        ("drosophibot2", &[0.2, 0.4, 0.8, 1.6][..], "N m", 1.0),
        ("scale-drosophila", &[0.025, 0.05, 0.1][..], "uN mm", 1e9),
    ] {
        let m = builtin(model)?;
        let mut points: Vec<SweepPoint> = Vec::new();
        for &sw in swings {
            let mut p = StepParams::table1(model);
            p.swing_s = sw;
            points.push(sweep_point(&m, &p)?);
        }
        let name = if model == "drosophibot2" {
            "Drosophibot II"
        } else {
            "Scale-Drosophila"
        };
        for p in &points {
            writeln!(
                s,
                "| {name} | {} | {} {unit} | {} {unit} | {} |",
                short(p.period),
                sig3(p.peak_torque * scale),
                sig3(p.peak_inertial_torque * scale),
                sig3(p.peak_inertial_torque / p.peak_torque)
            )?;
        }
        let r = classify_sweep(&points).context("sweep")?;
        notes.push(format!(
            "{name}: inertial part ~ T^{:.2}; inertial share {} at the {} s period, {} at {} s",
            r.inertial_exponent,
            sig3(r.inertial_share[points.len() - 1]),
            short(points[points.len() - 1].period),
            sig3(r.inertial_share[0]),
            short(points[0].period)
        ));
    }
    writeln!(s, "\n{}.", notes.join("; "))?;
    Ok(s)
}

/// At most four decimals, trailing zeros dropped (periods made of swing / (1 - duty)).
fn short(x: f64) -> String {
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Three significant digits.
fn sig3(x: f64) -> String {
    let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
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
