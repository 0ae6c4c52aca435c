//! Why a trial could not be begun, published or read. Each names the folder or file.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TrialError {
    #[error(
        "trial folder {folder} exists: a trial never reuses a folder (give another --trial \
         name, or none: a new folder is named by the start time)"
    )]
    Taken { folder: PathBuf },
    #[error("trial name {name:?}: {why}")]
    BadName { name: String, why: &'static str },
    #[error("cannot create the trial folder {folder}: {source}")]
    Create {
        folder: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} is not a folder of trials (it is a file)")]
    NotAFolder { path: PathBuf },
    #[error("writing {path}: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    #[error("reading {path}: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a trial.json this build reads: {source}")]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    #[error(
        "{path}: trial format version {found}, this build reads version {expected} (read it with \
         the dbot that wrote it)"
    )]
    Version {
        path: PathBuf,
        found: u32,
        expected: u32,
    },
    #[error("the plan the step table came from: {source}")]
    Plan {
        #[source]
        source: planner::plan_dir::PlanDirError,
    },
    #[error("{path}, line {line}: {what}")]
    Csv {
        path: PathBuf,
        line: usize,
        what: String,
    },
}
