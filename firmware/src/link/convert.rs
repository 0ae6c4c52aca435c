//! Between the controller's units (ticks, microradians, firmware enums) and the protocol's (1e-4 rad,
//! `RunState`, `ProtocolError`).

use embedded_storage::nor_flash::NorFlash;
use protocol::{
    BusStats, DeviceMessage, Fault, FaultKind, JointFeedback, Proprioception, ProtocolError,
    RunState, Telemetry, UploadError,
};

use crate::controller::{CommandError, Controller};
use crate::safety::{SafeReason, State};
use crate::store::StoreError;
use crate::telemetry::Record;

/// The protocol's view of a state.
pub fn run_state(s: State) -> RunState {
    match s {
        State::Boot => RunState::Boot,
        State::Idle => RunState::Idle,
        State::Standing => RunState::Standing,
        State::Ramping => RunState::Ramping,
        State::Walking => RunState::Walking,
        State::Stopping => RunState::Stopping,
        State::Streaming => RunState::Streaming,
        State::Safe(_) | State::EStop => RunState::Fault,
    }
}

/// The fault behind a state, if any.
pub fn fault(s: State) -> Option<Fault> {
    let (kind, joint) = match s {
        State::EStop => (FaultKind::EmergencyStop, None),
        State::Safe(SafeReason::ServoError { joint, error, .. }) => {
            (FaultKind::ServoError { bits: error }, Some(joint))
        }
        State::Safe(SafeReason::ServoMissing { joint, cycles, .. }) => {
            (FaultKind::ServoMissing { cycles }, Some(joint))
        }
        State::Safe(SafeReason::ServoStuck {
            joint,
            goal_range,
            present_range,
            ..
        }) => (
            FaultKind::ServoStuck {
                goal_range,
                present_range,
            },
            Some(joint),
        ),
        State::Safe(SafeReason::SetpointTimeout) => (FaultKind::SetpointTimeout, None),
        State::Safe(SafeReason::Watchdog) => (FaultKind::Watchdog, None),
        State::Boot
        | State::Idle
        | State::Standing
        | State::Ramping
        | State::Walking
        | State::Stopping
        | State::Streaming => return None,
    };
    Some(Fault { kind, joint })
}

/// Present Velocity (0.229 rev/min) in 1e-3 rad/s: x 0.229 x 2 pi / 60 x 1000 = x 23.981.
fn velocity(raw: i32) -> i16 {
    (i64::from(raw) * 23_981 / 1000).clamp(i16::MIN.into(), i16::MAX.into()) as i16
}

/// A telemetry record as the protocol message of its cycle: `Proprioception` for a streaming
/// cycle, else `Telemetry`.
pub fn telemetry<F: NorFlash + crate::store::FlashWindow>(
    c: &Controller<F>,
    r: &Record,
) -> DeviceMessage {
    let mut joints = heapless::Vec::new();
    for (s, cal) in r.joints.iter().zip(c.joints()).take(r.joint_count.into()) {
        let _ = joints.push(JointFeedback {
            commanded: cal.calibration.ticks_to_angle(s.commanded),
            present: cal.calibration.ticks_to_angle(s.present),
            velocity: velocity(s.velocity) * cal.calibration.sign.as_i32() as i16,
            load: s.load,
            error: s.error,
            flags: s.flags,
        });
    }
    let bus = BusStats {
        cycle_us: r.cycle_us,
        timeouts: r.timeouts,
        crc_errors: r.crc_errors,
        missed_deadlines: r.overruns,
    };
    // The record's own setpoint, not the controller's current one: the link converts records
    // cycles after they were taken, and setpoints keep arriving meanwhile.
    if let Some(sp) = r.setpoint {
        DeviceMessage::Proprioception(Proprioception {
            time_us: r.time_us,
            cycle: r.cycle,
            setpoint_seq: sp.seq,
            setpoint_age: sp.age,
            joints,
            bus,
        })
    } else {
        DeviceMessage::Telemetry(Telemetry {
            time_us: r.time_us,
            cycle: r.cycle,
            step: r.step,
            slice: r.slice,
            joints,
            bus,
            platform: r.platform.map(|p| protocol::PlatformFeedback {
                servo_id: p.id,
                goal: p.goal,
                present: p.present,
                flags: p.flags,
            }),
            state: run_state(r.state),
            health: r.health[..usize::from(r.joint_count).min(r.health.len())]
                .iter()
                .copied()
                .collect(),
        })
    }
}

/// A refused command as the protocol's error.
pub fn command_error(e: CommandError) -> ProtocolError {
    match e {
        CommandError::WrongState(r) => ProtocolError::WrongState {
            state: run_state(r.state),
        },
        CommandError::Moving { state } => ProtocolError::WrongState {
            state: run_state(state),
        },
        CommandError::SlotEmpty { slot } => ProtocolError::SlotEmpty { slot },
        CommandError::BadTable { error, .. } => ProtocolError::Table(error),
        CommandError::NoSuchSlot { slot, slots } => ProtocolError::NoSuchSlot { slot, slots },
        CommandError::NoSuchJoint { joint, joints } => ProtocolError::NoSuchJoint { joint, joints },
        CommandError::OutOfRange { what, value } => ProtocolError::InvalidSetting {
            setting: what,
            value: value.clamp(i32::MIN.into(), i32::MAX.into()) as i32,
        },
        CommandError::Store(e) => store_error(e),
        CommandError::Switch(e) => ProtocolError::Switch(e),
        CommandError::Steer(e) => ProtocolError::Steer(e),
        CommandError::Platform(e) => ProtocolError::Platform(e),
        // CommandError is non_exhaustive for its users, not for this crate.
    }
}

/// A gait store error as the protocol's error.
pub fn store_error(e: StoreError) -> ProtocolError {
    match e {
        StoreError::NoSuchSlot { slot, slots } => ProtocolError::NoSuchSlot { slot, slots },
        StoreError::BadSize { len, max } => ProtocolError::Upload(UploadError::TooLarge {
            total_len: len,
            capacity: max,
        }),
        StoreError::NoUpload => ProtocolError::Upload(UploadError::NotStarted),
        StoreError::OutOfOrder { expected, got } if got < expected => {
            ProtocolError::Upload(UploadError::Duplicate {
                offset: got,
                received: expected,
            })
        }
        StoreError::OutOfOrder { expected, got } => {
            ProtocolError::Upload(UploadError::OutOfOrder {
                offset: got,
                expected,
            })
        }
        StoreError::Overflow { offset, len, total } => {
            ProtocolError::Upload(UploadError::PastEnd {
                offset,
                len,
                total_len: total,
            })
        }
        StoreError::Incomplete { received, total } => {
            ProtocolError::Upload(UploadError::Truncated {
                received,
                total_len: total,
            })
        }
        StoreError::ChecksumMismatch { expected, actual } => {
            ProtocolError::Upload(UploadError::ChecksumMismatch {
                expected,
                computed: actual,
            })
        }
        StoreError::Verify { offset } => ProtocolError::Flash { offset },
        StoreError::Flash(_) => ProtocolError::Flash { offset: 0 },
    }
}
