//! `dbot record`: records the board's telemetry as a trial (`board::trial`): a new folder in
//! `--out` per recording, named by its start time, holding the tidy CSV (written as it arrives),
//! the plots of measured against modelled torque (paper fig. 5) and commanded against present
//! angles, a README and trial.json, and a line in `TRIAL INDEX.txt` beside the folders.
//!
//! The trial is recorded into a hidden `.partial-` folder and published when the recording ends:
//! as asked under its start time, after Ctrl-C as `... interrupted`, after a failed link as
//! `... failed`; a recording without a single row is removed. No recording ever replaces another.
//! Ctrl-C stops the walk (whoever started it: `board::record::stop_walk`, the one stop path),
//! records until the robot stands, keeps the trial and exits non-zero.
//!
//! With `--strain PORT` the lab's strain board is recorded beside the servos
//! (`board::strain::StrainBeside`): calibrated before the robot moves, its `strain.csv` put on
//! the telemetry's time base at the end; a strain board that fails mid-recording costs only its
//! own later rows, the servo recording goes on and the trial is kept.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use anyhow::{Context, bail};
use board::link::{Board, Transport};
use board::platform::Perturb;
use board::record::{
    CaptureError, Ended, JointMeta, Recorder, Until, capture_until_standing, capture_while,
    joint_names, joints_of_table, missing_cycles,
};
use board::strain::{StrainBeside, StrainEnd};
use board::trial::{
    BoardSettings, FirmwareMeta, GaitMeta, Outcome, PlanMeta, TELEMETRY_CSV, TrialFolder, TrialMeta,
};
use indicatif::{ProgressBar, ProgressStyle};
use report::recording::{plot_angles, plot_torques};

use crate::args::board::BoardArgs;
use crate::common::interrupt;
use crate::common::output::replace;
use crate::common::playback;

/// Record a trial: telemetry, plots, README and trial.json in a new folder of OUT.
///
/// Each recording is a new trial folder in OUT named by its start time (UTC,
/// `YYYY-MM-DD HH_MM_SS`), listed in OUT/TRIAL INDEX.txt. Ctrl-C stops the walk at the end of
/// its step, records until the robot stands and keeps the trial as `... interrupted`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot record --out trials --table walk.dbgt --play 1 --steps 10 --notes first-try
  dbot record --out trials --port physics --table walk.dbgt --play 0 --steps 2   # uploads, walks, records
  dbot record --out trials --table walk.dbgt --seconds 20   # whatever the board is doing
  dbot record --out trials --table walk.dbgt --play 1 --steps 10 --strain /dev/ttyACM1   # with strain
  dbot record --out trials --table walk.dbgt --play 1 --steps 6 --perturb RM:3:rise
  dbot record --out trials --port physics:flat+platform:RM --table walk.dbgt --play 0 --steps 6 --perturb RM:3:rise")]
pub struct Args {
    /// Folder of trials: the trial is a new folder in it, listed in its TRIAL INDEX.txt.
    #[arg(long)]
    pub out: PathBuf,
    /// Name of the trial's folder (default: its start time, UTC); one that exists is refused.
    #[arg(long)]
    pub trial: Option<String>,
    /// Free-text notes, kept in the trial's README, trial.json and the index.
    #[arg(long, default_value = "")]
    pub notes: String,
    /// The ground walked on: floor, sandpaper, wire-mesh or anti-slip-mat (kept in the trial).
    /// A physics port's scene names its own (`--port physics:flat+floor`; sandpaper without);
    /// this, if given, must agree with it.
    #[arg(long)]
    pub substrate: Option<String>,
    /// Seconds to record, board clock (default: until the gait started with --play ends, else 10).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Step table of the gait: its joint map turns load registers into torques and gives the
    /// modelled torque (without it only raw registers are recorded). With --play it is uploaded
    /// into that slot first unless the slot holds it already (so the fresh robot of `--port
    /// physics` or `--port virtual` walks it).
    #[arg(long)]
    pub table: Option<PathBuf>,
    /// The plan directory the step table was built from, for the trial's metadata (default: the
    /// table's folder when it holds a plan.json).
    #[arg(long, requires = "table")]
    pub plan: Option<PathBuf>,
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
    /// Record the lab's strain board on this port beside the servos (a serial path, or `virtual`
    /// for a board in this process: fed by the body's simulated gauges on `--port physics`, at
    /// zero strain otherwise); it calibrates before the robot moves.
    #[arg(long, value_name = "PORT")]
    pub strain: Option<String>,
    /// With --play: move the perturbation platform under a leg, LEG:STEP:MOVE (e.g. RM:3:rise):
    /// at the first bus cycle of step STEP (counted from 0, within --steps) the platform servo
    /// goes to `rise` (2330 ticks) or `fall` (1570), two cycles later back to `rest` (2020), the
    /// lab's positions; kept in the trial. Without it a platform left set up is cleared.
    #[arg(long, requires = "play", value_name = "LEG:STEP:MOVE")]
    pub perturb: Option<String>,
    /// With --perturb: the platform servo's bus ID (default: the lab's 22 unless the gait's
    /// joints use it, then the first free ID after theirs: 23 for the built-in model's).
    #[arg(long, requires = "perturb")]
    pub platform_id: Option<u8>,
    /// Telemetry every this many bus cycles (1 to 65535, and at most what the recorder's 2 s
    /// silence limit allows at the bus's rate: 199 at 100 Hz).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u16).range(1..))]
    pub every: u16,
    #[command(flatten)]
    pub board: BoardArgs,
}

/// Everything before the first record: the session, the named joints, when to stop, the
/// trial's metadata so far and the strain board when one records beside.
type Started = (
    crate::common::session::Session,
    Vec<JointMeta>,
    Until,
    TrialMeta,
    Option<StrainBeside>,
);

/// A step table given with `--table`: its bytes and where it came from.
struct Table {
    path: PathBuf,
    bytes: Vec<u8>,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        if let Some(s) = self.seconds
            && !(s.is_finite() && s > 0.0)
        {
            bail!("--seconds {s}: must be a positive number of seconds");
        }
        let table = match &self.table {
            Some(p) => Some(Table {
                path: p.clone(),
                bytes: std::fs::read(p).with_context(|| format!("reading {}", p.display()))?,
            }),
            None => None,
        };
        if let Some(t) = &table {
            protocol::GaitTable::parse(&t.bytes)
                .with_context(|| format!("{} (--table) is not a step table", t.path.display()))?;
        }
        let plan = self.plan_meta()?;
        // A leg that is not a leg, a step beyond the run: refused before any port is opened.
        let perturb = self.perturbation()?;
        // Refused before any port is opened; `StrainBeside::start` checks the connected port again.
        if let (Some(strain), Some(servo)) = (&self.strain, &self.board.port) {
            board::strain::port::check_not_servo_port(strain, servo)
                .with_context(|| format!("--strain {strain}"))?;
        }
        interrupt::catch()?;
        // Ctrl-C stops a walk (even one another command started) before a second one may exit.
        interrupt::hold();
        // A trial folder that exists or cannot be written fails here, before the robot moves.
        let folder = TrialFolder::begin(&self.out, self.trial.as_deref(), SystemTime::now())?;
        match self.start(table.as_ref(), plan, perturb, &folder) {
            Ok((mut s, joints, until, meta, strain)) => {
                let slices = table
                    .as_ref()
                    .and_then(|t| protocol::GaitTable::parse(&t.bytes).ok())
                    .map_or(0, |t| t.slice_count());
                let summary =
                    record_trial(&mut s.board, folder, joints, slices, until, meta, strain)?;
                println!("{summary}");
                s.close()
            }
            Err(e) => {
                // Nothing was recorded: no trial.
                folder.discard();
                Err(e)
            }
        }
    }

    /// `--perturb` and `--platform-id`, checked against `--steps`.
    fn perturbation(&self) -> anyhow::Result<Option<Perturb>> {
        let Some(spec) = &self.perturb else {
            return Ok(None);
        };
        let table = self.table.as_ref().and_then(|t| std::fs::read(t).ok());
        let id = self
            .platform_id
            .unwrap_or_else(|| board::platform::default_platform_id_for(table.as_deref()));
        let p = Perturb::parse(spec, id)
            .and_then(|p| p.check_steps(self.steps).map(|()| p))
            .with_context(|| format!("--perturb {spec}"))?;
        Ok(Some(p))
    }

    /// `--plan`, or the table's folder when it is a plan directory.
    fn plan_meta(&self) -> anyhow::Result<Option<PlanMeta>> {
        let dir = match (&self.plan, &self.table) {
            (Some(d), _) => Some(d.clone()),
            (None, Some(t)) => t
                .parent()
                .filter(|d| d.join("plan.json").is_file())
                .map(Path::to_owned),
            (None, None) => None,
        };
        Ok(match dir {
            Some(d) => Some(PlanMeta::read(&d)?),
            None => None,
        })
    }

    /// Connects, sets the telemetry rate, uploads the table (with --play) and starts the walk:
    /// everything before the first record, and the trial's metadata as far as it is known then.
    fn start(
        &self,
        table: Option<&Table>,
        plan: Option<PlanMeta>,
        perturb: Option<Perturb>,
        folder: &TrialFolder,
    ) -> anyhow::Result<Started> {
        let mut s = self.board.connect()?;
        let substrate = board::port::trial_substrate(s.board.port(), self.substrate.as_deref())?;
        if s.is_virtual() && self.play.is_none() {
            bail!("the virtual robot only walks while dbot runs: give --play SLOT [--steps K]");
        }
        board::record::set_recording_rate(&mut s.board, self.every)
            .with_context(|| format!("--every {}", self.every))?;
        if let (Some(slot), Some(t)) = (self.play, table) {
            playback::upload_table(&mut s, slot, &t.path, &t.bytes)?;
        }
        if let Some(m) =
            perturb.and_then(|p| board::port::platform_port_problem(s.board.port(), p.leg))
        {
            bail!("--perturb: {m}");
        }
        let joints = named_joints(&mut s, table.map(|t| t.bytes.as_slice()), self.play)?;
        // The platform's servo answers (checked by the board) before anything moves; a platform
        // an earlier trial left set up does not move in this one.
        if self.play.is_some() {
            match &perturb {
                Some(p) => s
                    .board
                    .set_platform(p.setup)
                    .map(|()| println!("platform servo ID {}", p.setup.servo_id))
                    .with_context(|| {
                        format!("--perturb {}", self.perturb.as_deref().unwrap_or(""))
                    })?,
                None if s.board.platform()?.is_some() => {
                    s.board.clear_platform().context("clearing the platform")?
                }
                None => {}
            }
        }
        // Calibrated, with its baseline sample in, before the robot moves.
        let strain = match &self.strain {
            Some(p) => {
                println!("strain board on {p}: calibrating");
                // `virtual` beside the physics robot reads the body's simulated gauges.
                let feed = s.board.transport_mut().strain_feed(p);
                let port = s.board.port().to_owned();
                Some(
                    StrainBeside::start_fed(p, &port, folder.work_dir(), feed)
                        .with_context(|| format!("--strain {p}"))?,
                )
            }
            None => None,
        };
        let mut meta = TrialMeta {
            format_version: board::trial::TRIAL_FORMAT,
            folder: String::new(),
            outcome: Outcome::Complete,
            started: folder.started().iso(),
            host_version: env!("CARGO_PKG_VERSION").to_owned(),
            command_line: std::env::args().collect(),
            port: s.board.port().to_owned(),
            firmware: FirmwareMeta::of(s.board.info()),
            settings: BoardSettings::of(&s.board.settings()?),
            gait: table
                .and_then(|t| protocol::GaitTable::parse(&t.bytes).ok())
                .map(|t| GaitMeta::of(&t.header(), t.crc(), None)),
            plan,
            direction: None,
            period_scale: None,
            steps: None,
            substrate,
            strain: strain.is_some(),
            perturbation: perturb.map(|p| p.record()),
            notes: self.notes.clone(),
            joints: joints.iter().map(|j| j.name.clone()).collect(),
            cycles: 0,
            duration_s: 0.0,
            missing_records: 0,
        };
        if let Some(slot) = self.play {
            let (cmd, gait) =
                playback::play_command(&mut s, slot, self.steps, self.period, self.backward)?;
            if interrupt::requested() {
                bail!("interrupted before the walk started: nothing was played or recorded");
            }
            println!("{}", playback::announce(slot, &gait, &cmd));
            meta.gait = Some(GaitMeta::of(&gait.gait.header, gait.gait.crc, Some(slot)));
            meta.direction = Some(cmd.direction);
            meta.period_scale = Some(f64::from(cmd.period_scale) / 1000.0);
            meta.steps = self.steps;
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
        Ok((s, joints, until, meta, strain))
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
    let mut joints = match &table {
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
    };
    if joints.is_empty() {
        joints = (0..s.board.settings()?.joints.len())
            .map(|j| JointMeta::named(format!("J{j}")))
            .collect();
    }
    if joints.is_empty() {
        bail!(
            "{}: the board reports no joints (no gait selected): nothing to record; upload a table and give --play SLOT",
            s.board.port()
        );
    }
    Ok(joints)
}

/// Records the trial `folder` (telemetry.csv, then the plots, README and trial.json) and
/// publishes it; returns a short summary. If the board vanishes or Ctrl-C ends the recording,
/// the rows so far are kept in a trial named so, the plots are drawn from them, and the error
/// says so (after Ctrl-C, once the robot stands).
fn record_trial<T: Transport>(
    board: &mut Board<T>,
    folder: TrialFolder,
    joints: Vec<JointMeta>,
    slices: usize,
    until: Until,
    mut meta: TrialMeta,
    mut strain: Option<StrainBeside>,
) -> anyhow::Result<String> {
    let dir = folder.work_dir().to_owned();
    let csv = dir.join(TELEMETRY_CSV);
    let mut rec =
        Recorder::create(&csv, joints).with_context(|| format!("creating {}", csv.display()))?;
    let bar = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("recording {spinner} {msg}").expect("template is valid"),
    );
    let mut progress = |t: f64| {
        if let Some(s) = strain.as_mut() {
            s.note(t);
        }
        if rec_tick(t) {
            bar.set_message(format!("{t:.1} s of board time"));
            bar.tick();
        }
    };
    let mut result = capture_while(board, &mut rec, until, interrupt::requested, &mut progress);
    let mut stopped = None;
    if matches!(result, Ok(Ended::Interrupted)) {
        bar.println("interrupted: stopping the walk (Ctrl-C again to exit at once)");
        let stop = board::record::stop_walk(board);
        interrupt::release();
        result = match stop {
            Ok(how) => {
                stopped = Some(how);
                capture_until_standing(board, &mut rec, &mut progress)
            }
            Err(e) => Err(CaptureError::Link {
                source: e,
                cycles: rec.cycles(),
            }),
        };
    }
    bar.finish_and_clear();
    let strain = strain.map(StrainBeside::finish);
    if let Err(CaptureError::Write(e)) = &result {
        // A failed write may have left half a row: the folder is not a recording.
        folder.discard();
        bail!("writing {}: {e}", csv.display());
    }
    if rec.rows().is_empty() {
        folder.discard();
        return match result {
            Err(e) => Err(anyhow::Error::new(e).context("no telemetry arrived: no trial kept")),
            Ok(_) => bail!("no telemetry arrived: nothing recorded, no trial kept"),
        };
    }
    meta.outcome = match (&result, stopped) {
        (Err(_), _) => Outcome::Failed,
        (Ok(_), Some(_)) => Outcome::Interrupted,
        (Ok(_), None) => Outcome::Complete,
    };
    meta.cycles = rec.cycles();
    meta.duration_s = rec.duration_s();
    meta.missing_records = missing_cycles(rec.rows());
    let plots = draw(&dir, &rec, slices);
    let path = folder.publish(&mut meta)?;
    let path = path.display();
    if let Err(e) = result {
        return Err(anyhow::Error::new(e)).with_context(|| {
            format!(
                "recording stopped: {} bus cycles kept in the trial {path}",
                rec.cycles()
            )
        });
    }
    plots?;
    let strain_line = match strain {
        None => String::new(),
        Some(end) => strain_summary(end, &path.to_string())?,
    };
    if let Some(how) = stopped {
        let state = board.status().map_or_else(
            |e| format!("unknown ({e})"),
            |st| crate::common::words::state_name(st.state).to_owned(),
        );
        bail!(
            "interrupted: {} and the robot is {state}; {} bus cycles ({:.2} s of board time) \
             kept in the trial {path}",
            how.describe(),
            rec.cycles(),
            rec.duration_s(),
        );
    }
    Ok(format!(
        "recorded {} bus cycles ({:.2} s of board time) x {} joints: trial {path}; {}{strain_line}",
        rec.cycles(),
        rec.duration_s(),
        rec.joints().len(),
        if meta.missing_records == 0 {
            "no telemetry record missing".to_string()
        } else {
            format!(
                "{} telemetry records missing (skipped cycle numbers)",
                meta.missing_records
            )
        }
    ))
}

/// The strain line of the summary, or the error of a strain stream that stopped early (the
/// servo recording is whole in `trial` by then).
fn strain_summary(end: StrainEnd, trial: &str) -> anyhow::Result<String> {
    let clock = match end.clock {
        Ok(Some(f)) => format!(
            "; strain on the board's clock (host {:.6} s per board s, telemetry jitter {:.1} ms \
             at the 95th percentile)",
            f.rate,
            f.jitter_p95_s * 1e3
        ),
        Ok(None) => "; strain not aligned: no telemetry arrived".to_owned(),
        Err(e) => format!("; strain kept on host time: {e}"),
    };
    // The recorder wrote into the unpublished folder: name the file where it is now.
    let csv = Path::new(trial).join(board::strain::recorder::STRAIN_CSV);
    match end.recording {
        Ok(mut r) => {
            r.csv = csv;
            Ok(format!("\n{r}{clock}"))
        }
        Err(mut e) => {
            e.csv = csv;
            bail!("the servo recording is complete in the trial {trial}, but {e}{clock}")
        }
    }
}

/// Whether to refresh the progress line (every tenth of a second of board time).
fn rec_tick(t: f64) -> bool {
    ((t * 100.0).round() as u64).is_multiple_of(10)
}

/// The plots (the trial folder is new: no plot of an earlier recording can be beside them).
fn draw(dir: &Path, rec: &Recorder, slices: usize) -> anyhow::Result<()> {
    replace(dir, "angles.png", |p| {
        plot_angles(p, rec.rows(), rec.joints())
            .map_err(|e| anyhow::anyhow!("plotting angles: {e}"))
    })?;
    if slices > 0 && rec.joints().iter().any(|j| j.model.is_some()) {
        replace(dir, "torque.png", |p| {
            plot_torques(p, rec.rows(), rec.joints(), slices)
                .map_err(|e| anyhow::anyhow!("plotting torques: {e}"))
        })?;
    }
    Ok(())
}
