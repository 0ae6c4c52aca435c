//! The walks of `dbot demo` on one in-process robot (the physics robot, or the virtual robot
//! without a body): upload the step table, walk forward and backward while recording, and with a
//! body a third walk forward with the torque bias off; then the animation and the fits beside
//! each recording (loads, contact forces, and the simulated gauges of the forward walks against
//! the predicted strain). What this returns is everything the demo's summary prints; the printing, the
//! stage lines and Ctrl-C belong to the caller ([`DemoProgress`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use board::link::{Board, UploadReport};
use board::record::{Ended, JointMeta, Recorder, joints_of_table};
use board::robot::{PlannedLoads, ServoDynamics, VirtualTransport};
use firmware::bus_loop::Timing;
use physics::{Figures, PhysicsRobot, WalkLog};
use planner::plan::Plan;
use protocol::Direction;
use report::recording::{plot_angles, plot_torques};

use crate::error::{Context, LabError, Result};
use crate::walk::play_and_record;
use crate::walk_files::{Walk, write_fits, write_walk_gif};
use crate::walk_fits::Fit;

/// Bus cycles between two poses of the animation (0.25 s at the board's 100 Hz).
pub const POSE_EVERY_CYCLES: usize = 25;
/// The label (and record directory) of the walk without the torque bias.
pub const BIAS_OFF_LABEL: &str = "forward, bias off";

/// What moves the demo robot's servos, and what it can say about the body after a walk.
pub trait DemoBody: ServoDynamics + std::fmt::Debug {
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

/// What the demo tells its user while it walks, and whether to stop.
pub trait DemoProgress {
    /// Walk `index` (0-based, of `walks`) starts: `steps` steps, `label`.
    fn walking(&mut self, index: usize, walks: usize, steps: u32, label: &str);
    /// The animation is being drawn.
    fn drawing(&mut self);
    /// Whether the user asked to stop (checked between two recorded bus cycles).
    fn stop_requested(&self) -> bool;
}

/// What the walks need from the planning stages.
#[derive(Debug, Clone, Copy)]
pub struct DemoInput<'a> {
    pub plan: &'a Plan,
    /// The step table as uploaded.
    pub table: &'a [u8],
    /// The servo joints' names, in table order.
    pub names: &'a [String],
    /// The plan's vertical GRF, `[slice][leg]` in `plan.legs` order, N.
    pub grf_z: &'a [Vec<f64>],
    /// The plan's solved inverse dynamics (the table's torques): with a body and gauges, the
    /// forward walks' simulated gauges are compared with the strain it predicts.
    pub cycle: Option<&'a planner::dynamics::CycleSolution>,
}

/// Everything the walks found.
#[derive(Debug)]
pub struct DemoWalks {
    pub upload: UploadReport,
    pub walks: Vec<Walk>,
    pub timing: Timing,
    /// Bytes on the wire to the servos and to the master.
    pub bus_bytes: (u64, u64),
    /// Simulated seconds since power-on.
    pub simulated_s: f64,
    /// The thorax height the plan keeps, m (`None`: no body).
    pub planned_height_m: Option<f64>,
    /// `walk.gif` and its frame count (with a body).
    pub gif: Option<(PathBuf, usize)>,
    /// Per walk with the bias on and a body: its label, load fits and GRF fits.
    pub fits: Vec<(&'static str, Vec<Fit>, Vec<Fit>)>,
    /// Per forward walk with a body and gauges (bias on and off): its label and the simulated
    /// gauges against the prediction ([`crate::strain_walk`]), written beside its recording.
    pub strain: Vec<(&'static str, Vec<Fit>)>,
}

/// Whether the robot has a body: then the demo walks three times and draws the walk.
pub fn has_body<S: DemoBody>(transport: &VirtualTransport<S>) -> bool {
    transport.robot().servos().planned_height_m().is_some()
}

/// Uploads the table, walks `steps` steps each way (and forward with the bias off, with a body)
/// recording into `out/record/DIRECTION`, and makes the walks' files.
pub fn walk_all<S: DemoBody>(
    transport: VirtualTransport<S>,
    input: &DemoInput<'_>,
    steps: u32,
    out: &Path,
    progress: &mut dyn DemoProgress,
) -> Result<DemoWalks> {
    let body = has_body(&transport);
    let mut board = Board::connect(transport)?;
    let checked = crate::simulated::checked(input.table, "the demo's gait")?;
    let upload = board.upload(0, &checked, |_, _| {})?;
    let parsed = protocol::GaitTable::parse(input.table)?;
    let joints = joints_of_table(&parsed, input.names);
    // With a body, a third walk: forward again with the firmware's torque bias switched off.
    let mut plans = vec![
        (Direction::Forward, "forward", "forward", true),
        (Direction::Backward, "backward", "backward", true),
    ];
    if body {
        plans.push((
            Direction::Forward,
            BIAS_OFF_LABEL,
            "forward-bias-off",
            false,
        ));
    }
    let count = plans.len();
    let mut walks = Vec::new();
    for (i, (direction, label, dir_name, bias_on)) in plans.into_iter().enumerate() {
        let mut meta = joints.clone();
        if !bias_on {
            // Stiffness 0 is the firmware's setting for "no bias" (firmware/src/bias.rs).
            for j in 0..joints.len() {
                board.set_stiffness(j as u8, board::rules::stiffness::Stiffness::OFF)?;
            }
            // The goals are now the planned angles: the recorder must not subtract a bias.
            for m in &mut meta {
                m.stiffness_nm_per_rad = None;
            }
        }
        progress.walking(i, count, steps, label);
        let dir = out.join("record").join(dir_name);
        let how = WalkHow {
            label,
            direction,
            bias_on,
            steps,
            slices: parsed.slice_count(),
        };
        let walk = walk_recorded(&mut board, &how, &dir, meta, || progress.stop_requested())?
            .ok_or_else(|| {
                LabError::Interrupted(format!(
                    "interrupted while recording into {}: the outputs written so far are complete, the others are as before",
                    dir.display()
                ))
            })?;
        walks.push(walk);
    }
    let robot = board.transport().robot();
    let planned_height_m = robot.servos().planned_height_m();
    let gif = match planned_height_m {
        Some(_) => {
            progress.drawing();
            Some(write_walk_gif(out, &input.plan.model, &walks)?)
        }
        None => None,
    };
    let mut fits = Vec::new();
    for w in walks.iter().filter(|w| w.bias_on) {
        if let Some(log) = &w.log {
            let (loads, grf) =
                write_fits(w, log, input.names, &input.plan.legs, input.grf_z, steps)?;
            fits.push((w.label, loads, grf));
        }
    }
    let mut strain = Vec::new();
    if let Some(cycle) = input.cycle {
        let predicted = crate::strain_walk::predicted(input.plan, cycle)?;
        let names: Vec<String> = input
            .plan
            .model
            .gauges
            .iter()
            .map(|g| g.name.clone())
            .collect();
        for w in walks.iter().filter(|w| w.direction == Direction::Forward) {
            let Some(log) = &w.log else { continue };
            if predicted.is_empty() {
                continue;
            }
            let fits = crate::strain_walk::strain_fits(log, &names, &predicted, steps);
            crate::strain_walk::write_strain_files(&w.dir, input.plan, &fits)?;
            strain.push((w.label, fits));
        }
    }
    Ok(DemoWalks {
        upload,
        strain,
        timing: robot.timing(),
        bus_bytes: robot.bus_bytes(),
        simulated_s: robot.now_us() as f64 * 1e-6,
        planned_height_m,
        gif,
        fits,
        walks,
    })
}

/// What one walk of [`walk_recorded`] plays.
#[derive(Debug, Clone, Copy)]
pub struct WalkHow {
    pub label: &'static str,
    pub direction: Direction,
    /// Whether the firmware adds the torque bias (the caller set the stiffness to match).
    pub bias_on: bool,
    pub steps: u32,
    /// Slices per step of the table played.
    pub slices: usize,
}

/// Plays one walk on `board` from standing, logging the body (a pose every
/// [`POSE_EVERY_CYCLES`] bus cycles), and records it into `dir` ([`record_walk`]): the walk with
/// what it did to the body. `None` when `stop` ended it early: then the previous recording stays.
pub fn walk_recorded<S: DemoBody>(
    board: &mut Board<VirtualTransport<S>>,
    how: &WalkHow,
    dir: &Path,
    joints: Vec<JointMeta>,
    stop: impl Fn() -> bool,
) -> Result<Option<Walk>> {
    let wall = Instant::now();
    board
        .transport_mut()
        .robot_mut()
        .servos_mut()
        .start_walk(POSE_EVERY_CYCLES);
    let Some(rec) = record_walk(
        board,
        how.direction,
        how.steps,
        dir,
        joints,
        how.slices,
        stop,
    )?
    else {
        return Ok(None);
    };
    let servos = board.transport_mut().robot_mut().servos_mut();
    Ok(Some(Walk {
        label: how.label,
        direction: how.direction,
        bias_on: how.bias_on,
        dir: dir.to_owned(),
        rec,
        wall: wall.elapsed(),
        figures: servos.walk_figures(),
        log: servos.take_log(),
    }))
}

/// Plays `steps` steps in `direction` and records them into `dir` (telemetry.csv, torque.png,
/// angles.png); `None` when `stop` ended the walk early: then the previous recording stays.
pub fn record_walk<S: DemoBody>(
    board: &mut Board<VirtualTransport<S>>,
    direction: Direction,
    steps: u32,
    dir: &Path,
    joints: Vec<JointMeta>,
    slices: usize,
    stop: impl Fn() -> bool,
) -> Result<Option<Recorder>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let csv = dir.join("telemetry.csv");
    let scratch = board::files::scratch_of(&csv)?;
    let (rec, ended) = play_and_record(board, direction, steps, &scratch, joints, stop)?;
    if ended == Ended::Interrupted {
        let _ = std::fs::remove_file(&scratch);
        return Ok(None);
    }
    board::files::commit_scratch(&csv)?;
    // Only whole walking steps go into the per-step statistics (not the start ramp).
    let walking: Vec<_> = rec
        .rows()
        .iter()
        .filter(|r| r.step < steps)
        .cloned()
        .collect();
    board::files::write_atomically(&dir.join("torque.png"), |p| {
        Ok(plot_torques(p, &walking, rec.joints(), slices)
            .map_err(|e| format!("plotting torques: {e}"))?)
    })?;
    board::files::write_atomically(&dir.join("angles.png"), |p| {
        Ok(
            plot_angles(p, rec.rows(), rec.joints())
                .map_err(|e| format!("plotting angles: {e}"))?,
        )
    })?;
    Ok(Some(rec))
}
