//! `dbot demo`: the whole path on the virtual robot. Plans the tripod gait of the built-in
//! Drosophibot II on flat ground with the paper's parameters (table 1 at the servo-safe 1.0 s
//! swing), solves its inverse dynamics, says whether the servos can follow it, writes the plan's
//! CSVs and plots, builds the step table, uploads it to the in-process virtual robot, walks 10
//! steps forward and 10 backward while recording, and prints a summary whose numbers all come from
//! this run.
//!
//! Every output goes through a scratch file renamed when complete, so a demo that is killed or
//! interrupted leaves each file either as the previous run wrote it or complete from this run.
//! Ctrl-C ends the demo at the next check (between stages, or between two recorded bus cycles)
//! with a non-zero exit.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use board::link::Board;
use board::record::{Ended, JointMeta, Recorder, Until, capture_while, joints_of_table, tracking};
use board::robot::{VirtualRobot, VirtualTransport};
use planner::gait::StepParams;
use planner::model::Leg;
use planner::plan_dir;
use protocol::{Direction, PlayCommand, Steps};
use report::recording::{plot_angles, plot_torques};

use crate::args::dynamics::DynamicsArgs;
use crate::common::interrupt;
use crate::common::output::replace;
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

/// Plan, upload, walk and record Drosophibot II's tripod gait on the virtual robot.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot demo                      # outputs in out/demo
  dbot demo --steps 3 --out /tmp/d   # 3 steps each way")]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Steps to walk in each direction.
    #[arg(long, default_value_t = 10)]
    pub steps: u32,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let out = &self.out;
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        if self.steps == 0 {
            bail!("--steps 0: give at least one step");
        }

        println!(
            "[1/5] planning the tripod gait of drosophibot2 (flat, table 1 of the paper, swing {:.1} s)",
            planner::gait::SERVO_SAFE_SWING_S
        );
        let model = planner::model::builtin("drosophibot2")?;
        let params = StepParams::preset("servo-safe", &model.name).context("servo-safe preset")?;
        let t0 = Instant::now();
        let plan = planner::plan::plan(&model, &params).context("planning the step")?;
        let t_plan = t0.elapsed();
        let dyn_args = DynamicsArgs {
            no_dynamics: false,
            friction_cone: false,
            push_only: false,
            mu: 0.5,
            torque_limits: false,
            parallel: false,
        };
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

        println!("[2/5] building the step table");
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

        println!("[3/5] uploading to the virtual robot");
        let mut board = Board::connect(VirtualTransport::new(VirtualRobot::new()))?;
        let up = board.upload(0, &table, |_, _| {})?;
        let parsed = protocol::GaitTable::parse(&table)?;
        let joints = joints_of_table(&parsed, &names);

        let mut walks = Vec::new();
        for (i, direction) in [Direction::Forward, Direction::Backward]
            .into_iter()
            .enumerate()
        {
            let label = if direction == Direction::Forward {
                "forward"
            } else {
                "backward"
            };
            println!(
                "[{}/5] walking {} steps {label}, recording",
                4 + i,
                self.steps
            );
            let dir = out.join("record").join(label);
            let wall = Instant::now();
            let rec = walk(
                &mut board,
                direction,
                self.steps,
                &dir,
                joints.clone(),
                parsed.slice_count(),
            )?;
            walks.push((label, dir, rec, wall.elapsed()));
        }

        let robot = board.transport().robot();
        let timing = robot.timing();
        let (to_servos, to_master) = robot.bus_bytes();
        let sim_s = robot.now_us() as f64 * 1e-6;
        println!();
        println!("outputs");
        println!("  plan (CSV, JSON, URDF, plots)  {}", plan_dir.display());
        println!(
            "  step table                     {} ({} bytes, CRC {:#010x})",
            table_path.display(),
            up.bytes,
            up.stored.crc
        );
        for (label, dir, _, _) in &walks {
            println!(
                "  recording {label:<9}            {}/telemetry.csv, torque.png, angles.png",
                dir.display()
            );
        }
        println!("planning");
        println!(
            "  {} slices, step period {:.3} s; kinematics {:.1} ms, inverse dynamics {:.1} ms (wall clock); {}",
            plan.slices(),
            plan.period_s,
            t_plan.as_secs_f64() * 1e3,
            t_dyn.as_secs_f64() * 1e3,
            dynamics.summary()
        );
        println!("bus (virtual robot, simulated time)");
        println!(
            "  {} cycles in {:.2} s: {:.1} Hz; {} overruns, longest bus transaction {} us; {:.0} bytes per cycle on the wire",
            timing.cycles,
            sim_s,
            timing.rate_hz(),
            timing.overruns,
            timing.max_busy_us,
            (to_servos + to_master) as f64 / timing.cycles.max(1) as f64
        );
        for (label, _, rec, wall) in &walks {
            println!(
                "tracking error {label} (present - planned angle, RMS over joints and cycles; {} cycles, {:.1} s simulated in {:.2} s of wall time)",
                rec.cycles(),
                rec.duration_s(),
                wall.as_secs_f64()
            );
            print_tracking(rec, &names);
        }
        Ok(())
    }
}

/// Plays `steps` steps in `direction` and records them into `dir`.
fn walk(
    board: &mut Board<VirtualTransport>,
    direction: Direction,
    steps: u32,
    dir: &Path,
    joints: Vec<JointMeta>,
    slices: usize,
) -> anyhow::Result<Recorder> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    board.discard_telemetry();
    board.play(PlayCommand {
        slot: 0,
        direction,
        period_scale: protocol::units::PERIOD_SCALE_ONE,
        steps: Steps::Count(steps),
    })?;
    let csv = dir.join("telemetry.csv");
    let scratch = dir.join(".partial-telemetry.csv");
    let mut rec = Recorder::create(&scratch, joints)
        .with_context(|| format!("creating {}", scratch.display()))?;
    let ended = capture_while(
        board,
        &mut rec,
        Until {
            seconds: None,
            standing: true,
        },
        interrupt::requested,
        |_| {},
    )?;
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
fn print_tracking(rec: &Recorder, names: &[String]) {
    let rows: Vec<_> = rec.rows().iter().filter(|r| r.step >= 1).cloned().collect();
    // With one step there is no step after the ramp's to measure: say so rather than print
    // zeros over an empty window.
    if rows.is_empty() {
        println!(
            "  no tracking error: it is measured from the second step on (give --steps 2 or more)"
        );
        return;
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
        println!(
            "  {}: RMS {:.4} rad ({:.2} deg), max {:.4} rad over {} joints",
            leg.name(),
            (sq / n.max(1) as f64).sqrt(),
            (sq / n.max(1) as f64).sqrt().to_degrees(),
            max,
            mine.len()
        );
    }
}
