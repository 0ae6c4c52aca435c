//! Recording a started trial until it ends (its time, the gait standing, the caller's stop, a
//! fault on the board, a failed link), then its plots, outcome and metadata, and publishing the
//! folder.

use std::cell::RefCell;
use std::path::Path;

use board::record::{
    CaptureError, Ended, Recorder, capture_until_standing, capture_while, missing_cycles,
};
use board::strain::StrainBeside;
use board::trial::{Outcome, TELEMETRY_CSV, TrialFault, TrialFolder};
use physics::Robot;
use report::recording::{plot_angles, plot_torques};

use super::start::{Dropped, Started};
use super::summary::{TrialSummary, strain_summary};
use super::{TrialHooks, library};
use crate::error::{Context, LabError, Result};

/// Records the trial `folder` (telemetry.csv, then the plots, README and trial.json) and
/// publishes it. If the board vanishes, stops the robot on a fault, or the caller stops the
/// recording, the rows so far are kept in a trial named so, the plots are drawn from them, and
/// the error says so (after a stop, once the robot stands; after a fault:
/// [`LabError::Faulted`], naming the fault, its joint and cycle).
pub(super) fn record(
    board: &mut Robot,
    folder: TrialFolder,
    started: Started,
    hooks: &mut dyn TrialHooks,
) -> Result<TrialSummary> {
    let Started {
        joints,
        until,
        mut meta,
        strain,
        slices,
        dropped_before,
    } = started;
    let dir = folder.work_dir().to_owned();
    let csv = dir.join(TELEMETRY_CSV);
    let mut rec =
        Recorder::create(&csv, joints).with_context(|| format!("creating {}", csv.display()))?;
    // The stop question and the progress both reach the caller, one after the other.
    let door = RefCell::new((hooks, strain));
    let progress = |t: f64| {
        let (hooks, strain) = &mut *door.borrow_mut();
        if let Some(s) = strain.as_mut() {
            s.note(t);
        }
        hooks.progress(t);
    };
    let mut result = capture_while(
        board,
        &mut rec,
        until,
        || door.borrow_mut().0.should_stop(),
        progress,
    );
    let mut stopped = None;
    if matches!(result, Ok(Ended::Interrupted)) {
        door.borrow_mut().0.stopping();
        let stop = board::record::stop_walk(board);
        door.borrow_mut().0.stop_asked();
        result = match stop {
            Ok(how) => {
                stopped = Some(how);
                capture_until_standing(board, &mut rec, progress)
            }
            Err(e) => Err(CaptureError::Link {
                source: e,
                cycles: rec.cycles(),
            }),
        };
    }
    let (_, strain) = door.into_inner();
    let strain = strain.map(StrainBeside::finish);
    if let Err(CaptureError::Write(e)) = &result {
        // A failed write may have left half a row: the folder is not a recording.
        folder.discard();
        crate::bail!("writing {}: {e}", csv.display());
    }
    if rec.rows().is_empty() {
        folder.discard();
        return match result {
            Err(e) => Err(e).context("no telemetry arrived: no trial kept"),
            Ok(_) => crate::bail!("no telemetry arrived: nothing recorded, no trial kept"),
        };
    }
    let fault = match &result {
        Ok(Ended::Faulted(seen)) => Some(*seen),
        _ => None,
    };
    meta.outcome = match (&result, stopped) {
        (Err(_), _) => Outcome::Failed,
        (Ok(Ended::Faulted(_)), _) => Outcome::Faulted,
        (Ok(_), Some(_)) => Outcome::Interrupted,
        (Ok(_), None) => Outcome::Complete,
    };
    meta.fault = fault.map(|seen| TrialFault {
        kind: seen
            .fault
            .map_or("unknown".to_owned(), |f| f.kind.name().to_owned()),
        reason: seen.fault.map_or_else(
            || "a fault, cleared before it could be read".to_owned(),
            |f| f.to_string(),
        ),
        joint: seen.fault.and_then(|f| f.joint),
        joint_name: seen
            .fault
            .and_then(|f| f.joint)
            .and_then(|j| rec.joints().get(usize::from(j)))
            .map(|j| j.name.clone()),
        cycle: seen.cycle,
    });
    meta.cycles = rec.cycles();
    meta.duration_s = rec.duration_s();
    meta.missing_records = missing_cycles(rec.rows());
    // Unknown when the link failed: the board's counter cannot be read.
    meta.lost_records = match &result {
        Ok(_) => Dropped::now(board)
            .ok()
            .map(|after| dropped_before.since(after)),
        Err(_) => None,
    };
    let plots = draw(&dir, &rec, slices);
    let path = folder.publish(&mut meta).map_err(library)?;
    let shown = path.display().to_string();
    if let Err(e) = result {
        return Err(e).with_context(|| {
            format!(
                "recording stopped: {} bus cycles kept in the trial {shown}",
                rec.cycles()
            )
        });
    }
    plots?;
    let strain = strain.map(|end| strain_summary(end, &shown)).transpose()?;
    if let (Some(seen), Some(f)) = (fault, &meta.fault) {
        return Err(LabError::Faulted(format!(
            "{seen}{}; {} bus cycles ({:.2} s of board time) kept in the trial {shown}; \
             `dbot status` shows the fault, `dbot set --clear-fault` clears it (Python: \
             Board.status(), Board.clear_fault())",
            f.joint_name
                .as_ref()
                .map_or(String::new(), |n| format!(" (joint {n})")),
            rec.cycles(),
            rec.duration_s(),
        )));
    }
    if let Some(how) = stopped {
        let state = board.status().map_or_else(
            |e| format!("unknown ({e})"),
            |st| st.state.name().to_owned(),
        );
        return Err(LabError::Interrupted(format!(
            "interrupted: {} and the robot is {state}; {} bus cycles ({:.2} s of board time) \
             kept in the trial {shown}",
            how.describe(),
            rec.cycles(),
            rec.duration_s(),
        )));
    }
    Ok(TrialSummary {
        path,
        cycles: rec.cycles(),
        duration_s: rec.duration_s(),
        joints: rec.joints().len(),
        missing_records: meta.missing_records,
        lost_records: meta.lost_records,
        strain,
    })
}

/// The plots (the trial folder is new: no plot of an earlier recording can be beside them).
fn draw(dir: &Path, rec: &Recorder, slices: usize) -> Result<()> {
    let angles = dir.join("angles.png");
    board::files::write_atomically(&angles, |p| {
        plot_angles(p, rec.rows(), rec.joints()).map_err(|e| format!("plotting angles: {e}").into())
    })
    .with_context(|| format!("writing {}", angles.display()))?;
    if slices > 0 && rec.joints().iter().any(|j| j.model.is_some()) {
        let torque = dir.join("torque.png");
        board::files::write_atomically(&torque, |p| {
            plot_torques(p, rec.rows(), rec.joints(), slices)
                .map_err(|e| format!("plotting torques: {e}").into())
        })
        .with_context(|| format!("writing {}", torque.display()))?;
    }
    Ok(())
}
