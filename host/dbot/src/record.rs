//! `dbot record`: saves the board's telemetry as a tidy CSV (written as it arrives) and plots the
//! measured against the modelled torque (paper fig. 5) and commanded against present angles.
//!
//! The CSV is written to `OUT/.partial-telemetry.csv` and renamed to `OUT/telemetry.csv` when the
//! recording ends (also when it ends early: every row in it is whole), so a killed `dbot record`
//! leaves the previous recording in place. Ctrl-C stops the walk at the end of the step (whoever
//! started it), records until the robot stands, keeps the file and exits non-zero.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use board::link::{Board, Transport};
use board::record::{
    CaptureError, Ended, JointMeta, Recorder, Until, capture_while, joint_names, joints_of_table,
    missing_cycles,
};
use indicatif::{ProgressBar, ProgressStyle};
use report::recording::{plot_angles, plot_torques};

use crate::args::board::BoardArgs;
use crate::common::interrupt;
use crate::common::output::replace;

/// Record telemetry to OUT/telemetry.csv and plot it (OUT/torque.png, OUT/angles.png).
///
/// Ctrl-C stops the walk at the end of its step, records until the robot stands and keeps the
/// rows so far in OUT/telemetry.csv.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot record --out rec --table walk.dbgt --play 1 --steps 10
  dbot record --out rec --table walk.dbgt --seconds 20   # whatever the board is doing")]
pub struct Args {
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
    /// Seconds to record, board clock (default: until the gait started with --play ends, else 10).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Step table of the gait being played: its joint map turns load registers into torques and
    /// gives the modelled torque (without it only raw registers are recorded).
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// Start this gait slot first and record it (the way to record on the virtual robot).
    #[arg(long)]
    pub play: Option<u8>,
    /// With --play: whole steps to play.
    #[arg(long, requires = "play")]
    pub steps: Option<u32>,
    /// With --play: walk backward.
    #[arg(long, requires = "play")]
    pub backward: bool,
    /// With --play: step period, s (default: the planned one).
    #[arg(long, requires = "play")]
    pub period: Option<f64>,
    /// Telemetry every this many bus cycles (1 to 65535: 0 would record nothing).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub every: u16,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if let Some(s) = self.seconds
            && !(s.is_finite() && s > 0.0)
        {
            bail!("--seconds {s}: must be a positive number of seconds");
        }
        let table = match &self.table {
            Some(p) => Some(std::fs::read(p).with_context(|| format!("reading {}", p.display()))?),
            None => None,
        };
        if let Some(b) = &table {
            let path = self.table.as_deref().unwrap_or(Path::new("?")).display();
            protocol::GaitTable::parse(b)
                .with_context(|| format!("{path} (--table) is not a step table"))?;
        }
        // A bad --out fails here, before the robot moves.
        std::fs::create_dir_all(&self.out)
            .with_context(|| format!("creating {}", self.out.display()))?;
        interrupt::catch()?;
        // Ctrl-C stops a walk (even one another command started) before a second one may exit.
        interrupt::hold();
        let mut s = self.board.connect()?;
        if s.is_virtual() && self.play.is_none() {
            bail!("the virtual robot only walks while dbot runs: give --play SLOT [--steps K]");
        }
        s.board.set_telemetry(self.every)?;
        let joints = named_joints(&mut s, table.as_deref(), self.play)?;
        if let Some(slot) = self.play {
            let (cmd, gait) = crate::common::playback::play_command(
                &mut s,
                slot,
                self.steps,
                self.period,
                self.backward,
            )?;
            if interrupt::requested() {
                bail!("interrupted before the walk started: nothing was played or recorded");
            }
            println!("{}", crate::common::playback::announce(slot, &gait, &cmd));
            s.board.discard_telemetry();
            s.board
                .play(cmd)
                .with_context(|| format!("playing slot {slot}"))?;
        }
        let until = Until {
            seconds: self
                .seconds
                .or(if self.play.is_some() && self.steps.is_some() {
                    None
                } else {
                    Some(10.0)
                }),
            standing: self.play.is_some(),
        };
        let slices = table
            .as_ref()
            .and_then(|b| protocol::GaitTable::parse(b).ok())
            .map_or(0, |t| t.slice_count());
        let summary = record_to(&mut s.board, &self.out, joints, slices, until)?;
        println!("{summary}");
        s.close()
    }
}

/// The board's joints named from the setup's model (`LF_ThC1`, ...): by the table's servo IDs;
/// without a table by the servo IDs the board reports for the slot to be played (or its selected
/// gait), and only when it knows none by its joint-map order (see [`board::record::joint_names`]).
fn named_joints(
    s: &mut crate::common::session::Session,
    table: Option<&[u8]>,
    play: Option<u8>,
) -> anyhow::Result<Vec<JointMeta>> {
    let spec = s.setup.model.as_deref().unwrap_or("drosophibot2");
    let model = crate::common::model_spec::load_model(spec)?;
    let table = table.and_then(|b| protocol::GaitTable::parse(b).ok());
    Ok(match &table {
        Some(t) => joints_of_table(t, &joint_names(&model, Some(t), t.joint_count())),
        None if let Some(ids) = s.board.joint_map(play)? => {
            board::record::joint_names_by_ids(&model, &ids.servo_ids)
                .into_iter()
                .map(JointMeta::named)
                .collect()
        }
        None => {
            let count = s.board.settings()?.joints.len();
            joint_names(&model, None, count)
                .into_iter()
                .map(JointMeta::named)
                .collect()
        }
    })
}

/// Records into `dir` (telemetry.csv, then the plots) and returns a short summary. If the board
/// vanishes or Ctrl-C ends the recording, the rows so far are kept in telemetry.csv, the plots are
/// drawn from them, and the error says so (after Ctrl-C, once the robot stands).
pub fn record_to<T: Transport>(
    board: &mut Board<T>,
    dir: &Path,
    joints: Vec<JointMeta>,
    slices: usize,
    until: Until,
) -> anyhow::Result<String> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let csv = dir.join("telemetry.csv");
    let scratch = dir.join(".partial-telemetry.csv");
    let mut joints = joints;
    if joints.is_empty() {
        joints = (0..board.settings()?.joints.len())
            .map(|j| JointMeta::named(format!("J{j}")))
            .collect();
    }
    if joints.is_empty() {
        bail!(
            "{}: the board reports no joints (no gait selected): nothing to record; upload a table and give --play SLOT",
            board.port()
        );
    }
    let mut rec = Recorder::create(&scratch, joints)
        .with_context(|| format!("creating {}", scratch.display()))?;
    let bar = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("recording {spinner} {msg}").expect("template is valid"),
    );
    let mut progress = |t: f64| {
        if rec_tick(t) {
            bar.set_message(format!("{t:.1} s of board time"));
            bar.tick();
        }
    };
    let mut result = capture_while(board, &mut rec, until, interrupt::requested, &mut progress);
    let interrupted = matches!(result, Ok(Ended::Interrupted));
    if interrupted {
        bar.println("interrupted: stopping at the end of the step (Ctrl-C again to exit at once)");
        let stopped = crate::common::playback::stop_walk(board);
        interrupt::release();
        result = match stopped {
            Ok(()) => capture_while(
                board,
                &mut rec,
                Until {
                    seconds: None,
                    standing: true,
                },
                || false,
                &mut progress,
            ),
            Err(e) => {
                bar.finish_and_clear();
                finish_csv(&scratch, &csv, &rec)?;
                return Err(e);
            }
        };
    }
    bar.finish_and_clear();
    if let Err(CaptureError::Write(e)) = &result {
        // A failed write may have left half a row: the scratch file is not a recording.
        let _ = std::fs::remove_file(&scratch);
        bail!("writing {}: {e}", scratch.display());
    }
    finish_csv(&scratch, &csv, &rec)?;
    replace(dir, "README.md", |p| {
        Ok(std::fs::write(p, board::record::TELEMETRY_README)?)
    })?;
    let plots = draw(dir, &rec, slices);
    if let Err(e) = result {
        return Err(anyhow::Error::new(e)).with_context(|| {
            format!(
                "recording stopped: {} rows kept in {}",
                rec.rows().len(),
                csv.display()
            )
        });
    }
    plots?;
    if interrupted {
        let state = board.status().map_or_else(
            |e| format!("unknown ({e})"),
            |st| crate::common::words::state_name(st.state).to_owned(),
        );
        bail!(
            "interrupted: the walk was stopped at the end of its step and the robot is {state}; \
             {} bus cycles ({:.2} s of board time) kept in {}",
            rec.cycles(),
            rec.duration_s(),
            csv.display()
        );
    }
    let missing = missing_cycles(rec.rows());
    Ok(format!(
        "recorded {} bus cycles ({:.2} s of board time) x {} joints to {}; {}",
        rec.cycles(),
        rec.duration_s(),
        rec.joints().len(),
        csv.display(),
        if missing == 0 {
            "no telemetry record missing".to_string()
        } else {
            format!("{missing} telemetry records missing (skipped cycle numbers)")
        }
    ))
}

/// Puts the finished scratch CSV in place of `csv` (every row in it is whole: rows are flushed
/// per bus cycle and a write error never gets here). A recording without a single row is not
/// kept: it would replace a good recording (and leave its plots beside a header-only CSV).
fn finish_csv(scratch: &Path, csv: &Path, rec: &Recorder) -> anyhow::Result<()> {
    if rec.rows().is_empty() {
        let _ = std::fs::remove_file(scratch);
        bail!(
            "no telemetry arrived: nothing recorded, {} is left as it was",
            csv.display()
        );
    }
    board::files::commit_scratch(csv).with_context(|| {
        format!(
            "keeping the recording ({} rows in {})",
            rec.rows().len(),
            scratch.display()
        )
    })
}

/// Whether to refresh the progress line (every tenth of a second of board time).
fn rec_tick(t: f64) -> bool {
    ((t * 100.0).round() as u64).is_multiple_of(10)
}

/// The plots, each through a scratch file (a killed run leaves the previous plot whole).
fn draw(dir: &Path, rec: &Recorder, slices: usize) -> anyhow::Result<()> {
    if rec.rows().is_empty() {
        return Ok(());
    }
    replace(dir, "angles.png", |p| {
        plot_angles(p, rec.rows(), rec.joints())
            .map_err(|e| anyhow::anyhow!("plotting angles: {e}"))
    })?;
    if slices > 0 && rec.joints().iter().any(|j| j.model.is_some()) {
        replace(dir, "torque.png", |p| {
            plot_torques(p, rec.rows(), rec.joints(), slices)
                .map_err(|e| anyhow::anyhow!("plotting torques: {e}"))
        })?;
    } else {
        // A torque plot of an earlier recording must not pass for this one's.
        let old = dir.join("torque.png");
        if old.exists() {
            std::fs::remove_file(&old)
                .with_context(|| format!("removing {} (of an earlier recording)", old.display()))?;
        }
    }
    Ok(())
}
