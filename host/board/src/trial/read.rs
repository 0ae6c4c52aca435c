//! Reading a trial folder back: its trial.json and its telemetry.csv as rows, the joint of each
//! row by its name in trial.json's joint list.

use std::path::{Path, PathBuf};

use super::error::TrialError;
use super::folder::{TELEMETRY_CSV, TRIAL_JSON};
use super::meta::{TRIAL_FORMAT, TrialMeta};
use crate::record::{
    CSV_HEADER, CSV_HEADER_BEFORE_HEALTH, CSV_HEADER_BEFORE_PLATFORM, CSV_HEADER_BEFORE_RUN_STATE,
    Row,
};
use protocol::RunState;

/// A trial read back.
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    pub path: PathBuf,
    pub meta: TrialMeta,
    /// One per bus cycle and joint, in the file's order.
    pub rows: Vec<Row>,
}

/// Reads the trial folder `path`.
pub fn read_trial(path: &Path) -> Result<Trial, TrialError> {
    let json_path = path.join(TRIAL_JSON);
    let text = std::fs::read(&json_path).map_err(|source| TrialError::Read {
        path: json_path.clone(),
        source,
    })?;
    #[derive(serde::Deserialize)]
    struct Version {
        format_version: u32,
    }
    let v: Version = serde_json::from_slice(&text).map_err(|source| TrialError::Json {
        path: json_path.clone(),
        source,
    })?;
    if v.format_version != TRIAL_FORMAT {
        return Err(TrialError::Version {
            path: json_path,
            found: v.format_version,
            expected: TRIAL_FORMAT,
        });
    }
    let meta: TrialMeta = serde_json::from_slice(&text).map_err(|source| TrialError::Json {
        path: json_path.clone(),
        source,
    })?;
    let rows = read_rows(&path.join(TELEMETRY_CSV), &meta.joints)?;
    Ok(Trial {
        path: path.to_owned(),
        meta,
        rows,
    })
}

/// The rows of a telemetry CSV whose joints are named `joints`.
fn read_rows(path: &Path, joints: &[String]) -> Result<Vec<Row>, TrialError> {
    let text = std::fs::read_to_string(path).map_err(|source| TrialError::Read {
        path: path.to_owned(),
        source,
    })?;
    let bad = |line: usize, what: String| TrialError::Csv {
        path: path.to_owned(),
        line,
        what,
    };
    let mut lines = text.lines().enumerate();
    let header = lines.next().map(|(_, l)| l).unwrap_or_default();
    // A trial written before the platform's, the run state's or the heat and supply columns:
    // what they hold is unknown.
    let columns = if header == CSV_HEADER.join(",") {
        CSV_HEADER.len()
    } else if header == CSV_HEADER[..CSV_HEADER_BEFORE_HEALTH].join(",") {
        CSV_HEADER_BEFORE_HEALTH
    } else if header == CSV_HEADER[..CSV_HEADER_BEFORE_RUN_STATE].join(",") {
        CSV_HEADER_BEFORE_RUN_STATE
    } else if header == CSV_HEADER[..CSV_HEADER_BEFORE_PLATFORM].join(",") {
        CSV_HEADER_BEFORE_PLATFORM
    } else {
        return Err(bad(
            1,
            format!("the header is not `{}`", CSV_HEADER.join(",")),
        ));
    };
    lines
        .map(|(i, l)| {
            let line = i + 1;
            let cells: Vec<&str> = l.split(',').collect();
            if cells.len() != columns {
                return Err(bad(
                    line,
                    format!("{} cells, expected {columns}", cells.len()),
                ));
            }
            let cell = |k: usize| cells[k];
            let num = |k: usize| -> Result<f64, TrialError> {
                cell(k).parse().map_err(|_| {
                    bad(
                        line,
                        format!("column {}: {:?} is not a number", CSV_HEADER[k], cell(k)),
                    )
                })
            };
            let opt = |k: usize| -> Result<Option<f64>, TrialError> {
                if cell(k).is_empty() {
                    Ok(None)
                } else {
                    num(k).map(Some)
                }
            };
            let int = |k: usize| -> Result<i64, TrialError> {
                cell(k).parse().map_err(|_| {
                    bad(
                        line,
                        format!("column {}: {:?} is not an integer", CSV_HEADER[k], cell(k)),
                    )
                })
            };
            fn fit<T: TryFrom<i64>>(v: i64) -> Option<T> {
                T::try_from(v).ok()
            }
            let ranged = |k: usize, v: Option<i64>| {
                let v = v.unwrap_or_default();
                bad(
                    line,
                    format!("column {}: {v} is out of range", CSV_HEADER[k]),
                )
            };
            // Empty (or not written at all): no platform set up.
            let tick = |k: usize| -> Result<Option<u16>, TrialError> {
                match cells.get(k) {
                    None | Some(&"") => Ok(None),
                    Some(_) => fit(int(k)?).map(Some).ok_or_else(|| ranged(k, int(k).ok())),
                }
            };
            let joint = joints.iter().position(|n| n == cell(4)).ok_or_else(|| {
                bad(
                    line,
                    format!("joint {:?} is not one of trial.json's joints", cell(4)),
                )
            })?;
            Ok(Row {
                time_s: num(0)?,
                cycle: fit(int(1)?).ok_or_else(|| ranged(1, int(1).ok()))?,
                step: fit(int(2)?).ok_or_else(|| ranged(2, int(2).ok()))?,
                slice: fit(int(3)?).ok_or_else(|| ranged(3, int(3).ok()))?,
                joint,
                planned_rad: opt(5)?,
                // Empty while torque is off: no goal was driven.
                commanded_rad: opt(6)?.unwrap_or(f64::NAN),
                present_rad: num(7)?,
                velocity_rad_s: num(8)?,
                load_raw: fit(int(9)?).ok_or_else(|| ranged(9, int(9).ok()))?,
                torque_estimate_nm: opt(10)?,
                modelled_nm: opt(11)?,
                error: fit(int(12)?).ok_or_else(|| ranged(12, int(12).ok()))?,
                flags: fit(int(13)?).ok_or_else(|| ranged(13, int(13).ok()))?,
                bus_cycle_us: fit(int(14)?).ok_or_else(|| ranged(14, int(14).ok()))?,
                platform_goal_ticks: tick(15)?,
                platform_present_ticks: tick(16)?,
                state: match cells.get(17) {
                    None => None,
                    Some(name) => Some(run_state(name).ok_or_else(|| {
                        bad(
                            line,
                            format!("column run_state: {name:?} is not a board run state"),
                        )
                    })?),
                },
                temperature_c: match cells.get(18) {
                    None | Some(&"") => None,
                    Some(_) => Some(fit(int(18)?).ok_or_else(|| ranged(18, int(18).ok()))?),
                },
                input_voltage_v: match cells.get(19) {
                    None | Some(&"") => None,
                    Some(_) => Some(num(19)?),
                },
            })
        })
        .collect()
}

/// The run state `dbot record` writes as `name` ([`RunState::key`]).
fn run_state(name: &str) -> Option<RunState> {
    [
        RunState::Idle,
        RunState::Standing,
        RunState::Ramping,
        RunState::Walking,
        RunState::Stopping,
        RunState::Streaming,
        RunState::Fault,
        RunState::Boot,
    ]
    .into_iter()
    .find(|s| s.key() == name)
}
