//! The trial index beside the trial folders: `TRIAL INDEX.txt`, one line per trial for people
//! (as the lab keeps it), and `trials.jsonl`, the same as one JSON object per line for programs.
//! Both are append-only logs: each line is written with one `write` to a file opened for
//! appending, so a kill leaves every earlier line whole (at worst the last line is missing).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::TrialError;
use super::meta::{Outcome, TrialMeta};

/// The human index file.
pub const INDEX_TXT: &str = "TRIAL INDEX.txt";
/// The machine index file.
pub const INDEX_JSONL: &str = "trials.jsonl";

/// One trial in `trials.jsonl`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct IndexEntry {
    /// The trial's folder, relative to the index.
    pub folder: String,
    pub outcome: Outcome,
    pub started: String,
    pub gait: Option<String>,
}

/// The index's line for a trial.
fn line(meta: &TrialMeta) -> String {
    let gait = meta.gait.as_ref().map_or("gait unknown".to_owned(), |g| {
        format!("gait {} (CRC {:08x})", g.name, g.crc)
    });
    let walk = match (meta.direction, meta.period_scale) {
        (Some(d), Some(s)) => format!("{}, period x{s:.3}", d.name()),
        _ => "walk not started by dbot record".to_owned(),
    };
    let perturbation = meta.perturbation.as_ref().map_or("none".to_owned(), |p| {
        format!("{} at step {}", p.leg, p.step)
    });
    let notes = meta.notes.replace(['\n', '\r', '\t'], " ");
    format!(
        "{}\t{}\t{gait}\t{walk}\tsubstrate {}\tstrain {}\tperturbation {perturbation}\t{notes}\n",
        meta.folder,
        meta.outcome.name(),
        meta.substrate.name(),
        if meta.strain { "yes" } else { "no" },
    )
}

fn append(path: &Path, text: &str) -> Result<(), TrialError> {
    let write = || -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()
    };
    write().map_err(|e| TrialError::Write {
        path: path.to_owned(),
        source: e.into(),
    })
}

/// Appends `meta`'s trial to both indexes in `parent`.
pub(super) fn append_index(parent: &Path, meta: &TrialMeta) -> Result<(), TrialError> {
    let entry = IndexEntry {
        folder: meta.folder.clone(),
        outcome: meta.outcome,
        started: meta.started.clone(),
        gait: meta.gait.as_ref().map(|g| g.name.clone()),
    };
    let json = serde_json::to_string(&entry).map_err(|e| TrialError::Write {
        path: parent.join(INDEX_JSONL),
        source: e.into(),
    })?;
    append(&parent.join(INDEX_TXT), &line(meta))?;
    append(&parent.join(INDEX_JSONL), &format!("{json}\n"))
}

/// The trials indexed in `parent`, oldest first (an empty list when there is no index yet).
pub fn list_trials(parent: &Path) -> Result<Vec<IndexEntry>, TrialError> {
    let path = parent.join(INDEX_JSONL);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(source) => return Err(TrialError::Read { path, source }),
    };
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l).map_err(|e| TrialError::Csv {
                path: path.clone(),
                line: i + 1,
                what: e.to_string(),
            })
        })
        .collect()
}

/// The folder of the last trial indexed in `parent`.
pub fn latest_trial(parent: &Path) -> Result<Option<PathBuf>, TrialError> {
    Ok(list_trials(parent)?.pop().map(|e| parent.join(e.folder)))
}
