//! The run-time settings of a `virtual:PATH` robot, kept beside its store in `PATH.settings.json`.
//!
//! A board keeps what `dbot set` sent until it is powered off; the virtual robot boots afresh at
//! every opening, so without this a setting would be gone at the next command. [`save`] writes
//! the file after settings changed (`dbot set` calls it); the port opener
//! ([`crate::port::connect`]) applies it at every opening, so `dbot` and Python see the same robot.

use std::path::{Path, PathBuf};

use crate::files::FileError;
use crate::link::{Board, LinkError, Transport};

/// What is kept: the bus, the telemetry rate and the stiffness per joint (P gain and torque bias).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SavedSettings {
    /// Bus baud rate, bit/s.
    pub baud: u32,
    /// Bus cycle rate, Hz.
    pub cycle_hz: u16,
    /// Telemetry every this many cycles (0 = off).
    pub telemetry_every: u16,
    /// Servo stiffness per joint, mN m/rad (empty while the robot has no joint map).
    pub stiffness: Vec<u32>,
}

/// Why saved settings could not be read, applied or written; each names the settings file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SettingsError {
    #[error("reading {path}: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} is not a settings file of the virtual robot: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("applying {what} from {path}: {source}")]
    Apply {
        path: PathBuf,
        what: String,
        #[source]
        source: LinkError,
    },
    /// A kept stiffness the rule refuses (the file was edited, or kept by an older dbot).
    #[error("{path}: the stiffness of joint {joint}: {source}")]
    Stiffness {
        path: PathBuf,
        joint: usize,
        source: crate::rules::stiffness::StiffnessError,
    },
    #[error("reading the settings to save in {path}: {source}")]
    Query {
        path: PathBuf,
        #[source]
        source: LinkError,
    },
    #[error(transparent)]
    Write(#[from] FileError),
}

/// The settings file of the store at `store`.
pub fn settings_path(store: &Path) -> PathBuf {
    let mut name = store.as_os_str().to_owned();
    name.push(".settings.json");
    PathBuf::from(name)
}

/// The settings saved beside `store` (`None`: nothing was saved).
pub fn load(store: &Path) -> Result<Option<SavedSettings>, SettingsError> {
    let path = settings_path(store);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(SettingsError::Read { path, source }),
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|e| SettingsError::Parse {
            path,
            message: e.to_string(),
        })
}

/// Applies the settings saved beside `store`, if any, to a freshly booted virtual robot.
pub fn apply<T: Transport>(board: &mut Board<T>, store: &Path) -> Result<(), SettingsError> {
    let Some(kept) = load(store)? else {
        return Ok(());
    };
    let path = settings_path(store);
    let failed = |what: String| {
        let path = path.clone();
        move |source| SettingsError::Apply { path, what, source }
    };
    let now = board.settings().map_err(failed(
        "nothing (the robot's settings could not be read)".into(),
    ))?;
    if (now.baud, now.cycle_hz) != (kept.baud, kept.cycle_hz) {
        board
            .set_bus(kept.baud, kept.cycle_hz)
            .map_err(failed("the bus settings".into()))?;
    }
    if now.telemetry_every != kept.telemetry_every {
        board
            .set_telemetry(kept.telemetry_every)
            .map_err(failed("the telemetry rate".into()))?;
    }
    // Stiffness is per joint of the joint map, which a freshly booted robot may not have yet.
    if now.joints.len() == kept.stiffness.len() {
        for (j, (&k, cur)) in kept.stiffness.iter().zip(&now.joints).enumerate() {
            if k != cur.stiffness {
                let k = crate::rules::stiffness::Stiffness::of_units(k).map_err(|source| {
                    SettingsError::Stiffness {
                        path: path.clone(),
                        joint: j,
                        source,
                    }
                })?;
                board
                    .set_stiffness(j as u8, k)
                    .map_err(failed(format!("the stiffness of joint {j}")))?;
            }
        }
    }
    Ok(())
}

/// Records the robot's present settings beside `store` (one atomic write: a crash leaves the
/// previous file).
pub fn save<T: Transport>(board: &mut Board<T>, store: &Path) -> Result<(), SettingsError> {
    let path = settings_path(store);
    let s = board.settings().map_err(|source| SettingsError::Query {
        path: path.clone(),
        source,
    })?;
    let kept = SavedSettings {
        baud: s.baud,
        cycle_hz: s.cycle_hz,
        telemetry_every: s.telemetry_every,
        stiffness: s.joints.iter().map(|j| j.stiffness).collect(),
    };
    let json = serde_json::to_string_pretty(&kept).expect("plain numbers serialise");
    Ok(crate::files::write_bytes_atomically(
        &path,
        json.as_bytes(),
    )?)
}
