//! The physics robot served on pseudo-terminals, as a lab's robot is on its USB ports
//! (`dbot sim-bus --physics`): its board linked at one path (`board::robot::pty`), and, when asked,
//! its body's simulated gauges on a virtual strain board linked at another
//! (`board::strain::pty`), so that separate processes open them as they open `/dev/ttyACM0` and
//! `/dev/ttyACM1`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;

use board::robot::pty::RobotPtyServer;
use board::strain::pty::StrainPtyServer;
use board::strain::source::Shared;
use board::strain::virtual_board::{Ended, VirtualStrainBoard};
use physics::PhysicsRobot;

use crate::error::{Context, LabError, Result};

/// The strain board beside the robot: linked at `link`, `gain` counts per microstrain.
#[derive(Debug, Clone, PartialEq)]
pub struct StrainLink {
    pub link: PathBuf,
    pub gain: f64,
}

/// The physics robot of the port spec `spec` (`physics`, `physics:SCENE[+SUBSTRATE]`) on a
/// pseudo-terminal linked at `link`, and its gauges on `strain` when given; nothing runs until
/// [`PhysicsServer::serve`].
#[derive(Debug)]
pub struct PhysicsServer {
    spec: String,
    link: PathBuf,
    robot: RobotPtyServer<PhysicsRobot>,
    strain: Option<(StrainLink, StrainPtyServer)>,
}

impl PhysicsServer {
    /// Builds the robot and opens its pseudo-terminals. Refused: a spec that is no physics robot,
    /// a scene or substrate that is not known, a link that cannot be made.
    pub fn open(spec: &str, link: &Path, strain: Option<StrainLink>) -> Result<Self> {
        let parsed =
            board::port::PortSpec::parse(spec).map_err(|e| LabError::Library(Box::new(e)))?;
        let board::port::PortSpec::Physics {
            scene,
            substrate,
            platform,
            model,
        } = parsed
        else {
            crate::bail!(
                "port `{spec}` is not a physics robot; give `physics` or `physics:SCENE[+SUBSTRATE][+platform:LEG][+model:FILE]`"
            )
        };
        let mut robot = physics::physics_body(&scene, substrate, platform, model.as_deref())
            .with_context(|| format!("port `{spec}`"))?;
        let strain = match strain {
            Some(s) => {
                let feed = Shared::default();
                robot.feed_strain(feed.clone());
                let board =
                    VirtualStrainBoard::new(Box::new(feed), Vec::new(), true).with_gain(s.gain);
                let server = StrainPtyServer::open(board, &s.link).with_context(|| {
                    format!(
                        "cannot serve the virtual strain board at {}",
                        s.link.display()
                    )
                })?;
                Some((s, server))
            }
            None => None,
        };
        let robot = RobotPtyServer::open(robot.into_transport(), link)
            .with_context(|| format!("cannot serve the physics robot at {}", link.display()))?;
        Ok(Self {
            spec: spec.to_owned(),
            link: link.to_owned(),
            robot,
            strain,
        })
    }

    /// What is served where, in one line.
    pub fn describe(&self) -> String {
        let strain = self.strain.as_ref().map_or(String::new(), |(s, server)| {
            format!(
                "; its gauges on a virtual strain board on {} linked at {} ({} counts per microstrain)",
                server.slave_path(),
                s.link.display(),
                s.gain
            )
        });
        format!(
            "serving the physics robot ({}) on {} linked at {}{strain}",
            self.spec,
            self.robot.slave_path(),
            self.link.display(),
        )
    }

    /// Runs the robot (and its strain board on a thread of its own) until `stop` is set. A
    /// strain board that stops early costs the robot nothing: its error is returned in
    /// [`Served::strain_error`] once the robot's serving ends.
    pub fn serve(self, stop: &'static AtomicBool) -> Result<Served> {
        let Self {
            mut robot, strain, ..
        } = self;
        let thread: Option<JoinHandle<_>> = strain
            .map(|(_, mut server)| std::thread::spawn(move || server.serve(stop, |_: &Ended| {})));
        let served = robot.serve(stop);
        stop.store(true, Ordering::Relaxed);
        let strain_error = match thread.map(JoinHandle::join) {
            None | Some(Ok(Ok(_))) => None,
            Some(Ok(Err(e))) => Some(format!("the virtual strain board stopped: {e}")),
            Some(Err(_)) => Some("the virtual strain board's thread panicked".to_owned()),
        };
        served.context("serving the physics robot failed")?;
        Ok(Served { strain_error })
    }
}

/// How a [`PhysicsServer`] ended.
#[derive(Debug, Clone, PartialEq)]
pub struct Served {
    /// Why the strain board stopped before the robot, if it did.
    pub strain_error: Option<String>,
}
