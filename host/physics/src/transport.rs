//! Opening any robot by port name with its kind kept in the type: [`open`] gives a [`Robot`], the
//! board client over a [`RobotLink`] whose variant says what is behind it (a board on a serial
//! port, the virtual robot, or the physics robot, whose [`Body`] it reaches). No global: the
//! physics robot is opened here because this crate is the one that links MuJoCo; the board crate
//! parses the names and opens the other kinds (`board::port`).
//!
//! On the physics robot time passes only while the host waits for bytes, in simulated time, as on
//! `virtual`.

use std::path::Path;
use std::time::Duration;

use board::link::{Board, DEFAULT_REPLY_TIMEOUT, SerialTransport, Transport, TransportError};
use board::port::{self, PortSpec};
use board::robot::VirtualTransport;
use planner::model::Leg;
use planner::terrain::Ground;

use crate::body::Body;
use crate::error::PhysicsError;
use crate::robot::{PhysicsRobot, PhysicsTransport};
use crate::substrate::Substrate;

/// The link under a robot opened by name. (The in-process robots are boxed: each holds a whole
/// board, flash included, beside a serial port's few bytes.)
#[derive(Debug)]
pub enum RobotLink {
    /// A board, or the RP2040 emulator's pseudo-terminal, on a serial device.
    Serial(SerialTransport),
    /// The in-process virtual robot (its servos carry the planned loads), optionally with its
    /// flash in a file.
    Virtual(Box<VirtualTransport>),
    /// The virtual robot with a MuJoCo body.
    Physics(Box<PhysicsTransport>),
}

/// A connected robot of any kind: `robot.transport()` says which.
pub type Robot = Board<RobotLink>;

/// Why a port could not be opened.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OpenError {
    #[error(transparent)]
    Board(#[from] port::OpenError),
    #[error(transparent)]
    Physics(#[from] PhysicsError),
}

impl From<board::link::LinkError> for OpenError {
    fn from(e: board::link::LinkError) -> Self {
        Self::Board(e.into())
    }
}

impl RobotLink {
    /// What kind of robot this is, in a word (`serial`, `virtual`, `physics`).
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Serial(_) => "serial",
            Self::Virtual(_) => "virtual",
            Self::Physics(_) => "physics",
        }
    }

    /// The in-process robot's simulated servo bus (`None` for a board on a serial port, whose
    /// bus the host reaches only through a servo adapter).
    pub fn bus_wire(&self) -> Option<dynamixel::sim::SimWire> {
        match self {
            Self::Virtual(t) => Some(t.robot().wire()),
            Self::Physics(t) => Some(t.robot().wire()),
            Self::Serial(_) => None,
        }
    }

    /// The physics robot's body model (`None` for any other kind).
    pub fn physics(&self) -> Option<&PhysicsRobot> {
        match self {
            Self::Physics(t) => Some(t.robot().servos()),
            Self::Serial(_) | Self::Virtual(_) => None,
        }
    }

    /// The physics robot's body model, to change (`None` for any other kind).
    pub fn physics_mut(&mut self) -> Option<&mut PhysicsRobot> {
        match self {
            Self::Physics(t) => Some(t.robot_mut().servos_mut()),
            Self::Serial(_) | Self::Virtual(_) => None,
        }
    }

    /// The simulated body now (`None`: a board or the virtual robot, which have no body).
    pub fn body(&self) -> Option<Body> {
        self.physics().map(PhysicsRobot::body)
    }

    /// The latest sample of the physics robot's simulated gauges (`None`: not the physics
    /// robot, or no bus cycle yet).
    pub fn strain(&self) -> Option<crate::SimulatedStrain> {
        self.physics().and_then(|p| p.latest_strain().cloned())
    }

    /// The physics robot's latest gauge sample at or before board time `t_s`, s (see
    /// `PhysicsRobot::strain_at`; `None`: not the physics robot, or no sample that old).
    pub fn strain_at(&self, t_s: f64) -> Option<crate::SimulatedStrain> {
        self.physics().and_then(|p| p.strain_at(t_s).cloned())
    }

    /// A feed of the physics robot's simulated gauges for a virtual strain board on
    /// `strain_port` (`board::strain::StrainBeside::start_fed`): Some only when the strain port
    /// is `virtual` and this is the physics robot, so `record --port physics --strain virtual`
    /// records the body's own gauges.
    pub fn strain_feed(&mut self, strain_port: &str) -> Option<board::strain::source::Shared> {
        if strain_port != board::strain::port::VIRTUAL {
            return None;
        }
        let robot = self.physics_mut()?;
        let feed = board::strain::source::Shared::default();
        robot.feed_strain(feed.clone());
        Some(feed)
    }

    fn inner(&mut self) -> &mut dyn Transport {
        match self {
            Self::Serial(t) => t,
            Self::Virtual(t) => &mut **t,
            Self::Physics(t) => &mut **t,
        }
    }

    fn inner_ref(&self) -> &dyn Transport {
        match self {
            Self::Serial(t) => t,
            Self::Virtual(t) => &**t,
            Self::Physics(t) => &**t,
        }
    }
}

impl Transport for RobotLink {
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        self.inner().send(bytes)
    }
    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        self.inner().recv(buf, timeout)
    }
    fn name(&self) -> &str {
        self.inner_ref().name()
    }
    fn now(&self) -> Duration {
        self.inner_ref().now()
    }
    fn shutdown(&mut self) -> Result<(), TransportError> {
        self.inner().shutdown()
    }
}

/// Opens the physics robot (Drosophibot II, or the body of the model file `model`) on `scene`
/// and `substrate`, with the perturbation platform under `platform`'s foot if given
/// (`board::port`'s `+platform:LEG` and `+model:FILE`).
pub fn open_physics(
    scene: &Ground,
    substrate: Substrate,
    platform: Option<Leg>,
    model: Option<&Path>,
) -> Result<PhysicsTransport, PhysicsError> {
    physics_body(scene, substrate, platform, model).map(PhysicsRobot::into_transport)
}

/// The body [`open_physics`] opens, before it is put on the board's bus (e.g. to feed a strain
/// board from it). Refused: a scene or substrate that cannot be, a model file that does not load
/// (named, with the problem and where).
pub fn physics_body(
    scene: &Ground,
    substrate: Substrate,
    platform: Option<Leg>,
    model: Option<&Path>,
) -> Result<PhysicsRobot, PhysicsError> {
    let spec = || match model {
        None => format!("physics:{scene}"),
        Some(m) => format!("physics:{scene}+model:{}", m.display()),
    };
    let body = match model {
        None => crate::robot::drosophibot()?,
        Some(path) => planner::model::load(path).map_err(|e| PhysicsError::Port {
            spec: spec(),
            problem: format!("model file {}: {e}", path.display()),
        })?,
    };
    let robot = match platform {
        None => PhysicsRobot::new(&body, scene).map(|r| r.on_substrate(substrate)),
        Some(leg) => PhysicsRobot::of_model_with_platform(
            &body,
            scene,
            substrate,
            board::platform::default_platform_id_for(None),
            crate::PlatformPlace::UnderFootOf(leg),
        ),
    };
    let robot = robot.map_err(|e| match e {
        PhysicsError::Scene { .. } | PhysicsError::Substrate { .. } => PhysicsError::Port {
            spec: spec(),
            problem: e.to_string(),
        },
        other => other,
    })?;
    Ok(match model {
        Some(path) => robot.from_model_file(&path.display().to_string()),
        None => robot,
    })
}

/// Opens `port` (see `board::port`) and connects, waiting [`DEFAULT_REPLY_TIMEOUT`] per reply.
pub fn open(port: &str) -> Result<Robot, OpenError> {
    open_within(port, DEFAULT_REPLY_TIMEOUT)
}

/// Opens `port` and connects, waiting `reply_timeout` for each reply; a `virtual:PATH` robot gets
/// the settings saved beside its store (`board::saved_settings`).
pub fn open_within(port: &str, reply_timeout: Duration) -> Result<Robot, OpenError> {
    let spec = PortSpec::parse(port).map_err(port::OpenError::from)?;
    let link = match &spec {
        PortSpec::Serial(path) => RobotLink::Serial(port::open_serial(path)?),
        PortSpec::Virtual { image } => {
            RobotLink::Virtual(Box::new(port::open_virtual(image.as_deref())?))
        }
        PortSpec::Physics {
            scene,
            substrate,
            platform,
            model,
        } => RobotLink::Physics(Box::new(open_physics(
            scene,
            *substrate,
            *platform,
            model.as_deref(),
        )?)),
    };
    Ok(port::connect(link, &spec, reply_timeout)?)
}
