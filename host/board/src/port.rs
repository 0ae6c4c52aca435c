//! Ports by name: a serial device path, `virtual` (an in-process virtual robot with a fresh
//! flash), `virtual:PATH` (one whose flash lives in the file PATH between commands) or
//! `physics[:SCENE[+SUBSTRATE][+platform:LEG]]` (the physics robot: the virtual robot driving a
//! MuJoCo body, on a [`Ground`] and a [`Substrate`]; with `+platform:LEG` the perturbation
//! platform's servo is on its bus at [`crate::platform::default_platform_id`] of its joints' IDs
//! (23) and the box goes under LEG's foot when that servo first moves, `physics::PlatformPlace`).
//!
//! This crate parses every name ([`PortSpec`]) and opens the kinds it owns ([`open_serial`],
//! [`open_virtual`]); the physics robot needs MuJoCo, which this library builds without, so the
//! `physics` crate opens it and holds the opener of every kind (`physics::open`, typed: its link
//! says which robot it is). [`connect`] is the one connection both use: it gives a `virtual:PATH`
//! robot back the settings saved beside its store ([`crate::saved_settings`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use planner::terrain::{Ground, TerrainError};

use planner::model::Leg;

use crate::link::{Board, LinkError, SerialTransport, Transport, TransportError};
use crate::platform::{PerturbError, leg_named};
use crate::robot::{VirtualRobot, VirtualTransport};
use crate::saved_settings::{self, SettingsError};
use crate::substrate::{Substrate, SubstrateError};

/// A port named on the command line, in the setup file or in Python.
#[derive(Debug, Clone, PartialEq)]
pub enum PortSpec {
    /// A serial device or pseudo-terminal path.
    Serial(String),
    /// `virtual` (no image) or `virtual:PATH`.
    Virtual { image: Option<PathBuf> },
    /// `physics` (scene `flat`) or `physics:SCENE[+SUBSTRATE][+platform:LEG][+model:FILE]` (any
    /// [`Ground`]; sand paper, the paper's substrate, unless `+floor`, `+wire-mesh` ... says
    /// otherwise; the leg the perturbation platform stands under, if it has one; the body of a
    /// model file, e.g. one `dbot identify` fitted, instead of the built-in Drosophibot II).
    Physics {
        scene: Ground,
        substrate: Substrate,
        platform: Option<Leg>,
        model: Option<PathBuf>,
    },
}

/// A port name that names a physics scene that cannot be.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("port `{port}`: {source}")]
pub struct PortSpecError {
    pub port: String,
    pub source: SceneError,
}

/// What is wrong with a physics scene: its terrain or its substrate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    #[error(transparent)]
    Terrain(#[from] TerrainError),
    #[error(transparent)]
    Substrate(#[from] SubstrateError),
    #[error(transparent)]
    Platform(#[from] PerturbError),
}

/// Why a port could not be opened and connected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OpenError {
    #[error(transparent)]
    Link(#[from] LinkError),
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(transparent)]
    Spec(#[from] PortSpecError),
}

impl PortSpec {
    /// Reads a port name; only a physics scene can be wrong (any other name is a device path).
    pub fn parse(s: &str) -> Result<Self, PortSpecError> {
        // The model file comes last: its path may hold any character.
        let (s, model) = match s.split_once("+model:") {
            Some((rest, file)) if s.starts_with("physics") && !file.is_empty() => {
                (rest, Some(PathBuf::from(file)))
            }
            _ => (s, None),
        };
        if s == "physics" {
            return Ok(Self::Physics {
                scene: Ground::Flat,
                substrate: Substrate::Sandpaper,
                platform: None,
                model,
            });
        }
        if let Some(scene) = s.strip_prefix("physics:") {
            let fail = |source: SceneError| PortSpecError {
                port: s.to_owned(),
                source,
            };
            let (scene, platform) = match scene.rsplit_once("+platform:") {
                Some((scene, leg)) => (scene, Some(leg_named(leg).map_err(|e| fail(e.into()))?)),
                None => (scene, None),
            };
            let (terrain, substrate) = Substrate::split_scene(scene).map_err(|e| fail(e.into()))?;
            let scene = Ground::parse(terrain).map_err(|e| fail(e.into()))?;
            return Ok(Self::Physics {
                scene,
                substrate,
                platform,
                model,
            });
        }
        Ok(match s.strip_prefix("virtual") {
            Some("") => Self::Virtual { image: None },
            Some(rest) if rest.starts_with(':') && rest.len() > 1 => Self::Virtual {
                image: Some(PathBuf::from(&rest[1..])),
            },
            _ => Self::Serial(s.to_owned()),
        })
    }

    /// The store of a `virtual:PATH` port (its flash image; the saved settings are beside it).
    pub fn store(&self) -> Option<&Path> {
        match self {
            Self::Virtual { image } => image.as_deref(),
            Self::Serial(_) | Self::Physics { .. } => None,
        }
    }
}

/// Opens the serial device (or pseudo-terminal) at `path`.
pub fn open_serial(path: &str) -> Result<SerialTransport, LinkError> {
    SerialTransport::open(path).map_err(|source| LinkError::Open {
        port: path.to_owned(),
        source,
    })
}

/// Opens the virtual robot: a fresh one, or one booting from the flash image `image` (locked for
/// this opening, saved at shutdown).
pub fn open_virtual(image: Option<&Path>) -> Result<VirtualTransport, LinkError> {
    let Some(p) = image else {
        return Ok(VirtualTransport::new(VirtualRobot::new()));
    };
    VirtualTransport::with_image(p).map_err(|e| LinkError::Open {
        port: format!("virtual:{}", p.display()),
        source: TransportError::Io(std::io::Error::other(e.to_string())),
    })
}

/// Connects to the board behind `transport` (opened for `spec`), waiting `reply_timeout` for each
/// reply, and applies the settings saved beside a `virtual:PATH` store.
pub fn connect<T: Transport>(
    transport: T,
    spec: &PortSpec,
    reply_timeout: Duration,
) -> Result<Board<T>, OpenError> {
    let mut board = Board::connect_within(transport, reply_timeout)?;
    if let Some(store) = spec.store() {
        saved_settings::apply(&mut board, store)?;
    }
    Ok(board)
}

/// Why `port` cannot carry a perturbation under `leg` (`None`: it can, or it is no physics
/// port: a board's platform servo answers or not at set-up): a physics port without a platform,
/// or with it under another leg, names the spec to use.
pub fn platform_port_problem(port: &str, leg: Leg) -> Option<String> {
    let Ok(PortSpec::Physics { platform, .. }) = PortSpec::parse(port) else {
        return None;
    };
    let (rest, model) = match port.split_once("+model:") {
        Some((rest, file)) => (rest, format!("+model:{file}")),
        None => (port, String::new()),
    };
    let plain = rest.split("+platform:").next().unwrap_or(rest);
    let plain = if plain == "physics" {
        "physics:flat"
    } else {
        plain
    };
    let want = format!("{plain}+platform:{}{model}", leg.name());
    match platform {
        None => Some(format!(
            "port `{port}` has no perturbation platform: open `{want}` instead"
        )),
        Some(l) if l != leg => Some(format!(
            "port `{port}` has its platform under {}, not {}: open `{want}` instead",
            l.name(),
            leg.name()
        )),
        Some(_) => None,
    }
}

/// The substrate of a trial on `port` with `--substrate` `flag`: a physics port's scene says
/// it (the flag, if given, must agree); another port's is the flag's, or unspecified.
pub fn trial_substrate(port: &str, flag: Option<&str>) -> Result<Substrate, SubstrateError> {
    let flag = flag
        .map(|name| Substrate::parse(name, "substrate"))
        .transpose()?;
    // A port whose scene cannot be parsed is refused when it is opened, naming it.
    let scene = match PortSpec::parse(port) {
        Ok(PortSpec::Physics { substrate, .. }) => Some(substrate),
        Ok(PortSpec::Serial(_) | PortSpec::Virtual { .. }) | Err(_) => None,
    };
    match (scene, flag) {
        (Some(s), Some(f)) if s != f => Err(SubstrateError::Disagrees {
            flag: f.name(),
            port: port.to_owned(),
            scene: s.name(),
        }),
        (Some(s), _) => Ok(s),
        (None, f) => Ok(f.unwrap_or_default()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trial_takes_its_substrate_from_the_physics_scene_or_the_flag() {
        assert_eq!(
            trial_substrate("physics:flat+floor", None),
            Ok(Substrate::Floor)
        );
        assert_eq!(
            trial_substrate("physics", Some("sandpaper")),
            Ok(Substrate::Sandpaper)
        );
        assert_eq!(
            trial_substrate("/dev/ttyACM0", Some("anti-slip-mat")),
            Ok(Substrate::AntiSlipMat)
        );
        assert_eq!(
            trial_substrate("/dev/ttyACM0", None),
            Ok(Substrate::Unspecified)
        );
        let e = trial_substrate("physics:flat+floor", Some("wire-mesh")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "substrate wire-mesh disagrees with port `physics:flat+floor`, whose scene walks on floor: give one of them"
        );
    }

    #[test]
    fn a_physics_port_for_a_perturbation_names_the_spec_with_the_platform() {
        use planner::model::Leg;
        assert_eq!(
            platform_port_problem("physics", Leg::RM).as_deref(),
            Some(
                "port `physics` has no perturbation platform: open `physics:flat+platform:RM` instead"
            )
        );
        assert_eq!(
            platform_port_problem("physics:flat+platform:LF", Leg::RM).as_deref(),
            Some(
                "port `physics:flat+platform:LF` has its platform under LF, not RM: open \
                 `physics:flat+platform:RM` instead"
            )
        );
        assert_eq!(
            platform_port_problem("physics:flat+platform:RM", Leg::RM),
            None
        );
        assert_eq!(platform_port_problem("/dev/ttyACM0", Leg::RM), None);
    }

    #[test]
    fn names_parse() {
        assert_eq!(
            PortSpec::parse("virtual").unwrap(),
            PortSpec::Virtual { image: None }
        );
        assert_eq!(
            PortSpec::parse("virtual:a/b.flash").unwrap(),
            PortSpec::Virtual {
                image: Some("a/b.flash".into())
            }
        );
        assert_eq!(
            PortSpec::parse("/dev/ttyACM0").unwrap(),
            PortSpec::Serial("/dev/ttyACM0".into())
        );
        assert_eq!(
            PortSpec::parse("virtualx").unwrap(),
            PortSpec::Serial("virtualx".into())
        );
        assert_eq!(
            PortSpec::parse("physics:incline:10"),
            Ok(PortSpec::Physics {
                scene: Ground::Incline { angle_deg: 10.0 },
                substrate: Substrate::Sandpaper,
                platform: None,
                model: None,
            })
        );
        assert_eq!(
            PortSpec::parse("physics"),
            Ok(PortSpec::Physics {
                scene: Ground::Flat,
                substrate: Substrate::Sandpaper,
                platform: None,
                model: None,
            })
        );
        assert_eq!(
            PortSpec::parse("physics:flat+floor+platform:RM"),
            Ok(PortSpec::Physics {
                scene: Ground::Flat,
                substrate: Substrate::Floor,
                platform: Some(planner::model::Leg::RM),
                model: None,
            })
        );
        // The model file comes last, its path taken whole (a `+` in it included).
        assert_eq!(
            PortSpec::parse("physics:incline:5+floor+platform:RM+model:out/a+b/fitted.toml"),
            Ok(PortSpec::Physics {
                scene: Ground::Incline { angle_deg: 5.0 },
                substrate: Substrate::Floor,
                platform: Some(planner::model::Leg::RM),
                model: Some("out/a+b/fitted.toml".into()),
            })
        );
        assert_eq!(
            PortSpec::parse("physics+model:m.toml"),
            Ok(PortSpec::Physics {
                scene: Ground::Flat,
                substrate: Substrate::Sandpaper,
                platform: None,
                model: Some("m.toml".into()),
            })
        );
        assert_eq!(
            PortSpec::parse("physics:flat+platform:RX")
                .unwrap_err()
                .to_string(),
            "port `physics:flat+platform:RX`: perturbation leg `RX` is not a leg (legs: LF, LM, \
             LH, RF, RM, RH)"
        );
        let e = PortSpec::parse("physics:grass").unwrap_err().to_string();
        assert!(
            e.starts_with("port `physics:grass`: terrain `grass`: unknown terrain"),
            "{e}"
        );
        assert_eq!(
            PortSpec::parse("physicsx").unwrap(),
            PortSpec::Serial("physicsx".into())
        );
    }

    #[test]
    fn saved_settings_are_applied_at_every_opening_of_a_store() {
        let dir = tempfile::tempdir().unwrap();
        let store = dir.path().join("robot.flash");
        let spec = PortSpec::parse(&format!("virtual:{}", store.display())).unwrap();
        let open = || {
            let t = open_virtual(spec.store()).unwrap();
            connect(t, &spec, crate::link::DEFAULT_REPLY_TIMEOUT).unwrap()
        };
        let mut b = open();
        // A fresh robot: the firmware's defaults (1 Mbit/s, 100 Hz; Config::default()).
        assert_eq!(b.settings().unwrap().cycle_hz, 100);
        // The rate: a baud change needs servos that follow it (`rules::bus`), and the virtual
        // servos keep theirs.
        b.set_bus(1_000_000, 150).unwrap();
        b.set_telemetry(7).unwrap();
        saved_settings::save(&mut b, spec.store().unwrap()).unwrap();
        b.transport_mut().shutdown().unwrap();
        drop(b);
        let mut again = open();
        let s = again.settings().unwrap();
        assert_eq!((s.baud, s.cycle_hz, s.telemetry_every), (1_000_000, 150, 7));
    }

    #[test]
    fn a_damaged_settings_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let store = dir.path().join("robot.flash");
        std::fs::write(saved_settings::settings_path(&store), "{ not json").unwrap();
        let spec = PortSpec::parse(&format!("virtual:{}", store.display())).unwrap();
        let t = open_virtual(spec.store()).unwrap();
        let e = connect(t, &spec, crate::link::DEFAULT_REPLY_TIMEOUT)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("robot.flash.settings.json") && e.contains("not a settings file"),
            "{e}"
        );
    }
}
