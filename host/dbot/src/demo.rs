//! `dbot demo`: the whole path on the physics robot (MuJoCo body under the firmware loop; or the
//! plain virtual robot with `--port virtual`). Plans the tripod gait of the built-in Drosophibot II
//! on flat ground with the paper's parameters (table 1 at the servo-safe 1.0 s swing), solves its
//! inverse dynamics, says whether the servos can follow it, writes the plan's CSVs and plots,
//! builds the step table, uploads it to the in-process robot, walks 10 steps forward and 10
//! backward while recording, and prints a summary whose numbers all come from this run; on the
//! physics robot also what each walk did to the body (distance per step against the plan, heading
//! drift, thorax height and tilt, slip per foot), the plan's GRF and torques against the simulated
//! contact forces and servo loads (R^2 of the plan's prediction), a third walk with the torque bias
//! off and what the bias buys, and `walk.gif`. The walks and their figures are `lab::demo`; this
//! file parses, announces the stages and prints (`common::walk_summary`). The summary is also
//! written to `summary.txt`.
//!
//! Every output goes through a scratch file renamed when complete, so a demo that is killed or
//! interrupted leaves each file either as the previous run wrote it or complete from this run.
//! Ctrl-C ends the demo at the next check (between stages, or between two recorded bus cycles)
//! with a non-zero exit.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use board::robot::{VirtualRobot, VirtualTransport};
use lab::demo::{DemoBody, DemoInput, DemoProgress, has_body, walk_all};
use lab::plan_dir_write::{PlanSource, write_plan_dir};
use lab::walk_words::{print_bias, print_body, print_fits, print_strain, print_tracking};
use physics::PhysicsRobot;
use planner::gait::StepParams;
use planner::plan_dir;

use crate::args::dynamics::DynamicsArgs;
use crate::common::{interrupt, output::replace};

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

/// The demo's stage lines while it walks, and Ctrl-C.
struct Stages {
    total: usize,
}

impl DemoProgress for Stages {
    fn walking(&mut self, index: usize, _walks: usize, steps: u32, label: &str) {
        println!(
            "[{}/{}] walking {steps} steps {label}, recording",
            4 + index,
            self.total
        );
    }
    fn drawing(&mut self) {
        println!("[{0}/{0}] drawing the walk (walk.gif)", self.total);
    }
    fn stop_requested(&self) -> bool {
        interrupt::requested()
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
            "[1/{total}] planning the tripod gait of drosophibot2 (flat, the servo-safe preset: table 1 of the paper at swing {:.1} s)",
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
        let source = PlanSource {
            model_source: "drosophibot2",
            table_name: Some(GAIT_NAME),
            spring: None,
        };
        let written = write_plan_dir(&plan_dir, &plan, &source, Some(&dynamics))?;
        println!(
            "  {}",
            crate::feasibility_args::summary(&written.feasibility)
        );
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
            cycle: &dynamics.cycle,
        };
        match self.port.as_str() {
            "physics" | "physics:flat" => {
                println!("[3/{total}] uploading to the physics robot (MuJoCo, flat ground)");
                let body = PhysicsRobot::drosophibot(&planner::terrain::Ground::Flat)?;
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
        let mut stages = Stages {
            total: stage_count(has_body(&transport)),
        };
        let input = DemoInput {
            plan,
            table,
            names,
            grf_z: ctx.grf_z,
            cycle: Some(ctx.cycle),
        };
        let done = walk_all(transport, &input, self.steps, out, &mut stages)?;
        let (up, walks, timing) = (&done.upload, &done.walks, &done.timing);
        let (to_servos, to_master) = done.bus_bytes;
        let sim_s = done.simulated_s;
        let mut s = String::new();
        writeln!(s, "outputs")?;
        writeln!(s, "  plan (CSV, JSON, URDF, plots)  {}", plan_dir.display())?;
        writeln!(
            s,
            "  step table                     {} ({} bytes, CRC {:#010x})",
            table_path.display(),
            up.bytes,
            up.stored.crc
        )?;
        for w in walks {
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
            if done.strain.iter().any(|(l, _)| *l == w.label) {
                writeln!(
                    s,
                    "  {:<28} {}/strain_vs_plan.png, strain_vs_plan.csv",
                    "",
                    w.dir.display()
                )?;
            }
        }
        if let Some((path, frames)) = &done.gif {
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
        for w in walks {
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
        for w in walks {
            if let Some(f) = &w.figures {
                print_body(&mut s, w, f, plan, self.steps)?;
            }
        }
        for (label, loads, grf) in &done.fits {
            print_fits(&mut s, label, loads, grf, self.steps)?;
        }
        for (label, fits) in &done.strain {
            print_strain(&mut s, label, fits, self.steps)?;
        }
        if let Some(h) = done.planned_height_m {
            print_bias(&mut s, walks, h, self.steps)?;
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
    /// The plan's solved cycle (the strain prediction the walks' gauges are compared with).
    cycle: &'a planner::dynamics::CycleSolution,
}
