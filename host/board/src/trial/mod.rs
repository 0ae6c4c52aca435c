//! Trial records, as the lab keeps its robot experiments (`../shared/reference/lab-practice.md`):
//! one folder per trial, never reused, named by its start time (UTC, `YYYY-MM-DD HH_MM_SS`),
//! holding the telemetry (`telemetry.csv`), a README for people and `trial.json` for programs
//! ([`TrialMeta`], versioned), and a line per trial in `TRIAL INDEX.txt` (and `trials.jsonl`)
//! beside the folders. A trial is recorded into a hidden `.partial-` folder and published under
//! a name that says how it ended ([`Outcome`]), so a failed or interrupted recording never
//! replaces or passes for a complete one.

mod clock;
mod describe;
mod error;
mod folder;
mod index;
mod meta;
mod read;
mod readme;

pub use clock::UtcSecond;
pub use error::TrialError;
pub use folder::{README_MD, TELEMETRY_CSV, TRIAL_JSON, TrialFolder};
pub use index::{INDEX_JSONL, INDEX_TXT, IndexEntry, latest_trial, list_trials};
pub use meta::{
    BoardSettings, FirmwareMeta, GaitMeta, JointSetting, Outcome, Perturbation, PlanMeta,
    Substrate, TRIAL_FORMAT, TrialFault, TrialMeta,
};
pub use read::{Trial, read_trial};
