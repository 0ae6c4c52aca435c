//! One request to the controller and its response. Upload steps go through the protocol's
//! `UploadTracker` first (so board and host share one set of rules and error names), then to the
//! gait store, which verifies the bytes in flash before it commits.

use embedded_storage::nor_flash::NorFlash;
use protocol::gait::{FORMAT_VERSION, GaitTable};
use protocol::upload::verify_stored;
use protocol::{
    Capabilities, DeviceInfo, FirmwareVersion, GaitSummary, JointSettings, PROTOCOL_VERSION,
    PlaybackPosition, ProtocolError, Request, Response, ServoSelect, Setpoint, Settings, SlotInfo,
    Status, Steps, UploadLimits, UploadTracker,
};

use super::convert::{command_error, fault, run_state, store_error};
use crate::controller::{Controller, PlayParams};
use crate::gait_view::URAD_PER_ANGLE_UNIT;
use crate::playback::Direction;
use crate::store::{CommitError, FlashWindow};

/// What this firmware can do.
pub const CAPABILITIES: Capabilities = Capabilities::GAIT_STORE
    .union(Capabilities::PLAYBACK)
    .union(Capabilities::TELEMETRY)
    .union(Capabilities::STREAMING)
    .union(Capabilities::TORQUE_FEED_FORWARD)
    .union(Capabilities::BUS_SETTINGS);

fn ack<E>(r: Result<(), E>, f: impl FnOnce(E) -> ProtocolError) -> Response {
    match r {
        Ok(()) => Response::Ack,
        Err(e) => Response::Error(f(e)),
    }
}

fn version() -> FirmwareVersion {
    let n = |s: &str| s.parse().unwrap_or(0);
    FirmwareVersion {
        major: n(env!("CARGO_PKG_VERSION_MAJOR")),
        minor: n(env!("CARGO_PKG_VERSION_MINOR")),
        patch: n(env!("CARGO_PKG_VERSION_PATCH")),
    }
}

fn slots<F: NorFlash + FlashWindow>(
    c: &Controller<F>,
) -> heapless::Vec<SlotInfo, { protocol::MAX_SLOTS }> {
    let mut v = heapless::Vec::new();
    for slot in 0..c.store().slots() {
        let gait = c
            .store()
            .table(slot)
            .and_then(|b| GaitTable::parse(b).ok())
            .map(|t| GaitSummary {
                header: t.header(),
                crc: t.crc(),
            });
        let _ = v.push(SlotInfo { slot, gait });
    }
    v
}

/// Answers `request`.
/// `rejected` is the link's count of undecodable frames (for the status counters).
pub fn handle<F: NorFlash + FlashWindow>(
    upload: &mut UploadTracker,
    c: &mut Controller<F>,
    request: Request,
    rejected: u32,
) -> Response {
    let limits = UploadLimits {
        slots: c.store().slots(),
        slot_capacity: c.store().max_table_len(),
    };
    match request {
        Request::GetDeviceInfo => Response::DeviceInfo(DeviceInfo {
            firmware: version(),
            protocol_version: PROTOCOL_VERSION,
            table_format_version: FORMAT_VERSION,
            build_id: 0,
            capabilities: CAPABILITIES,
            slot_capacity: limits.slot_capacity,
            max_chunk_len: protocol::MAX_CHUNK_LEN as u16,
            slots: slots(c),
        }),
        Request::GetStatus => {
            let k = c.counters();
            let playback = match (c.selected_slot(), c.play_clock(), c.playback()) {
                (Some(slot), Some(p), Some((step, slice))) if c.state().plays() => {
                    Some(PlaybackPosition {
                        slot,
                        direction: match p.direction() {
                            Direction::Forward => protocol::Direction::Forward,
                            Direction::Backward => protocol::Direction::Backward,
                        },
                        period_scale: p.scale().min(u16::MAX.into()) as u16,
                        step,
                        slice,
                    })
                }
                _ => None,
            };
            let torque = if c.torque_on() {
                (1u64 << c.joints().len()).wrapping_sub(1) as u32
            } else {
                0
            };
            Response::Status(Status {
                state: run_state(c.state()),
                fault: fault(c.state()),
                playback,
                upload: upload.progress(),
                torque_enabled: torque,
                counters: protocol::Counters {
                    cycles: k.cycles,
                    missed_deadlines: k.overruns,
                    bus_timeouts: k.timeouts,
                    crc_errors: k.crc_errors,
                    rejected_frames: rejected,
                    telemetry_dropped: c.telemetry_dropped(),
                },
            })
        }
        Request::ListGaits => Response::Slots(slots(c)),
        Request::UploadBegin {
            slot,
            header,
            total_len,
        } => {
            if let Err(e) = upload.begin(slot, &header, total_len, &limits) {
                return Response::Error(e.into());
            }
            match c.upload_begin(slot, total_len) {
                Ok(()) => Response::Ack,
                Err(e) => {
                    let _ = upload.abort();
                    Response::Error(command_error(e))
                }
            }
        }
        Request::UploadChunk { offset, data } => {
            // Refuse while moving before the tracker counts the chunk.
            if !c.state().allows_flash_writes() {
                return Response::Error(ProtocolError::WrongState {
                    state: run_state(c.state()),
                });
            }
            let received = match upload.chunk(offset, &data) {
                Ok(r) => r,
                Err(e) => return Response::Error(e.into()),
            };
            match c.upload_chunk(offset, &data) {
                Ok(()) => Response::ChunkAccepted { received },
                Err(e) => {
                    // The store lost the upload (flash error): the tracker must not go on.
                    let _ = upload.abort();
                    Response::Error(command_error(e))
                }
            }
        }
        Request::UploadCommit { crc } => {
            if !c.state().allows_flash_writes() {
                return Response::Error(ProtocolError::WrongState {
                    state: run_state(c.state()),
                });
            }
            let finished = match upload.commit(crc) {
                Ok(f) => f,
                Err(e) => {
                    if matches!(e, protocol::UploadError::ChecksumMismatch { .. }) {
                        c.upload_abort();
                    }
                    return Response::Error(e.into());
                }
            };
            match c.upload_commit_verified(crc, |bytes| verify_stored(&finished, bytes).map(|_| ()))
            {
                Ok(info) => Response::Committed {
                    slot: info.slot,
                    crc: info.crc,
                },
                Err(CommitError::Rejected(e)) => Response::Error(e.into()),
                Err(CommitError::Store(e)) => Response::Error(store_error(e)),
            }
        }
        Request::UploadAbort => {
            c.upload_abort();
            match upload.abort() {
                Ok(_) => Response::Ack,
                Err(e) => Response::Error(e.into()),
            }
        }
        Request::DeleteGait { slot } => ack(c.delete_gait(slot), command_error),
        Request::Play(p) => ack(
            c.play(PlayParams {
                slot: p.slot,
                direction: match p.direction {
                    protocol::Direction::Forward => Direction::Forward,
                    protocol::Direction::Backward => Direction::Backward,
                },
                period_scale: p.period_scale,
                steps: match p.steps {
                    Steps::Continuous => None,
                    Steps::Count(n) => Some(n),
                },
            }),
            command_error,
        ),
        Request::Stop => ack(c.stop(), command_error),
        Request::SetPeriodScale { scale } => ack(c.set_period_scale(scale), command_error),
        Request::GetSettings => {
            let mut joints = heapless::Vec::new();
            for (cal, &k) in c.joints().iter().zip(c.stiffness()) {
                let a = cal.calibration.ticks_to_angle(cal.min_ticks);
                let b = cal.calibration.ticks_to_angle(cal.max_ticks);
                let _ = joints.push(JointSettings {
                    stiffness: k,
                    min: a.min(b),
                    max: a.max(b),
                    torque_enabled: c.torque_on(),
                });
            }
            let cfg = c.config();
            Response::Settings(Settings {
                baud: cfg.baud,
                cycle_hz: cfg.cycle_hz,
                telemetry_every: cfg.telemetry_every,
                joints,
            })
        }
        Request::SetBus { baud, cycle_hz } => ack(c.set_bus(baud, cycle_hz), command_error),
        Request::SetStiffness { joint, stiffness } => {
            ack(c.set_stiffness(joint, stiffness), command_error)
        }
        Request::SetLimits { joint, min, max } => {
            let Some(cal) = c.joints().get(usize::from(joint)).copied() else {
                return Response::Error(ProtocolError::NoSuchJoint {
                    joint,
                    joints: c.joints().len() as u8,
                });
            };
            let a = cal.calibration.angle_to_ticks(min.into());
            let b = cal.calibration.angle_to_ticks(max.into());
            if min > max {
                return Response::Error(ProtocolError::InvalidSetting {
                    setting: protocol::Setting::Limits,
                    value: min.into(),
                });
            }
            ack(c.set_limits(joint, a.min(b), a.max(b)), command_error)
        }
        Request::SetTorque {
            servos: ServoSelect::All,
            enable,
        } => ack(c.set_torque(enable), command_error),
        Request::RebootServos { servos } => ack(
            c.reboot_servos(match servos {
                ServoSelect::All => None,
                ServoSelect::Joint(j) => Some(j),
            }),
            command_error,
        ),
        // Torque acts on the whole robot: the state machine has no per-servo torque.
        Request::SetTorque { .. } => Response::Error(ProtocolError::Unsupported),
        Request::EmergencyStop => {
            c.emergency_stop();
            Response::Ack
        }
        Request::ClearFault => ack(c.clear_fault(), command_error),
        Request::SetTelemetry { every } => {
            c.set_telemetry(every);
            Response::Ack
        }
        Request::EnterStreaming(s) => ack(
            c.enter_streaming(s.timeout_cycles, s.feedback_every),
            command_error,
        ),
        Request::LeaveStreaming => ack(c.leave_streaming(), command_error),
        _ => Response::Error(ProtocolError::Unsupported),
    }
}

/// A streamed setpoint (no reply: the proprioception stream names the last one taken).
pub fn setpoint<F: NorFlash + FlashWindow>(c: &mut Controller<F>, sp: &Setpoint) {
    let mut joints: heapless::Vec<(i32, Option<i32>), { protocol::MAX_JOINTS }> =
        heapless::Vec::new();
    for j in &sp.joints {
        let _ = joints.push((
            i32::from(j.angle) * URAD_PER_ANGLE_UNIT,
            j.torque.map(i32::from),
        ));
    }
    // A setpoint outside streaming or of the wrong length is dropped; the age in Proprioception
    // shows the host that it was not taken.
    let _ = c.setpoint(sp.seq, &joints);
}
