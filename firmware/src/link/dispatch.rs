//! The board's [`Handler`]: one short method per typed request (`protocol::endpoint`), each
//! returning its reply type or the error that travels back as data; [`handle`] is the protocol's
//! `dispatch` over them. Upload steps go through the protocol's `UploadTracker` first (so board
//! and host share one set of rules and error names), then to the gait store, which verifies the
//! bytes in flash before it commits.

use embedded_storage::nor_flash::NorFlash;
use protocol::endpoint::{self as ep, ChunkAccepted, Committed, Handler, Slots};
use protocol::gait::{FORMAT_VERSION, GaitTable};
use protocol::upload::verify_stored;
use protocol::{
    Capabilities, DeviceInfo, FirmwareVersion, GaitHeader, GaitSummary, JointIds, JointSettings,
    LossReason, LostCopy, PROTOCOL_VERSION, PlayCommand, PlaybackPosition, ProtocolError,
    QueueCommand, Request, Response, ServoSelect, Setpoint, Settings, SlotInfo, Status, Steps,
    StreamConfig, UploadLimits, UploadTracker,
};

use super::convert::{command_error, fault, run_state, store_error};
use crate::controller::{Controller, PlayParams};
use crate::gait_view::URAD_PER_ANGLE_UNIT;
use crate::playback::Direction;
use crate::store::{self, CommitError, FlashWindow};

/// What this firmware can do.
pub const CAPABILITIES: Capabilities = Capabilities::GAIT_STORE
    .union(Capabilities::PLAYBACK)
    .union(Capabilities::TELEMETRY)
    .union(Capabilities::STREAMING)
    .union(Capabilities::TORQUE_FEED_FORWARD)
    .union(Capabilities::BUS_SETTINGS);

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
        let _ = v.push(SlotInfo {
            slot,
            gait,
            lost: lost_copy(c, slot),
        });
    }
    v
}

/// What the store lost in `slot` at mount, with the lost table's name if its header still reads.
fn lost_copy<F: NorFlash + FlashWindow>(c: &Controller<F>, slot: u8) -> Option<LostCopy> {
    let l = c.store().lost(slot)?;
    let bytes = c.store().lost_bytes(slot);
    let name = bytes.and_then(GaitHeader::peek).map(|h| h.name);
    // The table's own CRC (its last 4 bytes), the number a host knows the gait by; the record's CRC
    // covers those 4 bytes too, so it is another number.
    let crc = l
        .len
        .and(bytes)
        .and_then(|b| b.last_chunk::<4>())
        .map(|w| u32::from_le_bytes(*w));
    Some(LostCopy {
        seq: l.seq,
        crc,
        reason: match l.reason {
            store::LossReason::TableChecksum { .. } => LossReason::TableChecksum,
            store::LossReason::RecordDamaged => LossReason::RecordDamaged,
        },
        name,
    })
}

/// Answers `request`.
/// `rejected` is the link's count of undecodable frames (for the status counters).
pub fn handle<F: NorFlash + FlashWindow>(
    upload: &mut UploadTracker,
    c: &mut Controller<F>,
    request: Request,
    rejected: u32,
) -> Response {
    // Any request is the host's sign of life for the host-loss rule of endless runs.
    c.host_contact();
    protocol::endpoint::dispatch(
        &mut Service {
            upload,
            c,
            rejected,
        },
        request,
    )
}

/// What a request may touch: the upload in progress and the controller.
struct Service<'a, F: NorFlash + FlashWindow> {
    upload: &'a mut UploadTracker,
    c: &'a mut Controller<F>,
    rejected: u32,
}

impl<F: NorFlash + FlashWindow> Service<'_, F> {
    fn limits(&self) -> UploadLimits {
        UploadLimits {
            slots: self.c.store().slots(),
            slot_capacity: self.c.store().max_table_len(),
        }
    }

    /// Flash is written only while nothing moves; refused before the tracker counts anything.
    fn flash_writable(&self) -> Result<(), ProtocolError> {
        if self.c.state().allows_flash_writes() {
            Ok(())
        } else {
            Err(ProtocolError::WrongState {
                state: run_state(self.c.state()),
            })
        }
    }
}

impl<F: NorFlash + FlashWindow> Handler for Service<'_, F> {
    fn get_device_info(&mut self, _: ep::GetDeviceInfo) -> Result<DeviceInfo, ProtocolError> {
        Ok(DeviceInfo {
            firmware: version(),
            protocol_version: PROTOCOL_VERSION,
            table_format_version: FORMAT_VERSION,
            build_id: crate::build_id::BUILD_ID,
            capabilities: CAPABILITIES,
            slot_capacity: self.limits().slot_capacity,
            max_chunk_len: protocol::MAX_CHUNK_LEN as u16,
            slots: slots(self.c),
        })
    }

    fn get_status(&mut self, _: ep::GetStatus) -> Result<Status, ProtocolError> {
        let c = &*self.c;
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
        Ok(Status {
            state: run_state(c.state()),
            fault: fault(c.state()),
            playback,
            upload: self.upload.progress(),
            torque_enabled: torque,
            counters: protocol::Counters {
                cycles: k.cycles,
                missed_deadlines: k.overruns,
                bus_timeouts: k.timeouts,
                crc_errors: k.crc_errors,
                rejected_frames: self.rejected,
                telemetry_dropped: c.telemetry_dropped(),
                rate_limited: k.rate_limited,
            },
            health_warning: c.health_warning(),
            health_stop: c.health_stop(),
        })
    }

    fn list_gaits(&mut self, _: ep::ListGaits) -> Result<Slots, ProtocolError> {
        Ok(slots(self.c))
    }

    fn upload_begin(&mut self, r: ep::UploadBegin) -> Result<(), ProtocolError> {
        let limits = self.limits();
        self.upload.begin(r.slot, &r.header, r.total_len, &limits)?;
        self.c.upload_begin(r.slot, r.total_len).map_err(|e| {
            let _ = self.upload.abort();
            command_error(e)
        })
    }

    fn upload_chunk(&mut self, r: ep::UploadChunk) -> Result<ChunkAccepted, ProtocolError> {
        self.flash_writable()?;
        let received = self.upload.chunk(r.offset, &r.data)?;
        match self.c.upload_chunk(r.offset, &r.data) {
            Ok(()) => Ok(ChunkAccepted { received }),
            Err(e) => {
                // The store lost the upload (flash error): the tracker must not go on.
                let _ = self.upload.abort();
                Err(command_error(e))
            }
        }
    }

    fn upload_commit(&mut self, r: ep::UploadCommit) -> Result<Committed, ProtocolError> {
        self.flash_writable()?;
        let finished = self.upload.commit(r.crc).inspect_err(|e| {
            if matches!(e, protocol::UploadError::ChecksumMismatch { .. }) {
                self.c.upload_abort();
            }
        })?;
        match self
            .c
            .upload_commit_verified(r.crc, |bytes| verify_stored(&finished, bytes).map(|_| ()))
        {
            Ok(info) => Ok(Committed {
                slot: info.slot,
                crc: info.crc,
            }),
            Err(CommitError::Rejected(e)) => Err(e.into()),
            Err(CommitError::Store(e)) => Err(store_error(e)),
        }
    }

    fn upload_abort(&mut self, _: ep::UploadAbort) -> Result<(), ProtocolError> {
        self.c.upload_abort();
        self.upload.abort().map(|_| ()).map_err(Into::into)
    }

    fn delete_gait(&mut self, r: ep::DeleteGait) -> Result<(), ProtocolError> {
        self.c.delete_gait(r.slot).map_err(command_error)
    }

    fn play(&mut self, p: PlayCommand) -> Result<(), ProtocolError> {
        self.c
            .play(play_params(p.slot, p.direction, p.period_scale, p.steps))
            .map_err(command_error)
    }

    fn queue_gait(&mut self, QueueCommand(q): QueueCommand) -> Result<(), ProtocolError> {
        self.c
            .queue_gait(play_params(q.slot, q.direction, q.period_scale, q.steps))
            .map_err(command_error)
    }

    fn clear_queue(&mut self, _: ep::ClearQueue) -> Result<(), ProtocolError> {
        self.c.clear_queue().map_err(command_error)
    }

    fn set_steer_family(&mut self, f: protocol::SteerFamily) -> Result<(), ProtocolError> {
        self.c.set_steer_family(f).map_err(command_error)
    }

    fn steer(&mut self, s: protocol::SteerCommand) -> Result<(), ProtocolError> {
        self.c.steer(s).map_err(command_error)
    }

    fn set_platform(&mut self, setup: protocol::PlatformSetup) -> Result<(), ProtocolError> {
        self.c.set_platform(setup).map_err(command_error)
    }

    fn clear_platform(&mut self, _: ep::ClearPlatform) -> Result<(), ProtocolError> {
        self.c.clear_platform().map_err(command_error)
    }

    fn get_platform(
        &mut self,
        _: ep::GetPlatform,
    ) -> Result<Option<protocol::PlatformStatus>, ProtocolError> {
        Ok(self.c.platform())
    }

    fn stop(&mut self, _: ep::Stop) -> Result<(), ProtocolError> {
        self.c.stop().map_err(command_error)
    }

    fn set_period_scale(&mut self, r: ep::SetPeriodScale) -> Result<(), ProtocolError> {
        self.c.set_period_scale(r.scale).map_err(command_error)
    }

    fn get_settings(&mut self, _: ep::GetSettings) -> Result<Settings, ProtocolError> {
        let c = &*self.c;
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
        Ok(Settings {
            baud: cfg.baud,
            cycle_hz: cfg.cycle_hz,
            telemetry_every: cfg.telemetry_every,
            joints,
            health: c.health_limits(),
        })
    }

    fn set_bus(&mut self, r: ep::SetBus) -> Result<(), ProtocolError> {
        self.c.set_bus(r.baud, r.cycle_hz).map_err(command_error)
    }

    fn set_stiffness(&mut self, r: ep::SetStiffness) -> Result<(), ProtocolError> {
        self.c
            .set_stiffness(r.joint, r.stiffness)
            .map_err(command_error)
    }

    fn set_limits(&mut self, r: ep::SetLimits) -> Result<(), ProtocolError> {
        let Some(cal) = self.c.joints().get(usize::from(r.joint)).copied() else {
            return Err(ProtocolError::NoSuchJoint {
                joint: r.joint,
                joints: self.c.joints().len() as u8,
            });
        };
        if r.min > r.max {
            return Err(ProtocolError::InvalidSetting {
                setting: protocol::Setting::Limits,
                value: r.min.into(),
            });
        }
        let a = cal.calibration.angle_to_ticks(r.min.into());
        let b = cal.calibration.angle_to_ticks(r.max.into());
        self.c
            .set_limits(r.joint, a.min(b), a.max(b))
            .map_err(command_error)
    }

    fn set_torque(&mut self, r: ep::SetTorque) -> Result<(), ProtocolError> {
        match r.servos {
            ServoSelect::All => self.c.set_torque(r.enable).map_err(command_error),
            // Torque acts on the whole robot: the state machine has no per-servo torque.
            ServoSelect::Joint(_) => Err(ProtocolError::Unsupported),
        }
    }

    fn reboot_servos(&mut self, r: ep::RebootServos) -> Result<(), ProtocolError> {
        let joint = match r.servos {
            ServoSelect::All => None,
            ServoSelect::Joint(j) => Some(j),
        };
        self.c.reboot_servos(joint).map_err(command_error)
    }

    fn emergency_stop(&mut self, _: ep::EmergencyStop) -> Result<(), ProtocolError> {
        self.c.emergency_stop();
        Ok(())
    }

    fn clear_fault(&mut self, _: ep::ClearFault) -> Result<(), ProtocolError> {
        self.c.clear_fault().map_err(command_error)
    }

    fn read_servo(&mut self, r: protocol::ServoRead) -> Result<(), ProtocolError> {
        use crate::controller::ServoReadError;
        self.c
            .read_servo(r)
            .map_err(|e| ProtocolError::InvalidSetting {
                setting: protocol::Setting::ServoRead,
                value: match e {
                    ServoReadError::Id(id) => i32::from(id),
                    ServoReadError::Len(len) => i32::from(len),
                },
            })
    }

    fn get_servo_read(
        &mut self,
        _: ep::GetServoRead,
    ) -> Result<Option<protocol::ServoReadResult>, ProtocolError> {
        Ok(self.c.servo_read_result())
    }

    fn set_health_limits(&mut self, r: protocol::HealthLimits) -> Result<(), ProtocolError> {
        self.c
            .set_health_limits(r)
            .map_err(|e| ProtocolError::InvalidSetting {
                setting: protocol::Setting::HealthLimits,
                value: e.value(),
            })
    }

    fn set_telemetry(&mut self, r: ep::SetTelemetry) -> Result<(), ProtocolError> {
        self.c.set_telemetry(r.every);
        Ok(())
    }

    fn enter_streaming(&mut self, s: StreamConfig) -> Result<(), ProtocolError> {
        self.c
            .enter_streaming(s.timeout_cycles, s.feedback_every)
            .map_err(command_error)
    }

    fn leave_streaming(&mut self, _: ep::LeaveStreaming) -> Result<(), ProtocolError> {
        self.c.leave_streaming().map_err(command_error)
    }

    fn get_joint_map(&mut self, r: ep::GetJointMap) -> Result<Option<JointIds>, ProtocolError> {
        let Some(slot) = r.slot else {
            // The joint map in use is the selected table's (select takes it over).
            return Ok(self.c.selected_slot().map(|slot| JointIds {
                slot,
                servo_ids: self.c.joints().iter().map(|j| j.id).collect(),
            }));
        };
        let slots = self.c.store().slots();
        if slot >= slots {
            return Err(ProtocolError::NoSuchSlot { slot, slots });
        }
        let Some(table) = self.c.store().table(slot) else {
            return Ok(None);
        };
        let table = GaitTable::parse(table).map_err(ProtocolError::Table)?;
        Ok(Some(JointIds {
            slot,
            servo_ids: (0..table.joint_count())
                .filter_map(|j| table.joint(j))
                .map(|m| m.servo_id)
                .collect(),
        }))
    }
}

/// The controller's play parameters of a `Play` or `QueueGait`.
fn play_params(
    slot: u8,
    direction: protocol::Direction,
    period_scale: u16,
    steps: Steps,
) -> PlayParams {
    PlayParams {
        slot,
        direction: match direction {
            protocol::Direction::Forward => Direction::Forward,
            protocol::Direction::Backward => Direction::Backward,
        },
        period_scale,
        steps: match steps {
            Steps::Continuous => None,
            Steps::Count(n) => Some(n),
        },
    }
}

/// A streamed setpoint (no reply: the proprioception stream names the last one taken).
pub fn setpoint<F: NorFlash + FlashWindow>(c: &mut Controller<F>, sp: &Setpoint) {
    c.host_contact();
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
