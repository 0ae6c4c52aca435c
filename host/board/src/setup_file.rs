//! The robot setup file (TOML): which port, bus baud and cycle rate, servo stiffness and model, so
//! that daily use is `dbot run --slot 1`. `dbot`'s flags override the file.
//!
//! ```toml
//! port = "/dev/ttyACM0"      # or "virtual", "virtual:out/robot.flash"
//! baud = 1000000             # Dynamixel bus, bit/s
//! rate = 100                 # bus cycles per second, Hz
//! stiffness = 8.4            # servo stiffness (P gain and torque bias), N m/rad (all joints)
//! model = "drosophibot2"     # robot model for plans and tables
//! slot = 1                   # default gait slot
//! ```
//!
//! Paths in the file (`virtual:PATH`, a device or link path, a model .toml/.aproj) are relative to
//! the file's folder, not to where `dbot` runs.
//!
//! Looked up at `--config PATH`, else `$DBOT_CONFIG`, else `./dbot.toml`, else
//! `$XDG_CONFIG_HOME/dbot/config.toml` (`~/.config/dbot/config.toml`). No file is fine: every field
//! has a default or a flag.

use std::path::{Path, PathBuf};

/// A robot setup. Every field is optional; missing ones take the flag or the built-in default.
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    /// Board port: a serial device path, `virtual` or `virtual:PATH`.
    pub port: Option<String>,
    /// Dynamixel bus baud rate, bit/s.
    pub baud: Option<u32>,
    /// Bus cycle rate, Hz.
    pub rate: Option<u16>,
    /// Servo stiffness (the servos' P gain and the torque bias's divisor), N m/rad.
    pub stiffness: Option<f64>,
    /// Robot model name (or path of a model file).
    pub model: Option<String>,
    /// Default gait slot.
    pub slot: Option<u8>,
}

/// Why the setup file could not be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    #[error("{path}: cannot read the robot setup: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: {field} = {value} is out of range: {why}")]
    Limit {
        path: PathBuf,
        field: &'static str,
        value: String,
        why: String,
    },
    #[error("{path}: {field} = {value} is out of range ({range})")]
    Range {
        path: PathBuf,
        field: &'static str,
        value: String,
        range: &'static str,
    },
}

impl RobotConfig {
    /// Parses `text` (the contents of `path`, named in errors with line and column).
    pub fn parse(path: &Path, text: &str) -> Result<Self, ConfigError> {
        let c: Self = toml::from_str(text).map_err(|e| ConfigError::Parse {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        c.check(path)?;
        Ok(c)
    }

    fn check(&self, path: &Path) -> Result<(), ConfigError> {
        let range = |field, value: String, range| ConfigError::Range {
            path: path.to_owned(),
            field,
            value,
            range,
        };
        // The hardware's limits (protocol::limits), the same `dbot set` and the firmware check.
        use protocol::limits::{CYCLE_HZ, LimitError, MX_BAUDS, ROBOT_SERVOS, check_bus};
        let limit = |field, value: String, e: LimitError| ConfigError::Limit {
            path: path.to_owned(),
            field,
            value,
            why: e.to_string(),
        };
        if let Some(k) = self.stiffness {
            protocol::limits::stiffness_units(k)
                .map_err(|e| limit("stiffness", k.to_string(), e))?;
        }
        if let Some(r) = self.rate
            && !CYCLE_HZ.contains(&r)
        {
            return Err(limit(
                "rate",
                r.to_string(),
                LimitError::CycleRate { hz: r },
            ));
        }
        if let Some(b) = self.baud
            && !MX_BAUDS.contains(&b)
        {
            return Err(limit("baud", b.to_string(), LimitError::Baud { baud: b }));
        }
        if let (Some(b), Some(r)) = (self.baud, self.rate) {
            check_bus(b, r, ROBOT_SERVOS).map_err(|e| limit("rate", r.to_string(), e))?;
        }
        if let Some(s) = self.slot
            && usize::from(s) >= protocol::MAX_SLOTS
        {
            return Err(range("slot", s.to_string(), "0 ..= 7"));
        }
        Ok(())
    }

    /// Reads `path`.
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.to_owned(),
            source,
        })?;
        let mut c = Self::parse(path, &text)?;
        c.relative_to(path.parent().unwrap_or(Path::new("")));
        Ok(c)
    }

    /// Makes the file's relative paths relative to `dir` (the file's folder).
    fn relative_to(&mut self, dir: &Path) {
        let join = |p: &str| dir.join(p).to_string_lossy().into_owned();
        if let Some(port) = &self.port {
            self.port = Some(match port.strip_prefix("virtual:") {
                Some(rest) if !rest.is_empty() => format!("virtual:{}", join(rest)),
                Some(_) => port.clone(),
                None if port == "virtual" || Path::new(port).is_absolute() => port.clone(),
                None => join(port),
            });
        }
        if let Some(m) = &self.model
            && is_model_file(m)
        {
            self.model = Some(join(m));
        }
    }

    /// The file named by `explicit`, else the first default path that exists, else an empty setup.
    /// An explicit path that does not exist is an error; a missing default file is not.
    pub fn find(explicit: Option<&Path>) -> Result<(Self, Option<PathBuf>), ConfigError> {
        if let Some(p) = explicit {
            return Ok((Self::load(p)?, Some(p.to_owned())));
        }
        for p in default_paths() {
            if p.is_file() {
                return Ok((Self::load(&p)?, Some(p)));
            }
        }
        Ok((Self::default(), None))
    }
}

/// Whether a `model` value names a file (a .toml model or an .aproj project) rather than a
/// built-in model.
pub fn is_model_file(spec: &str) -> bool {
    matches!(
        Path::new(spec).extension().and_then(|e| e.to_str()),
        Some("toml" | "aproj")
    )
}

/// Where a setup file is looked for, in order.
pub fn default_paths() -> Vec<PathBuf> {
    let mut v = Vec::new();
    if let Some(p) = std::env::var_os("DBOT_CONFIG") {
        v.push(PathBuf::from(p));
    }
    v.push(PathBuf::from("dbot.toml"));
    let base = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")));
    if let Some(b) = base {
        v.push(b.join("dbot").join("config.toml"));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_file_parses() {
        let c = RobotConfig::parse(
            Path::new("t.toml"),
            "port = \"virtual\"\nbaud = 2000000\nrate = 200\nstiffness = 8.4\nmodel = \"drosophibot2\"\nslot = 1\n",
        )
        .unwrap();
        assert_eq!(c.port.as_deref(), Some("virtual"));
        assert_eq!(c.rate, Some(200));
        assert_eq!(c.stiffness, Some(8.4));
        assert_eq!(c.slot, Some(1));
    }

    #[test]
    fn paths_in_the_file_are_relative_to_its_folder() {
        let dir = tempfile::tempdir().unwrap();
        let lab = dir.path().join("lab");
        std::fs::create_dir(&lab).unwrap();
        let file = lab.join("dbot.toml");
        std::fs::write(
            &file,
            "port = \"virtual:robot.flash\"\nmodel = \"models/fly.toml\"\n",
        )
        .unwrap();
        let c = RobotConfig::load(&file).unwrap();
        let want_port = format!("virtual:{}", lab.join("robot.flash").display());
        assert_eq!(c.port.as_deref(), Some(want_port.as_str()));
        let want_model = lab.join("models/fly.toml").display().to_string();
        assert_eq!(c.model.as_deref(), Some(want_model.as_str()));
        // Built-in names, `virtual` and absolute device paths are not paths to resolve.
        std::fs::write(&file, "port = \"/dev/ttyACM0\"\nmodel = \"drosophibot2\"\n").unwrap();
        let c = RobotConfig::load(&file).unwrap();
        assert_eq!(c.port.as_deref(), Some("/dev/ttyACM0"));
        assert_eq!(c.model.as_deref(), Some("drosophibot2"));
        std::fs::write(&file, "port = \"virtual\"\n").unwrap();
        assert_eq!(
            RobotConfig::load(&file).unwrap().port.as_deref(),
            Some("virtual")
        );
    }

    #[test]
    fn unknown_fields_and_bad_values_name_the_problem() {
        let e = RobotConfig::parse(Path::new("t.toml"), "prot = \"x\"\n").unwrap_err();
        assert!(e.to_string().contains("prot"), "{e}");
        let e = RobotConfig::parse(Path::new("t.toml"), "rate = 5\n").unwrap_err();
        assert!(e.to_string().contains("rate = 5"), "{e}");
        let e = RobotConfig::parse(Path::new("t.toml"), "stiffness = -1.0\n").unwrap_err();
        assert!(e.to_string().contains("stiffness"), "{e}");
    }
}
