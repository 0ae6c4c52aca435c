//! Opening a port by name: a serial device path, `virtual` (an in-process virtual robot with a
//! fresh flash), `virtual:PATH` (one whose flash lives in the file PATH between commands) or
//! `physics[:SCENE]` (the physics robot: the virtual robot driving a MuJoCo body, registered by the
//! binary that links the `physics` crate, see [`register_physics`]).

use std::path::PathBuf;
use std::sync::OnceLock;

use crate::link::{LinkError, SerialTransport, Transport, TransportError};
use crate::robot::{VirtualRobot, VirtualTransport};

/// A port named on the command line or in the setup file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortSpec {
    Serial(String),
    Virtual {
        image: Option<PathBuf>,
    },
    /// `physics` or `physics:SCENE`, the whole name.
    Physics(String),
}

/// Opens a `physics[:SCENE]` port; an error is a sentence naming the problem.
pub type PhysicsOpener = fn(&str) -> Result<Box<dyn Transport>, String>;

static PHYSICS: OnceLock<PhysicsOpener> = OnceLock::new();

/// Makes `physics[:SCENE]` ports open with `open`. The physics robot lives in the `physics` crate
/// because it needs MuJoCo, which this library must build without; a binary that links it calls
/// `physics::register_port()` once at start. The first registration wins.
pub fn register_physics(open: PhysicsOpener) {
    let _ = PHYSICS.set(open);
}

impl PortSpec {
    pub fn parse(s: &str) -> Self {
        if s == "physics" || s.starts_with("physics:") {
            return Self::Physics(s.to_owned());
        }
        match s.strip_prefix("virtual") {
            Some("") => Self::Virtual { image: None },
            Some(rest) if rest.starts_with(':') && rest.len() > 1 => Self::Virtual {
                image: Some(PathBuf::from(&rest[1..])),
            },
            _ => Self::Serial(s.to_owned()),
        }
    }

    /// Opens the transport.
    pub fn open(&self) -> Result<Box<dyn Transport>, LinkError> {
        match self {
            Self::Serial(path) => SerialTransport::open(path)
                .map(|t| Box::new(t) as Box<dyn Transport>)
                .map_err(|source| LinkError::Open {
                    port: path.clone(),
                    source,
                }),
            Self::Virtual { image: None } => {
                Ok(Box::new(VirtualTransport::new(VirtualRobot::new())))
            }
            Self::Virtual { image: Some(p) } => VirtualTransport::with_image(p)
                .map(|t| Box::new(t) as Box<dyn Transport>)
                .map_err(|e| LinkError::Open {
                    port: format!("virtual:{}", p.display()),
                    source: TransportError::Io(std::io::Error::other(e.to_string())),
                }),
            Self::Physics(spec) => {
                let opened = match PHYSICS.get() {
                    Some(open) => open(spec),
                    None => Err(
                        "this program was built without the physics robot (the `physics` \
                         crate registers it with physics::register_port())"
                            .to_owned(),
                    ),
                };
                opened.map_err(|e| LinkError::Open {
                    port: spec.clone(),
                    source: TransportError::Io(std::io::Error::other(e)),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse() {
        assert_eq!(
            PortSpec::parse("virtual"),
            PortSpec::Virtual { image: None }
        );
        assert_eq!(
            PortSpec::parse("virtual:a/b.flash"),
            PortSpec::Virtual {
                image: Some("a/b.flash".into())
            }
        );
        assert_eq!(
            PortSpec::parse("/dev/ttyACM0"),
            PortSpec::Serial("/dev/ttyACM0".into())
        );
        assert_eq!(
            PortSpec::parse("virtualx"),
            PortSpec::Serial("virtualx".into())
        );
        assert_eq!(
            PortSpec::parse("physics:incline:10"),
            PortSpec::Physics("physics:incline:10".into())
        );
        assert_eq!(
            PortSpec::parse("physics"),
            PortSpec::Physics("physics".into())
        );
        assert_eq!(
            PortSpec::parse("physicsx"),
            PortSpec::Serial("physicsx".into())
        );
    }
}
