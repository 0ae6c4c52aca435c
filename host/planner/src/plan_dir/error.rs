//! Why a plan directory could not be read: each error names the file (and the line or field).

use std::path::PathBuf;

use super::ReportError;
use crate::model::ModelError;
use crate::plan::gait_table::TableError;

/// A plan directory that could not be read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlanDirError {
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{file}: no `format_version`: not a plan directory of this format (written by a dbot before plan directory format {expected}?); plan it again with `dbot plan`"
    )]
    NoVersion { file: PathBuf, expected: u32 },
    #[error(
        "{file}: plan directory format_version {found}, this dbot reads format {expected}; plan it again with this dbot"
    )]
    Version {
        file: PathBuf,
        found: u64,
        expected: u32,
    },
    #[error("{file}: {source}")]
    Json {
        file: PathBuf,
        source: serde_json::Error,
    },
    #[error("{file}: {source}")]
    Model { file: PathBuf, source: ModelError },
    #[error("{file}: no `{column}` column{hint}")]
    NoColumn {
        file: PathBuf,
        column: &'static str,
        hint: &'static str,
    },
    /// The planned torques are not in the directory, and `needed_by` needs them.
    #[error(
        "{file}: no `{}` column (written without dynamics, by --no-dynamics or Plan.write(dynamics=False)? {needed_by} needs the torques)",
        super::columns::TORQUE_NM
    )]
    NoTorques {
        file: PathBuf,
        needed_by: &'static str,
    },
    #[error("{file} line {line}: {problem}")]
    Row {
        file: PathBuf,
        line: usize,
        problem: String,
    },
    #[error("{file}: {problem}")]
    Shape { file: PathBuf, problem: String },
    /// The directory contradicts itself (a hand-edited plan.json or feet.csv).
    #[error(
        "{file}: {problem}: the plan directory contradicts itself (edited by hand?); plan it again with `dbot plan`"
    )]
    Disagrees { file: PathBuf, problem: String },
    #[error("writing {file}: {source}")]
    Write { file: PathBuf, source: ReportError },
    #[error("building the step table of {dir}: {source}")]
    Table { dir: PathBuf, source: TableError },
}
