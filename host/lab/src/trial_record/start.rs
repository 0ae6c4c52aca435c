//! Everything of a trial before its first record: the telemetry rate, the table uploaded, the
//! joints named, the platform set up (or a stale one cleared), the strain board calibrated, the
//! metadata as far as it is known then, and the walk started.

use board::record::{JointMeta, Until};
use board::strain::StrainBeside;
use board::trial::{BoardSettings, FirmwareMeta, GaitMeta, Outcome, TrialFolder, TrialMeta};
use physics::{Robot, RobotLink};

use super::check::Checked;
use super::{TrialHooks, TrialRequest, joints, library, playback};
use crate::error::{Context, Result};

/// Everything before the first record.
pub(super) struct Started {
    pub joints: Vec<JointMeta>,
    pub until: Until,
    pub meta: TrialMeta,
    pub strain: Option<StrainBeside>,
    /// Slices per step of the table (0 without one): the torque plot's phase axis.
    pub slices: usize,
    /// Telemetry records dropped so far on the board and on the host: what the recording's lost
    /// records are counted from.
    pub dropped_before: Dropped,
}

/// Telemetry records dropped since boot on the board (its queue full) and since the link opened
/// on the host (its backlog full).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Dropped {
    pub board: u32,
    pub host: u64,
}

impl Dropped {
    /// The counts now (asks the board).
    pub fn now(board: &mut Robot) -> std::result::Result<Self, board::link::LinkError> {
        Ok(Self {
            board: board.status()?.counters.telemetry_dropped,
            host: board.telemetry_dropped(),
        })
    }

    /// Records dropped between `self` and `later`.
    pub fn since(self, later: Self) -> u64 {
        u64::from(later.board.wrapping_sub(self.board)) + later.host.saturating_sub(self.host)
    }
}

/// Sets the telemetry rate, uploads the table (with `play`) and starts the walk.
pub(super) fn start(
    board: &mut Robot,
    request: &TrialRequest,
    checked: &Checked<'_>,
    folder: &TrialFolder,
    hooks: &mut dyn TrialHooks,
) -> Result<Started> {
    let substrate = board::port::trial_substrate(board.port(), request.substrate.as_deref())
        .map_err(library)?;
    let play = request.play;
    if matches!(board.transport(), RobotLink::Virtual(_)) && play.is_none() {
        crate::bail!(
            "the virtual robot only walks while the trial records: give --play SLOT [--steps K] (Python: play=SLOT, steps=K)"
        );
    }
    board::record::set_recording_rate(board, request.every)
        .with_context(|| format!("every {}", request.every))?;
    if let (Some(p), Some(t)) = (play, &request.table) {
        let overrides = board::rules::Overrides {
            allow_infeasible: p.allow_infeasible,
        };
        let (line, warning) = playback::upload_table(
            board,
            p.slot,
            &t.path,
            &t.bytes,
            &request.model,
            overrides,
            || hooks.should_stop(),
        )?;
        if let Some(w) = warning {
            hooks.warn(&w);
        }
        if let Some(line) = line {
            hooks.say(&line);
        }
    }
    // The walk to start, checked before anything moves: a period shorter than planned must be
    // one the servos can follow (the rule of `dbot run --period` and `Board.play`).
    let walk = match play {
        Some(p) => {
            let (command, gait) =
                playback::play_command(board, p.slot, p.steps, p.period, p.backward)?;
            let known = match (&request.table, &request.held_table) {
                (Some(t), _) => Some(t.bytes.clone()),
                (None, Some(held)) => Some(held.clone()),
                (None, None) => {
                    board::rules::period::table_of_port(board.port(), p.slot).map_err(library)?
                }
            };
            let overrides = board::rules::Overrides {
                allow_infeasible: p.allow_infeasible,
            };
            let checked = board::rules::period::check_play(
                board,
                command,
                known.as_deref(),
                &request.model,
                overrides,
            )
            .map_err(library)?;
            if let Some(w) = checked.warning() {
                hooks.warn(w);
            }
            Some((p, checked, gait))
        }
        None => None,
    };
    // A physics robot without the platform under that leg cannot move it: said before anything
    // moves, naming the port spec to use.
    if let Some(m) = checked
        .perturb
        .and_then(|p| board::port::platform_port_problem(board.port(), p.leg))
    {
        crate::bail!("perturb: {m}");
    }
    let mut joints = joints::named_joints(
        board,
        &request.model,
        checked.table.as_ref(),
        play.map(|p| p.slot),
    )?;
    // The platform's servo answers (checked by the board) before anything moves; a platform an
    // earlier trial left set up does not move in this one.
    if play.is_some() {
        match &checked.perturb {
            Some(p) => {
                board.set_platform(p.setup).with_context(|| {
                    format!("perturb {}", request.perturb.as_deref().unwrap_or(""))
                })?;
                hooks.say(&format!("platform servo ID {}", p.setup.servo_id));
            }
            None if board.platform()?.is_some() => {
                board.clear_platform().context("clearing the platform")?
            }
            None => {}
        }
    }
    // Calibrated, with its baseline sample in, before the robot moves.
    let strain = match &request.strain {
        Some(p) => {
            hooks.say(&format!("strain board on {p}: calibrating"));
            // `virtual` beside the physics robot reads the body's simulated gauges.
            let feed = board.transport_mut().strain_feed(p);
            let port = board.port().to_owned();
            Some(
                StrainBeside::start_fed(p, &port, folder.work_dir(), feed)
                    .with_context(|| format!("strain board {p}"))?,
            )
        }
        None => None,
    };
    let mut meta = TrialMeta {
        format_version: board::trial::TRIAL_FORMAT,
        folder: String::new(),
        outcome: Outcome::Complete,
        fault: None,
        started: folder.started().iso(),
        host_version: env!("CARGO_PKG_VERSION").to_owned(),
        command_line: request.command_line.clone(),
        port: board.port().to_owned(),
        firmware: FirmwareMeta::of(board.info()),
        // Read again once the walk has started (below).
        settings: BoardSettings::of(&board.settings()?),
        gait: checked
            .table
            .as_ref()
            .map(|t| GaitMeta::of(&t.header(), t.crc(), None)),
        plan: checked.plan.clone(),
        direction: None,
        period_scale: None,
        steps: None,
        substrate,
        strain: strain.is_some(),
        perturbation: checked.perturb.map(|p| p.record()),
        notes: request.notes.clone(),
        joints: joints.iter().map(|j| j.name.clone()).collect(),
        cycles: 0,
        duration_s: 0.0,
        missing_records: 0,
        lost_records: None,
    };
    let dropped_before = Dropped::now(board)?;
    if let Some((p, checked, gait)) = walk {
        let cmd = *checked.command();
        if hooks.should_stop() {
            crate::bail!("interrupted before the walk started: nothing was played or recorded");
        }
        hooks.say(&playback::announce(p.slot, &gait, &cmd));
        meta.gait = Some(GaitMeta::of(&gait.gait.header, gait.gait.crc, Some(p.slot)));
        meta.direction = Some(cmd.direction);
        meta.period_scale = Some(f64::from(cmd.period_scale) / 1000.0);
        meta.steps = p.steps;
        board.discard_telemetry();
        board
            .play(&checked)
            .with_context(|| format!("playing slot {}", p.slot))?;
    }
    // The settings the walk runs with (playing a new table takes its stiffness, a table already
    // selected keeps `dbot set --stiffness`): what planned_rad subtracts the bias at.
    let settings = board.settings()?;
    meta.settings = BoardSettings::of(&settings);
    board::record::held_stiffness(&mut joints, &settings);
    let until = Until {
        seconds: request.seconds.or(match play {
            Some(p) if p.steps.is_some() => None,
            _ => Some(10.0),
        }),
        standing: play.is_some(),
    };
    Ok(Started {
        joints,
        until,
        meta,
        strain,
        slices: checked.table.as_ref().map_or(0, |t| t.slice_count()),
        dropped_before,
    })
}
