//! The run-time settings of a `virtual:PATH` robot, kept beside its store in `PATH.settings.json`.
//!
//! A board keeps what `dbot set` sent until it is powered off; the virtual robot boots afresh at
//! every command, so without this a setting would be gone at the next command. `dbot set` writes
//! the file after changing settings, and every command that opens the robot applies it first.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use board::link::{Board, Transport};

/// What is kept: the bus, the telemetry rate and the stiffness per joint (P gain and torque bias).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KeptSettings {
    /// Bus baud rate, bit/s.
    pub baud: u32,
    /// Bus cycle rate, Hz.
    pub cycle_hz: u16,
    /// Telemetry every this many cycles (0 = off).
    pub telemetry_every: u16,
    /// Servo stiffness per joint, mN m/rad (empty while the robot has no joint map).
    pub stiffness: Vec<u32>,
}

/// The settings file of the store at `store`.
pub fn settings_path(store: &Path) -> PathBuf {
    let mut name = store.as_os_str().to_owned();
    name.push(".settings.json");
    PathBuf::from(name)
}

/// Applies the kept settings of `store`, if any, to a freshly booted virtual robot.
pub fn apply<T: Transport>(board: &mut Board<T>, store: &Path) -> anyhow::Result<()> {
    let path = settings_path(store);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    let kept: KeptSettings =
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
    let now = board.settings()?;
    if (now.baud, now.cycle_hz) != (kept.baud, kept.cycle_hz) {
        board
            .set_bus(kept.baud, kept.cycle_hz)
            .with_context(|| format!("applying the bus settings of {}", path.display()))?;
    }
    if now.telemetry_every != kept.telemetry_every {
        board.set_telemetry(kept.telemetry_every)?;
    }
    // Stiffness is per joint of the joint map, which a freshly booted robot may not have yet.
    if now.joints.len() == kept.stiffness.len() {
        for (j, (&k, cur)) in kept.stiffness.iter().zip(&now.joints).enumerate() {
            if k != cur.stiffness {
                board.set_stiffness(j as u8, k).with_context(|| {
                    format!(
                        "applying the stiffness of joint {j} from {}",
                        path.display()
                    )
                })?;
            }
        }
    }
    Ok(())
}

/// Records the robot's present settings beside `store`.
pub fn save<T: Transport>(board: &mut Board<T>, store: &Path) -> anyhow::Result<()> {
    let s = board.settings()?;
    let kept = KeptSettings {
        baud: s.baud,
        cycle_hz: s.cycle_hz,
        telemetry_every: s.telemetry_every,
        stiffness: s.joints.iter().map(|j| j.stiffness).collect(),
    };
    let path = settings_path(store);
    let json = serde_json::to_string_pretty(&kept)?;
    crate::common::output::replace_file(&path, |p| Ok(std::fs::write(p, &json)?))
}
