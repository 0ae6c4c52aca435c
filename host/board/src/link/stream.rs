//! Streaming mode on the [`Board`] client: enter and leave it, send one [`Setpoint`] per bus cycle,
//! read the board's [`Proprioception`]. The board applies limits, bias and the setpoint-loss rule
//! (hold for `timeout_cycles`, then safe); the host only converts SI units to the wire's fixed point.

use std::time::Duration;

use protocol::{
    Client, DeviceMessage, JointSetpoint, MAX_FRAME_LEN, MAX_JOINTS, Proprioception, Setpoint,
    StreamConfig,
};

use super::board::Board;
use super::error::LinkError;
use super::transport::Transport;

/// Proprioception records kept while nobody reads them; older ones are dropped.
const PROPRIOCEPTION_BACKLOG: usize = 100_000;

/// Why SI setpoints cannot be put on the wire.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SetpointError {
    #[error("setpoint has {count} joints; the wire carries at most {max}")]
    TooManyJoints { count: usize, max: usize },
    #[error("setpoint has {angles} angles but {torques} torques; give one torque per joint")]
    TorqueCount { angles: usize, torques: usize },
    #[error("joint {joint}: {what} {value} is outside {min}..={max} (or not a number)")]
    OutOfRange {
        joint: usize,
        what: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
}

/// A setpoint from joint angles (rad) and optional torque feed-forward (N m), in joint-map order.
pub fn setpoint_from_si(
    seq: u32,
    angles_rad: &[f64],
    torques_nm: Option<&[f64]>,
) -> Result<Setpoint, SetpointError> {
    if angles_rad.len() > MAX_JOINTS {
        return Err(SetpointError::TooManyJoints {
            count: angles_rad.len(),
            max: MAX_JOINTS,
        });
    }
    if let Some(t) = torques_nm
        && t.len() != angles_rad.len()
    {
        return Err(SetpointError::TorqueCount {
            angles: angles_rad.len(),
            torques: t.len(),
        });
    }
    let fixed = |joint: usize, what: &'static str, value: f64, scale: f64| {
        protocol::units::to_fixed(value, scale, i16::MIN.into(), i16::MAX.into())
            .map(|v| v as i16)
            .ok_or(SetpointError::OutOfRange {
                joint,
                what,
                value,
                min: f64::from(i16::MIN) / scale,
                max: f64::from(i16::MAX) / scale,
            })
    };
    let mut joints = heapless::Vec::new();
    for (j, &a) in angles_rad.iter().enumerate() {
        let angle = fixed(j, "angle (rad)", a, protocol::units::ANGLE_PER_RAD)?;
        let torque = match torques_nm {
            Some(t) => Some(fixed(
                j,
                "torque (N m)",
                t[j],
                protocol::units::TORQUE_PER_NM,
            )?),
            None => None,
        };
        // Cannot fail: the length was checked against MAX_JOINTS above.
        let _ = joints.push(JointSetpoint { angle, torque });
    }
    Ok(Setpoint { seq, joints })
}

impl<T: Transport> Board<T> {
    /// Switches from a standing posture to streaming (the board refuses it otherwise).
    pub fn enter_streaming(&mut self, config: StreamConfig) -> Result<(), LinkError> {
        self.proprioception.clear();
        self.call(config)
    }

    /// Back to standing, holding the last setpoint.
    pub fn leave_streaming(&mut self) -> Result<(), LinkError> {
        self.call(protocol::endpoint::LeaveStreaming)
    }

    /// Sends one setpoint (not answered: its `seq` comes back in [`Proprioception::setpoint_seq`]).
    pub fn send_setpoint(&mut self, setpoint: &Setpoint) -> Result<(), LinkError> {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let frame =
            Client::encode_setpoint(setpoint, &mut buf).map_err(|error| LinkError::Encode {
                request: "Setpoint",
                error,
            })?;
        // Sent from the stack buffer, without a copy to the heap (one per bus cycle).
        self.send_raw(frame)
    }

    /// The next proprioception record, waiting up to `timeout` on the transport's clock.
    pub fn proprioception(
        &mut self,
        timeout: Duration,
    ) -> Result<Option<Proprioception>, LinkError> {
        if let Some(p) = self.proprioception.pop_front() {
            return Ok(Some(p));
        }
        let deadline = self.now() + timeout;
        while let Some(message) = self.next_message(deadline)? {
            match message {
                DeviceMessage::Proprioception(p) => return Ok(Some(p)),
                DeviceMessage::Telemetry(t) => self.keep_telemetry(t),
                _ => {}
            }
        }
        Ok(None)
    }

    /// Every proprioception record that has arrived so far, without waiting.
    pub fn drain_proprioception(&mut self) -> Result<Vec<Proprioception>, LinkError> {
        let mut out: Vec<Proprioception> = self.proprioception.drain(..).collect();
        while let Some(p) = self.proprioception(Duration::ZERO)? {
            out.push(p);
        }
        Ok(out)
    }

    pub(super) fn keep_proprioception(&mut self, p: Proprioception) {
        if self.proprioception.len() >= PROPRIOCEPTION_BACKLOG {
            self.proprioception.pop_front();
        }
        self.proprioception.push_back(p);
    }
}
