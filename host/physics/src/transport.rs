//! The physics robot behind the host's [`Transport`] seam, as `VirtualTransport` serves the
//! virtual robot: time passes only while the host waits for bytes, in simulated time.

use std::time::Duration;

use board::link::{Transport, TransportError};

use crate::error::PhysicsError;
use crate::robot::PhysicsRobot;

/// A link to an in-process [`PhysicsRobot`].
#[derive(Debug)]
pub struct PhysicsTransport {
    robot: PhysicsRobot,
    name: String,
}

impl PhysicsTransport {
    pub fn new(robot: PhysicsRobot) -> Self {
        let name = format!("physics:{}", robot.scene());
        Self { robot, name }
    }

    /// Opens a port named `physics` (flat ground) or `physics:SCENE` with Drosophibot II.
    pub fn open(spec: &str) -> Result<Self, PhysicsError> {
        let scene = match spec.strip_prefix("physics") {
            Some("") => "flat",
            Some(rest) if rest.len() > 1 && rest.starts_with(':') => &rest[1..],
            _ => {
                return Err(PhysicsError::Port {
                    spec: spec.to_owned(),
                    problem: "not a physics port".into(),
                });
            }
        };
        Ok(Self::new(PhysicsRobot::drosophibot(scene)?))
    }

    pub fn robot(&self) -> &PhysicsRobot {
        &self.robot
    }

    pub fn robot_mut(&mut self) -> &mut PhysicsRobot {
        &mut self.robot
    }
}

impl Transport for PhysicsTransport {
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        self.robot.receive(bytes);
        Ok(())
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        let deadline = self.robot.now_us() + timeout.as_micros() as u64;
        loop {
            if self.robot.pending() > 0 {
                return Ok(self.robot.take(buf));
            }
            if self.robot.next_cycle_us() > deadline {
                self.robot.run_until(deadline);
                return Ok(0);
            }
            self.robot.cycle();
        }
    }

    fn name(&self) -> &str {
        &self.name
    }

    fn now(&self) -> Duration {
        Duration::from_micros(self.robot.now_us())
    }

    fn shutdown(&mut self) -> Result<(), TransportError> {
        Ok(())
    }
}

/// Registers `physics[:SCENE]` with the host's port parser (`board::port::PortSpec`), so every
/// board command of a program that calls this once works on the physics robot.
pub fn register_port() {
    board::port::register_physics(|spec| {
        PhysicsTransport::open(spec)
            .map(|t| Box::new(t) as Box<dyn Transport>)
            .map_err(|e| e.to_string())
    });
}
