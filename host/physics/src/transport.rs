//! The physics robot as a port: `physics[:SCENE]` opens the board's virtual robot with a MuJoCo
//! body ([`PhysicsRobot::into_transport`]); time passes only while the host waits for bytes, in
//! simulated time, as on `--port virtual`.

use board::link::Transport;

use crate::error::PhysicsError;
use crate::robot::{PhysicsRobot, PhysicsTransport};

/// Opens a port named `physics` (flat ground) or `physics:SCENE` with Drosophibot II.
pub fn open(spec: &str) -> Result<PhysicsTransport, PhysicsError> {
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
    Ok(PhysicsRobot::drosophibot(scene)?.into_transport())
}

/// Registers `physics[:SCENE]` with the host's port parser (`board::port::PortSpec`), so every
/// board command of a program that calls this once works on the physics robot.
pub fn register_port() {
    board::port::register_physics(|spec| {
        open(spec)
            .map(|t| Box::new(t) as Box<dyn Transport>)
            .map_err(|e| e.to_string())
    });
}
