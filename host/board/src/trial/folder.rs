//! A trial's folder, from its start to its publication: the recording is written into
//! `PARENT/.partial-NAME` (so no reader takes a trial for finished while it is recorded), which
//! is renamed to `PARENT/NAME` when the recording ends as asked, `NAME interrupted` after Ctrl-C
//! and `NAME failed` when the link failed, never over an existing folder; a recording without a
//! single row is removed. NAME is the start time, UTC, as the lab names trials
//! (`YYYY-MM-DD HH_MM_SS`), with ` (2)`, ` (3)`, ... when a trial of that second exists.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use super::clock::UtcSecond;
use super::error::TrialError;
use super::index::append_index;
use super::meta::{Outcome, TrialMeta};
use super::readme::readme;
use crate::files::{self, FileError};

/// The metadata file of a trial folder.
pub const TRIAL_JSON: &str = "trial.json";
/// The telemetry of a trial folder.
pub const TELEMETRY_CSV: &str = "telemetry.csv";
/// The human README of a trial folder.
pub const README_MD: &str = "README.md";

/// A trial being recorded.
#[derive(Debug)]
pub struct TrialFolder {
    parent: PathBuf,
    name: String,
    work: PathBuf,
    started: UtcSecond,
}

/// Whether a trial named `name` (in any outcome, or being recorded) exists in `parent`.
fn taken(parent: &Path, name: &str) -> bool {
    let names = [
        name.to_owned(),
        format!("{name} interrupted"),
        format!("{name} failed"),
        format!(".partial-{name}"),
    ];
    names
        .iter()
        .any(|n| parent.join(n).symlink_metadata().is_ok())
}

/// Refuses a trial name that is not one folder name a user can read and type.
fn check_name(name: &str) -> Result<(), TrialError> {
    let bad = |why| {
        Err(TrialError::BadName {
            name: name.to_owned(),
            why,
        })
    };
    if name.trim().is_empty() {
        return bad("empty");
    }
    if name.starts_with('.') {
        return bad("starts with '.' (hidden, and the prefix of folders being recorded)");
    }
    if name.contains('/') || name.chars().any(char::is_control) {
        return bad("holds '/' or a control character: give one folder name");
    }
    Ok(())
}

impl TrialFolder {
    /// Begins a trial in `parent` (created if missing): named `name`, or by `started` when
    /// `None`. A named trial that exists, a parent that is a file or where no folder can be
    /// created is refused here, before the caller moves anything.
    pub fn begin(
        parent: &Path,
        name: Option<&str>,
        started: SystemTime,
    ) -> Result<Self, TrialError> {
        let started = UtcSecond::of(started);
        if parent.is_file() {
            return Err(TrialError::NotAFolder {
                path: parent.to_owned(),
            });
        }
        std::fs::create_dir_all(parent).map_err(|source| TrialError::Create {
            folder: parent.to_owned(),
            source,
        })?;
        let name = match name {
            Some(n) => {
                check_name(n)?;
                if taken(parent, n) {
                    return Err(TrialError::Taken {
                        folder: parent.join(n),
                    });
                }
                n.to_owned()
            }
            None => {
                let base = started.folder_name();
                (1..)
                    .map(|k| match k {
                        1 => base.clone(),
                        k => format!("{base} ({k})"),
                    })
                    .find(|n| !taken(parent, n))
                    .expect("some suffix is free")
            }
        };
        let work = parent.join(format!(".partial-{name}"));
        // create_dir, not create_dir_all: two recorders never share a folder.
        std::fs::create_dir(&work).map_err(|source| match source.kind() {
            std::io::ErrorKind::AlreadyExists => TrialError::Taken {
                folder: parent.join(&name),
            },
            _ => TrialError::Create {
                folder: work.clone(),
                source,
            },
        })?;
        Ok(Self {
            parent: parent.to_owned(),
            name,
            work,
            started,
        })
    }

    /// The folder the recording is written into until [`TrialFolder::publish`].
    pub fn work_dir(&self) -> &Path {
        &self.work
    }

    /// The trial's name (its folder's, less any outcome word).
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn started(&self) -> UtcSecond {
        self.started
    }

    /// The folder the trial gets when it ends with `outcome`.
    pub fn final_path(&self, outcome: Outcome) -> PathBuf {
        self.parent.join(folder_name(&self.name, outcome))
    }

    /// Writes trial.json and README.md (`meta.folder` and `meta.outcome` set here), renames the
    /// folder to its final name and appends the trial to the index beside it. Returns the folder.
    pub fn publish(self, meta: &mut TrialMeta) -> Result<PathBuf, TrialError> {
        meta.folder = folder_name(&self.name, meta.outcome);
        write(&self.work.join(TRIAL_JSON), meta.to_json().as_bytes())?;
        write(&self.work.join(README_MD), readme(meta).as_bytes())?;
        let done = self.parent.join(&meta.folder);
        files::rename_new(&self.work, &done).map_err(|e| TrialError::Write {
            path: done.clone(),
            source: e.into(),
        })?;
        append_index(&self.parent, meta)?;
        Ok(done)
    }

    /// Removes the folder of a trial that recorded nothing.
    pub fn discard(self) {
        let _ = std::fs::remove_dir_all(&self.work);
    }
}

fn folder_name(name: &str, outcome: Outcome) -> String {
    match outcome.suffix() {
        Some(word) => format!("{name} {word}"),
        None => name.to_owned(),
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), TrialError> {
    files::write_bytes_atomically(path, bytes).map_err(|e: FileError| TrialError::Write {
        path: path.to_owned(),
        source: e.into(),
    })
}
