//! `dbot demo`: the whole path on the physics robot (MuJoCo body under the firmware loop; or the
//! plain virtual robot with `--port virtual`). Plans the tripod gait of the built-in Drosophibot II
//! on flat ground with the paper's parameters (table 1 at the servo-safe 1.0 s swing), solves its
//! inverse dynamics, says whether the servos can follow it, writes the plan's CSVs and plots,
//! builds the step table, uploads it to the in-process robot, walks 10 steps forward and 10
//! backward while recording, and prints a summary whose numbers all come from this run; on the
//! physics robot also what each walk did to the body (distance per step against the plan, heading
//! drift, thorax height and tilt, slip per foot), the plan's GRF and torques against the simulated
//! contact forces and servo loads (R^2, `common::demo_fit`), a third walk with the torque bias off
//! and what the bias buys (`common::demo_bias`), and `walk.gif` (`common::demo_walk`). The summary
//! is also written to `summary.txt`.
//!
//! Every output goes through a scratch file renamed when complete, so a demo that is killed or
//! interrupted leaves each file either as the previous run wrote it or complete from this run.
//! Ctrl-C ends the demo at the next check (between stages, or between two recorded bus cycles)
//! with a non-zero exit.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use board::link::Board;
use board::record::{Ended, JointMeta, Recorder, joints_of_table, tracking};
use board::robot::{PlannedLoads, ServoDynamics, VirtualRobot, VirtualTransport};
use physics::{Figures, PhysicsRobot, WalkLog};
use planner::gait::StepParams;
use planner::model::Leg;
use planner::plan_dir;
use protocol::Direction;
use report::recording::{plot_angles, plot_torques};

use crate::args::dynamics::DynamicsArgs;
use crate::common::demo_walk::{self, Walk};
use crate::common::interrupt;
use crate::common::output::replace;
use crate::common::physics_walk;
use crate::common::plan_output::write_plan_dir;

/// The demo's gait name in its plan directory and step table.
const GAIT_NAME: &str = "dbII tripod";

/// Fails with a message saying where the demo was when Ctrl-C arrived.
fn check_interrupt(stage: &str) -> anyhow::Result<()> {
    if interrupt::requested() {
        bail!(
            "interrupted {stage}: the outputs written so far are complete, the others are as before"
        );
    }
    Ok(())
}

/// What moves the demo robot's servos, and what it can say about the body after a walk.
trait DemoBody: ServoDynamics + std::fmt::Debug {
    /// Starts measuring a walk, logging a pose every `pose_every` bus cycles.
    fn start_walk(&mut self, _pose_every: usize) {}
    /// What the walk did to the body (`None`: the robot has no body).
    fn walk_figures(&self) -> Option<Figures> {
        None
    }
    /// The walk's log (`None`: the robot has no body).
    fn take_log(&mut self) -> Option<WalkLog> {
        None
    }
    /// The thorax height the plan keeps, m (`None`: no body).
    fn planned_height_m(&self) -> Option<f64> {
        None
    }
}

impl DemoBody for PlannedLoads {}

impl DemoBody for PhysicsRobot {
    fn start_walk(&mut self, pose_every: usize) {
        self.reset_figures();
        self.start_log(pose_every);
    }
    fn walk_figures(&self) -> Option<Figures> {
        self.figures().cloned()
    }
    fn take_log(&mut self) -> Option<WalkLog> {
        PhysicsRobot::take_log(self)
    }
    fn planned_height_m(&self) -> Option<f64> {
        Some(PhysicsRobot::planned_height_m(self))
    }
}

/// Plan, upload, walk and record Drosophibot II's tripod gait on the physics robot.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot demo                      # outputs in out/demo
  dbot demo --steps 3 --out /tmp/d   # 3 steps each way
  dbot demo --port virtual       # the virtual robot without a body (loads = planned torques)")]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Steps to walk in each direction.
    #[arg(long, default_value_t = 10)]
    pub steps: u32,
    /// Robot to walk: `physics` (MuJoCo body on flat ground, firmware in the loop) or `virtual`
    /// (servo lags carrying the planned torques, no body).
    #[arg(long, default_value = "physics")]
    pub port: String,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let out = &self.out;
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        if self.steps == 0 {
            bail!("--steps 0: give at least one step");
        }

        let total = stage_count(self.port != "virtual");
        println!(
            "[1/{total}] planning the tripod gait of drosophibot2 (flat, table 1 of the paper, swing {:.1} s)",
            planner::gait::SERVO_SAFE_SWING_S
        );
        let model = planner::model::builtin("drosophibot2")?;
        let params = StepParams::preset("servo-safe", &model.name).context("servo-safe preset")?;
        let t0 = Instant::now();
        let plan = planner::plan::plan(&model, &params).context("planning the step")?;
        let t_plan = t0.elapsed();
        let dyn_args = DynamicsArgs::WALK;
        let t1 = Instant::now();
        let dynamics = dyn_args.solve(&plan)?.context("inverse dynamics")?;
        let t_dyn = t1.elapsed();
        // Until here a Ctrl-C simply ends the process: nothing has been written yet.
        interrupt::catch()?;
        let plan_dir = out.join("plan");
        let (_, feasible) = write_plan_dir(
            &plan_dir,
            &plan,
            "drosophibot2",
            Some(GAIT_NAME),
            Some(&dynamics),
            serde_json::Value::Null,
        )?;
        println!("  {}", crate::feasibility_args::summary(&feasible));
        check_interrupt("after writing the plan")?;

        println!("[2/{total}] building the step table");
        // From the plan directory as written: the table `dbot table --plan` and `dbot upload
        // --plan` build from it, byte for byte.
        let written = plan_dir::read(&plan_dir)?;
        let table = written.step_table(None)?;
        let names = written.servo_joint_names();
        let table_path = out.join("drosophibot2-tripod.dbgt");
        replace(out, "drosophibot2-tripod.dbgt", |p| {
            Ok(std::fs::write(p, &table)?)
        })?;
        check_interrupt("after writing the step table")?;

        let ctx = Walked {
            plan: &plan,
            plan_dir: &plan_dir,
            table: &table,
            table_path: &table_path,
            names: &names,
            t_plan,
            t_dyn,
            dynamics_summary: dynamics.summary(),
            grf_z: &dynamics.grf[2],
        };
        match self.port.as_str() {
            "physics" | "physics:flat" => {
                println!("[3/{total}] uploading to the physics robot (MuJoCo, flat ground)");
                let body = PhysicsRobot::drosophibot("flat")?;
                self.walk_and_report(body.into_transport(), &ctx, "physics robot")
            }
            "virtual" => {
                println!("[3/{total}] uploading to the virtual robot");
                self.walk_and_report(
                    VirtualTransport::new(VirtualRobot::new()),
                    &ctx,
                    "virtual robot",
                )
            }
            other => bail!("--port {other}: the demo walks `physics` or `virtual`"),
        }
    }

    fn walk_and_report<S: DemoBody>(
        &self,
        transport: VirtualTransport<S>,
        ctx: &Walked<'_>,
        robot_name: &str,
    ) -> anyhow::Result<()> {
        let out = &self.out;
        let Walked {
            plan,
            plan_dir,
            table,
            table_path,
            names,
            t_plan,
            t_dyn,
            ..
        } = *ctx;
        let mut board = Board::connect(transport)?;
        let up = board.upload(0, table, |_, _| {})?;
        let parsed = protocol::GaitTable::parse(table)?;
        let joints = joints_of_table(&parsed, names);
        let has_body = board
            .transport()
            .robot()
            .servos()
            .planned_height_m()
            .is_some();
        // With a body, a third walk: forward again with the firmware's torque bias switched off.
        let mut plans = vec![
            (Direction::Forward, "forward", "forward", true),
            (Direction::Backward, "backward", "backward", true),
        ];
        if has_body {
            plans.push((
                Direction::Forward,
                BIAS_OFF_LABEL,
                "forward-bias-off",
                false,
            ));
        }
        let stages = stage_count(has_body);
        let mut walks = Vec::new();
        for (i, (direction, label, dir_name, bias_on)) in plans.into_iter().enumerate() {
            let mut meta = joints.clone();
            if !bias_on {
                // Stiffness 0 is the firmware's setting for "no bias" (firmware/src/bias.rs).
                for j in 0..joints.len() {
                    board.set_stiffness(j as u8, 0)?;
                }
                // The goals are now the planned angles: the recorder must not subtract a bias.
                for m in &mut meta {
                    m.stiffness_nm_per_rad = None;
                }
            }
            println!(
                "[{}/{stages}] walking {} steps {label}, recording",
                4 + i,
                self.steps
            );
            let dir = out.join("record").join(dir_name);
            let wall = Instant::now();
            board
                .transport_mut()
                .robot_mut()
                .servos_mut()
                .start_walk(POSE_EVERY_CYCLES);
            let rec = walk(
                &mut board,
                direction,
                self.steps,
                &dir,
                meta,
                parsed.slice_count(),
            )?;
            let servos = board.transport_mut().robot_mut().servos_mut();
            let figures = servos.walk_figures();
            let log = servos.take_log();
            walks.push(Walk {
                label,
                bias_on,
                dir,
                rec,
                wall: wall.elapsed(),
                figures,
                log,
            });
        }

        let mut s = String::new();
        let robot = board.transport().robot();
        let timing = robot.timing();
        let (to_servos, to_master) = robot.bus_bytes();
        let sim_s = robot.now_us() as f64 * 1e-6;
        let planned_height = robot.servos().planned_height_m();
        let gif = match planned_height {
            Some(_) => {
                println!("[{stages}/{stages}] drawing the walk (walk.gif)");
                Some(demo_walk::write_walk_gif(out, &plan.model, &walks)?)
            }
            None => None,
        };
        let mut fits = Vec::new();
        for w in walks.iter().filter(|w| w.bias_on) {
            if let Some(log) = &w.log {
                fits.push((
                    w.label,
                    demo_walk::write_fits(w, log, names, &plan.legs, ctx.grf_z, self.steps)?,
                ));
            }
        }

        writeln!(s, "outputs")?;
        writeln!(s, "  plan (CSV, JSON, URDF, plots)  {}", plan_dir.display())?;
        writeln!(
            s,
            "  step table                     {} ({} bytes, CRC {:#010x})",
            table_path.display(),
            up.bytes,
            up.stored.crc
        )?;
        for w in &walks {
            writeln!(
                s,
                "  recording {:<18} {}/telemetry.csv, torque.png, angles.png{}",
                w.label,
                w.dir.display(),
                if w.bias_on && w.log.is_some() {
                    ", grf_vs_plan.png, grf_vs_plan.csv, loads_vs_plan.csv, fit.csv"
                } else {
                    ""
                }
            )?;
        }
        if let Some((path, frames)) = &gif {
            writeln!(
                s,
                "  animation                      {} ({frames} frames, simulated body poses)",
                path.display()
            )?;
        }
        writeln!(
            s,
            "  this summary                   {}",
            out.join(SUMMARY).display()
        )?;
        writeln!(s, "planning")?;
        writeln!(
            s,
            "  {} slices, step period {:.3} s; kinematics {:.1} ms, inverse dynamics {:.1} ms (wall clock); {}",
            plan.slices(),
            plan.period_s,
            t_plan.as_secs_f64() * 1e3,
            t_dyn.as_secs_f64() * 1e3,
            ctx.dynamics_summary
        )?;
        writeln!(s, "bus ({robot_name}, simulated time)")?;
        writeln!(
            s,
            "  {} cycles in {:.2} s: {:.1} Hz; {} overruns, longest bus transaction {} us; {:.0} bytes per cycle on the wire",
            timing.cycles,
            sim_s,
            timing.rate_hz(),
            timing.overruns,
            timing.max_busy_us,
            (to_servos + to_master) as f64 / timing.cycles.max(1) as f64
        )?;
        for w in &walks {
            writeln!(
                s,
                "tracking error {} (present - planned angle, RMS over joints and cycles; {} cycles, {:.1} s simulated in {:.2} s of wall time)",
                w.label,
                w.rec.cycles(),
                w.rec.duration_s(),
                w.wall.as_secs_f64()
            )?;
            print_tracking(&mut s, &w.rec, names)?;
        }
        for w in &walks {
            if let Some(f) = &w.figures {
                print_body(&mut s, w.label, f, plan, self.steps, w.rec.duration_s())?;
            }
        }
        for (label, (loads, grf)) in &fits {
            demo_walk::print_fits(&mut s, label, loads, grf, self.steps)?;
        }
        if let Some(h) = planned_height {
            demo_walk::print_bias(&mut s, &walks, h, self.steps)?;
        }
        print!("\n{s}");
        replace(out, SUMMARY, |p| Ok(std::fs::write(p, &s)?))?;
        Ok(())
    }
}

/// Stages the demo announces: plan, table, upload, the walks (a third, bias off, with a body) and
/// with a body the animation.
fn stage_count(has_body: bool) -> usize {
    if has_body { 7 } else { 5 }
}

/// Bus cycles between two poses of the animation (0.25 s at the board's 100 Hz).
const POSE_EVERY_CYCLES: usize = 25;
/// The label (and record directory) of the walk without the torque bias.
const BIAS_OFF_LABEL: &str = "forward, bias off";
/// The summary file in the output directory: what the demo prints after the walks.
const SUMMARY: &str = "summary.txt";

/// What the walks need from the planning stages.
struct Walked<'a> {
    plan: &'a planner::plan::Plan,
    plan_dir: &'a Path,
    table: &'a [u8],
    table_path: &'a Path,
    names: &'a [String],
    t_plan: std::time::Duration,
    t_dyn: std::time::Duration,
    dynamics_summary: String,
    /// The plan's vertical GRF, `[slice][leg]` in `plan.legs` order, N.
    grf_z: &'a [Vec<f64>],
}

/// The body's figures of one walk against the plan. The plan moves the thorax at translation /
/// stance time for the whole cycle (0.085 m / 1.5 s x 2.5 s = 0.142 m per step for the servo-safe
/// preset, as for table 1's 0.75 s of 1.25 s; 0.085 m is each foot's stroke), keeps the resting body height and does not tilt or turn.
fn print_body(
    s: &mut String,
    label: &str,
    f: &Figures,
    plan: &planner::plan::Plan,
    steps: u32,
    seconds: f64,
) -> std::fmt::Result {
    let planned = plan.thorax_velocity.x * plan.period_s;
    let sign = if label == "backward" { -1.0 } else { 1.0 };
    let per_step = sign * f.forward_m / f64::from(steps);
    writeln!(
        s,
        "body {label} (physics robot, sampled every bus cycle over the walk's {seconds:.1} s)"
    )?;
    writeln!(
        s,
        "  distance {:.4} m per step, planned {:.4} m ({:+.1} %; the feet's stroke is {:.3} m); lateral {:+.4} m",
        per_step,
        planned,
        (per_step / planned - 1.0) * 100.0,
        plan.params.translation_m,
        f.lateral_m
    )?;
    writeln!(
        s,
        "  heading drift {:+.2} deg; thorax height {:.1} mm at the start, {:.1} mm lowest, {:.1} mm at the end (plan: constant); tilt up to {:.2} deg (plan: 0)",
        f.heading_rad.to_degrees(),
        f.height_start_m * 1e3,
        f.height_min_m * 1e3,
        f.height_end_m * 1e3,
        f.tilt_max_rad.to_degrees()
    )?;
    let slip: Vec<String> = f
        .slip_m
        .iter()
        .map(|(leg, x)| format!("{} {:.1}", leg.name(), x * 1e3))
        .collect();
    writeln!(s, "  slip while loaded, mm: {}", slip.join(", "))?;
    match f.verdict(0.01) {
        None => writeln!(
            s,
            "  the robot carried the gait (no sag over 10 mm, no fall)"
        ),
        Some(v) => writeln!(s, "  {v}"),
    }
}

/// Plays `steps` steps in `direction` and records them into `dir`.
fn walk<S: DemoBody>(
    board: &mut Board<VirtualTransport<S>>,
    direction: Direction,
    steps: u32,
    dir: &Path,
    joints: Vec<JointMeta>,
    slices: usize,
) -> anyhow::Result<Recorder> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let csv = dir.join("telemetry.csv");
    let scratch = dir.join(".partial-telemetry.csv");
    let (rec, ended) = physics_walk::play_and_record(board, direction, steps, &scratch, joints)?;
    if ended == Ended::Interrupted {
        // An interrupted walk is not the demo's recording: the previous one stays.
        let _ = std::fs::remove_file(&scratch);
        check_interrupt(&format!("while recording into {}", dir.display()))?;
    }
    board::files::commit_scratch(&csv)?;
    // Only whole walking steps go into the per-step statistics (not the start ramp).
    let walking: Vec<_> = rec
        .rows()
        .iter()
        .filter(|r| r.step < steps)
        .cloned()
        .collect();
    replace(dir, "torque.png", |p| {
        plot_torques(p, &walking, rec.joints(), slices)
            .map_err(|e| anyhow::anyhow!("plotting torques: {e}"))
    })?;
    replace(dir, "angles.png", |p| {
        plot_angles(p, rec.rows(), rec.joints())
            .map_err(|e| anyhow::anyhow!("plotting angles: {e}"))
    })?;
    Ok(rec)
}

/// RMS tracking error per leg, over the steps after the first (the first starts from the ramp).
fn print_tracking(s: &mut String, rec: &Recorder, names: &[String]) -> std::fmt::Result {
    let rows: Vec<_> = rec.rows().iter().filter(|r| r.step >= 1).cloned().collect();
    // With one step there is no step after the ramp's to measure: say so rather than print
    // zeros over an empty window.
    if rows.is_empty() {
        writeln!(
            s,
            "  no tracking error: it is measured from the second step on (give --steps 2 or more)"
        )?;
        return Ok(());
    }
    let per_joint = tracking(&rows, names.len());
    for leg in Leg::ALL {
        let mine: Vec<_> = per_joint
            .iter()
            .filter(|t| {
                names
                    .get(t.joint)
                    .is_some_and(|n| n.starts_with(leg.name()))
            })
            .collect();
        if mine.is_empty() {
            continue;
        }
        let n: usize = mine.iter().map(|t| t.samples).sum();
        let sq: f64 = mine
            .iter()
            .map(|t| t.rms_rad * t.rms_rad * t.samples as f64)
            .sum();
        let max = mine.iter().map(|t| t.max_abs_rad).fold(0.0, f64::max);
        writeln!(
            s,
            "  {}: RMS {:.4} rad ({:.2} deg), max {:.4} rad over {} joints",
            leg.name(),
            (sq / n.max(1) as f64).sqrt(),
            (sq / n.max(1) as f64).sqrt().to_degrees(),
            max,
            mine.len()
        )?;
    }
    Ok(())
}
