//! Opening a port by name: a serial device path, `virtual` (an in-process virtual robot with a
//! fresh flash) or `virtual:PATH` (one whose flash lives in the file PATH between commands).

use std::path::PathBuf;

use crate::link::{LinkError, SerialTransport, Transport, TransportError};
use crate::robot::{VirtualRobot, VirtualTransport};

/// A port named on the command line or in the setup file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortSpec {
    Serial(String),
    Virtual { image: Option<PathBuf> },
}

impl PortSpec {
    pub fn parse(s: &str) -> Self {
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
    }
}
