//! Proptest strategies for every message type and for gait tables of random shape.
#![allow(dead_code)]

pub mod golden_table;

use proptest::collection::vec;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use protocol::gait::{JointField, MAX_SLICES, NAME_LEN, TableError};
use protocol::*;

pub fn hvec<T: core::fmt::Debug, const N: usize>(
    item: impl Strategy<Value = T>,
    max: usize,
) -> impl Strategy<Value = heapless::Vec<T, N>> {
    vec(item, 0..=max.min(N)).prop_map(|v| v.into_iter().collect::<heapless::Vec<T, N>>())
}

pub fn header() -> impl Strategy<Value = GaitHeader> {
    (
        any::<u8>(),
        any::<u16>(),
        any::<u32>(),
        any::<u16>(),
        any::<[u8; NAME_LEN]>(),
    )
        .prop_map(
            |(joint_count, slice_count, step_period_us, duty, name)| GaitHeader {
                joint_count,
                slice_count,
                step_period_us,
                duty,
                name,
            },
        )
}

pub fn run_state() -> impl Strategy<Value = RunState> {
    prop_oneof![
        Just(RunState::Idle),
        Just(RunState::Standing),
        Just(RunState::Ramping),
        Just(RunState::Walking),
        Just(RunState::Stopping),
        Just(RunState::Streaming),
        Just(RunState::Fault),
        Just(RunState::Boot),
    ]
}

pub fn direction() -> impl Strategy<Value = Direction> {
    prop_oneof![Just(Direction::Forward), Just(Direction::Backward)]
}

pub fn servo_select() -> impl Strategy<Value = ServoSelect> {
    prop_oneof![
        Just(ServoSelect::All),
        any::<u8>().prop_map(ServoSelect::Joint)
    ]
}

pub fn request() -> impl Strategy<Value = Request> {
    let steps = prop_oneof![Just(Steps::Continuous), any::<u32>().prop_map(Steps::Count)];
    let play = (any::<u8>(), direction(), any::<u16>(), steps).prop_map(
        |(slot, direction, period_scale, steps)| {
            Request::Play(PlayCommand {
                slot,
                direction,
                period_scale,
                steps,
            })
        },
    );
    prop_oneof![
        Just(Request::GetDeviceInfo),
        Just(Request::GetStatus),
        Just(Request::ListGaits),
        (any::<u8>(), header(), any::<u32>()).prop_map(|(slot, header, total_len)| {
            Request::UploadBegin {
                slot,
                header,
                total_len,
            }
        }),
        (any::<u32>(), hvec(any::<u8>(), MAX_CHUNK_LEN))
            .prop_map(|(offset, data)| Request::UploadChunk { offset, data }),
        any::<u32>().prop_map(|crc| Request::UploadCommit { crc }),
        Just(Request::UploadAbort),
        any::<u8>().prop_map(|slot| Request::DeleteGait { slot }),
        play,
        Just(Request::Stop),
        any::<u16>().prop_map(|scale| Request::SetPeriodScale { scale }),
        Just(Request::GetSettings),
        (any::<u32>(), any::<u16>())
            .prop_map(|(baud, cycle_hz)| Request::SetBus { baud, cycle_hz }),
        (any::<u8>(), any::<u32>())
            .prop_map(|(joint, stiffness)| Request::SetStiffness { joint, stiffness }),
        (any::<u8>(), any::<i16>(), any::<i16>())
            .prop_map(|(joint, min, max)| Request::SetLimits { joint, min, max }),
        (servo_select(), any::<bool>())
            .prop_map(|(servos, enable)| Request::SetTorque { servos, enable }),
        servo_select().prop_map(|servos| Request::RebootServos { servos }),
        Just(Request::EmergencyStop),
        Just(Request::ClearFault),
        any::<u16>().prop_map(|every| Request::SetTelemetry { every }),
        (any::<u16>(), any::<u16>()).prop_map(|(timeout_cycles, feedback_every)| {
            Request::EnterStreaming(StreamConfig {
                timeout_cycles,
                feedback_every,
            })
        }),
        Just(Request::LeaveStreaming),
        any::<Option<u8>>().prop_map(|slot| Request::GetJointMap { slot }),
        platform_setup().prop_map(Request::SetPlatform),
        Just(Request::ClearPlatform),
        Just(Request::GetPlatform),
        health_limits().prop_map(Request::SetHealthLimits),
        servo_read().prop_map(Request::ReadServo),
        Just(Request::GetServoRead),
    ]
}

pub fn platform_setup() -> impl Strategy<Value = PlatformSetup> {
    let moves = prop_oneof![Just(PlatformMove::Rise), Just(PlatformMove::Fall)];
    (
        any::<(u8, u16, u16, u16, u16)>(),
        moves,
        any::<(u32, u16)>(),
    )
        .prop_map(
            |((servo_id, rest, rise, fall, profile_velocity), moves, (step, hold_cycles))| {
                PlatformSetup {
                    servo_id,
                    rest,
                    rise,
                    fall,
                    profile_velocity,
                    moves,
                    step,
                    hold_cycles,
                }
            },
        )
}

pub fn platform_status() -> impl Strategy<Value = PlatformStatus> {
    let state = prop_oneof![
        Just(PlatformState::Checking),
        any::<u16>().prop_map(|present| PlatformState::Ready { present }),
        Just(PlatformState::NotAnswering),
    ];
    (platform_setup(), state).prop_map(|(setup, state)| PlatformStatus { setup, state })
}

pub fn platform_feedback() -> impl Strategy<Value = PlatformFeedback> {
    any::<(u8, u16, u16, u8)>().prop_map(|(servo_id, goal, present, flags)| PlatformFeedback {
        servo_id,
        goal,
        present,
        flags,
    })
}

pub fn setpoint() -> impl Strategy<Value = Setpoint> {
    let joint = (any::<i16>(), any::<Option<i16>>())
        .prop_map(|(angle, torque)| JointSetpoint { angle, torque });
    (any::<u32>(), hvec(joint, MAX_JOINTS)).prop_map(|(seq, joints)| Setpoint { seq, joints })
}

/// `cases` cases a property, failures kept beside the test file in `proptest-regressions`, where
/// proptest reads them back.
pub fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..ProptestConfig::default()
    }
}

pub fn host_message() -> impl Strategy<Value = HostMessage> {
    prop_oneof![
        (any::<u16>(), request()).prop_map(|(seq, request)| HostMessage::Request { seq, request }),
        setpoint().prop_map(HostMessage::Setpoint),
    ]
}

pub fn table_error() -> impl Strategy<Value = TableError> {
    let field = prop_oneof![
        Just(JointField::ServoId),
        Just(JointField::Model),
        Just(JointField::Sign),
        Just(JointField::ZeroOffset),
        Just(JointField::Limits),
        Just(JointField::Stiffness),
        Just(JointField::Leg),
        Just(JointField::Reserved),
    ];
    prop_oneof![
        (any::<u32>(), any::<u32>())
            .prop_map(|(len, needed)| TableError::Truncated { len, needed }),
        any::<[u8; 4]>().prop_map(|found| TableError::BadMagic { found }),
        (any::<u16>(), any::<u16>())
            .prop_map(|(found, supported)| TableError::UnsupportedVersion { found, supported }),
        any::<u8>().prop_map(|count| TableError::BadJointCount { count }),
        any::<u16>().prop_map(|count| TableError::BadSliceCount { count }),
        any::<u16>().prop_map(|duty| TableError::BadDuty { duty }),
        Just(TableError::BadPeriod),
        any::<u8>().prop_map(|offset| TableError::Reserved { offset }),
        (any::<u32>(), any::<u32>())
            .prop_map(|(declared, computed)| TableError::LengthMismatch { declared, computed }),
        (any::<u32>(), any::<u32>())
            .prop_map(|(stored, computed)| TableError::Crc { stored, computed }),
        (any::<u8>(), field).prop_map(|(joint, field)| TableError::BadJoint { joint, field }),
        (any::<u16>(), any::<u8>()).prop_map(|(slice, bits)| TableError::BadStance { slice, bits }),
        (any::<u16>(), any::<u8>(), any::<i16>()).prop_map(|(slice, joint, angle)| {
            TableError::AngleOutOfLimits {
                slice,
                joint,
                angle,
            }
        }),
    ]
}

pub fn upload_error() -> impl Strategy<Value = UploadError> {
    let u = || any::<u32>();
    prop_oneof![
        Just(UploadError::NotStarted),
        (any::<u8>(), any::<u8>())
            .prop_map(|(slot, slots)| UploadError::NoSuchSlot { slot, slots }),
        table_error().prop_map(UploadError::BadHeader),
        (u(), u()).prop_map(|(total_len, expected)| UploadError::LengthMismatch {
            total_len,
            expected
        }),
        (u(), u()).prop_map(|(total_len, capacity)| UploadError::TooLarge {
            total_len,
            capacity
        }),
        u().prop_map(|offset| UploadError::EmptyChunk { offset }),
        (u(), u(), u()).prop_map(|(offset, len, max)| UploadError::ChunkTooLong {
            offset,
            len,
            max
        }),
        (u(), u(), u()).prop_map(|(offset, len, total_len)| UploadError::PastEnd {
            offset,
            len,
            total_len
        }),
        (u(), u()).prop_map(|(offset, received)| UploadError::Duplicate { offset, received }),
        (u(), u()).prop_map(|(offset, expected)| UploadError::OutOfOrder { offset, expected }),
        (u(), u()).prop_map(|(received, total_len)| UploadError::Truncated {
            received,
            total_len
        }),
        (u(), u())
            .prop_map(|(expected, computed)| UploadError::ChecksumMismatch { expected, computed }),
        table_error().prop_map(UploadError::Table),
        Just(UploadError::HeaderMismatch),
    ]
}

pub fn frame_error() -> impl Strategy<Value = FrameError> {
    prop_oneof![
        Just(FrameError::Cobs),
        Just(FrameError::TooLong),
        any::<u16>().prop_map(|len| FrameError::TooShort { len }),
        (any::<u32>(), any::<u32>())
            .prop_map(|(stored, computed)| FrameError::Crc { stored, computed }),
        Just(FrameError::Decode),
        any::<u16>().prop_map(|extra| FrameError::TrailingBytes { extra }),
        Just(FrameError::BufferTooSmall),
    ]
}

pub fn protocol_error() -> impl Strategy<Value = ProtocolError> {
    let setting = prop_oneof![
        Just(Setting::Baud),
        Just(Setting::CycleRate),
        Just(Setting::Stiffness),
        Just(Setting::Limits),
        Just(Setting::PeriodScale),
        Just(Setting::StepCount),
        Just(Setting::Telemetry),
        Just(Setting::StreamTimeout),
        Just(Setting::StreamFeedback),
        Just(Setting::SetpointJoints),
        Just(Setting::HealthLimits),
        Just(Setting::ServoRead),
    ];
    prop_oneof![
        Just(ProtocolError::Unsupported),
        run_state().prop_map(|state| ProtocolError::WrongState { state }),
        (any::<u8>(), any::<u8>())
            .prop_map(|(slot, slots)| ProtocolError::NoSuchSlot { slot, slots }),
        any::<u8>().prop_map(|slot| ProtocolError::SlotEmpty { slot }),
        any::<u8>().prop_map(|slot| ProtocolError::SlotBusy { slot }),
        (any::<u8>(), any::<u8>())
            .prop_map(|(joint, joints)| ProtocolError::NoSuchJoint { joint, joints }),
        (setting, any::<i32>())
            .prop_map(|(setting, value)| ProtocolError::InvalidSetting { setting, value }),
        upload_error().prop_map(ProtocolError::Upload),
        table_error().prop_map(ProtocolError::Table),
        any::<u32>().prop_map(|offset| ProtocolError::Flash { offset }),
        frame_error().prop_map(ProtocolError::Frame),
        (any::<u8>(), any::<u8>()).prop_map(|(servo_id, joint)| ProtocolError::Platform(
            PlatformError::JointId { servo_id, joint }
        )),
        (any::<u32>(), any::<u32>()).prop_map(|(step, steps)| ProtocolError::Platform(
            PlatformError::StepBeyondRun { step, steps }
        )),
        any::<u8>()
            .prop_map(|servo_id| ProtocolError::Platform(PlatformError::NotAnswering { servo_id })),
    ]
}

pub fn fault() -> impl Strategy<Value = Fault> {
    let kind = prop_oneof![
        Just(FaultKind::EmergencyStop),
        any::<u8>().prop_map(|bits| FaultKind::ServoError { bits }),
        any::<u8>().prop_map(|cycles| FaultKind::ServoMissing { cycles }),
        Just(FaultKind::SetpointTimeout),
        Just(FaultKind::Watchdog),
    ];
    (kind, any::<Option<u8>>()).prop_map(|(kind, joint)| Fault { kind, joint })
}

pub fn lost_copy() -> impl Strategy<Value = LostCopy> {
    let reason = prop_oneof![
        Just(LossReason::TableChecksum),
        Just(LossReason::RecordDamaged)
    ];
    (
        any::<Option<u32>>(),
        any::<Option<u32>>(),
        reason,
        any::<Option<[u8; protocol::gait::NAME_LEN]>>(),
    )
        .prop_map(|(seq, crc, reason, name)| LostCopy {
            seq,
            crc,
            reason,
            name,
        })
}

pub fn slot_info() -> impl Strategy<Value = SlotInfo> {
    let summary = (header(), any::<u32>()).prop_map(|(header, crc)| GaitSummary { header, crc });
    (
        any::<u8>(),
        proptest::option::of(summary),
        proptest::option::of(lost_copy()),
    )
        .prop_map(|(slot, gait, lost)| SlotInfo { slot, gait, lost })
}

pub fn joint_ids() -> impl Strategy<Value = JointIds> {
    (any::<u8>(), hvec(any::<u8>(), MAX_JOINTS))
        .prop_map(|(slot, servo_ids)| JointIds { slot, servo_ids })
}

pub fn device_info() -> impl Strategy<Value = DeviceInfo> {
    (
        any::<(u16, u16, u16)>(),
        any::<(u16, u16, u32, u32)>(),
        any::<(u32, u16)>(),
        hvec(slot_info(), MAX_SLOTS),
    )
        .prop_map(
            |(
                (major, minor, patch),
                (pv, tv, build_id, caps),
                (slot_capacity, max_chunk_len),
                slots,
            )| {
                DeviceInfo {
                    firmware: FirmwareVersion {
                        major,
                        minor,
                        patch,
                    },
                    protocol_version: pv,
                    table_format_version: tv,
                    build_id,
                    capabilities: Capabilities(caps),
                    slot_capacity,
                    max_chunk_len,
                    slots,
                }
            },
        )
}

pub fn status() -> impl Strategy<Value = Status> {
    let playback = (
        any::<u8>(),
        direction(),
        any::<u16>(),
        any::<u32>(),
        any::<u16>(),
    )
        .prop_map(
            |(slot, direction, period_scale, step, slice)| PlaybackPosition {
                slot,
                direction,
                period_scale,
                step,
                slice,
            },
        );
    let upload = any::<(u8, u32, u32)>().prop_map(|(slot, received, total_len)| UploadProgress {
        slot,
        received,
        total_len,
    });
    let counters = any::<[u32; 7]>().prop_map(|c| Counters {
        cycles: c[0],
        missed_deadlines: c[1],
        bus_timeouts: c[2],
        crc_errors: c[3],
        rejected_frames: c[4],
        telemetry_dropped: c[5],
        rate_limited: c[6],
    });
    (
        run_state(),
        proptest::option::of(fault()),
        proptest::option::of(playback),
        proptest::option::of(upload),
        any::<u32>(),
        counters,
    )
        .prop_map(
            |(state, fault, playback, upload, torque_enabled, counters)| Status {
                state,
                fault,
                playback,
                upload,
                torque_enabled,
                counters,
                health_warning: None,
                health_stop: None,
            },
        )
        .prop_flat_map(|s| {
            (
                Just(s),
                proptest::option::of(health_alarm()),
                proptest::option::of(health_alarm()),
            )
        })
        .prop_map(|(s, health_warning, health_stop)| Status {
            health_warning,
            health_stop,
            ..s
        })
}

pub fn health_alarm() -> impl Strategy<Value = HealthAlarm> {
    let kind = prop_oneof![
        Just(HealthKind::Hot),
        Just(HealthKind::LowVoltage),
        Just(HealthKind::HighVoltage)
    ];
    let level = prop_oneof![Just(HealthLevel::Warn), Just(HealthLevel::Stop)];
    (any::<(u8, u8, u16, u16)>(), kind, level).prop_map(
        |((joint, id, value, limit), kind, level)| HealthAlarm {
            joint,
            id,
            kind,
            level,
            value,
            limit,
        },
    )
}

pub fn health_limits() -> impl Strategy<Value = HealthLimits> {
    any::<(u8, u8, u16, u16, u16, u16)>().prop_map(|(a, b, c, d, e, f)| HealthLimits {
        warn_temperature_c: a,
        stop_temperature_c: b,
        warn_low_dv: c,
        stop_low_dv: d,
        warn_high_dv: e,
        stop_high_dv: f,
    })
}

pub fn servo_health() -> impl Strategy<Value = ServoHealth> {
    any::<(u8, u16)>().prop_map(|(temperature_c, voltage_dv)| ServoHealth {
        temperature_c,
        voltage_dv,
    })
}

pub fn settings() -> impl Strategy<Value = Settings> {
    let joint = (any::<u32>(), any::<i16>(), any::<i16>(), any::<bool>()).prop_map(
        |(stiffness, min, max, torque_enabled)| JointSettings {
            stiffness,
            min,
            max,
            torque_enabled,
        },
    );
    (
        any::<u32>(),
        any::<u16>(),
        any::<u16>(),
        hvec(joint, MAX_JOINTS),
        health_limits(),
    )
        .prop_map(
            |(baud, cycle_hz, telemetry_every, joints, health)| Settings {
                baud,
                cycle_hz,
                telemetry_every,
                joints,
                health,
            },
        )
}

pub fn response() -> impl Strategy<Value = Response> {
    prop_oneof![
        Just(Response::Ack),
        device_info().prop_map(Response::DeviceInfo),
        status().prop_map(Response::Status),
        settings().prop_map(Response::Settings),
        hvec(slot_info(), MAX_SLOTS).prop_map(Response::Slots),
        any::<u32>().prop_map(|received| Response::ChunkAccepted { received }),
        (any::<u8>(), any::<u32>()).prop_map(|(slot, crc)| Response::Committed { slot, crc }),
        protocol_error().prop_map(Response::Error),
        proptest::option::of(joint_ids()).prop_map(Response::JointMap),
        proptest::option::of(platform_status()).prop_map(Response::Platform),
        proptest::option::of(servo_read_result()).prop_map(Response::ServoRead),
    ]
}

pub fn servo_read() -> impl Strategy<Value = ServoRead> {
    any::<(u8, u16, u8)>().prop_map(|(id, addr, len)| ServoRead { id, addr, len })
}

pub fn servo_read_result() -> impl Strategy<Value = ServoReadResult> {
    let outcome = prop_oneof![
        (any::<u8>(), hvec(any::<u8>(), MAX_SERVO_READ))
            .prop_map(|(error, data)| ServoReadOutcome::Data { error, data }),
        any::<(u8, u16, u8)>().prop_map(|(error, model_number, firmware)| {
            ServoReadOutcome::Ping {
                error,
                model_number,
                firmware,
            }
        }),
        Just(ServoReadOutcome::Timeout),
        Just(ServoReadOutcome::Corrupt),
    ];
    (servo_read(), outcome).prop_map(|(request, outcome)| ServoReadResult { request, outcome })
}

pub fn feedback() -> impl Strategy<Value = JointFeedback> {
    any::<(i16, i16, i16, i16, u8, u8)>().prop_map(
        |(commanded, present, velocity, load, error, flags)| JointFeedback {
            commanded,
            present,
            velocity,
            load,
            error,
            flags,
        },
    )
}

pub fn bus_stats() -> impl Strategy<Value = BusStats> {
    any::<[u32; 4]>().prop_map(|b| BusStats {
        cycle_us: b[0],
        timeouts: b[1],
        crc_errors: b[2],
        missed_deadlines: b[3],
    })
}

pub fn device_message() -> impl Strategy<Value = DeviceMessage> {
    let telemetry = (
        any::<(u64, u32, u32, u16)>(),
        hvec(feedback(), MAX_JOINTS),
        bus_stats(),
        proptest::option::of(platform_feedback()),
        run_state(),
        hvec(servo_health(), MAX_JOINTS),
    )
        .prop_map(
            |((time_us, cycle, step, slice), joints, bus, platform, state, health)| {
                DeviceMessage::Telemetry(Telemetry {
                    time_us,
                    cycle,
                    step,
                    slice,
                    joints,
                    bus,
                    platform,
                    state,
                    health,
                })
            },
        );
    let proprio = (
        any::<(u64, u32, u32, u16)>(),
        hvec(feedback(), MAX_JOINTS),
        bus_stats(),
    )
        .prop_map(
            |((time_us, cycle, setpoint_seq, setpoint_age), joints, bus)| {
                DeviceMessage::Proprioception(Proprioception {
                    time_us,
                    cycle,
                    setpoint_seq,
                    setpoint_age,
                    joints,
                    bus,
                })
            },
        );
    prop_oneof![
        (any::<u16>(), response())
            .prop_map(|(seq, response)| DeviceMessage::Reply { seq, response }),
        telemetry,
        proprio,
        frame_error().prop_map(DeviceMessage::Rejected),
        (any::<u32>(), protocol_error())
            .prop_map(|(seq, error)| DeviceMessage::SetpointRejected { seq, error }),
    ]
}

/// A random but valid gait in SI units: joint specs, stance flags, angles (inside the limits), torques.
#[derive(Debug, Clone)]
pub struct RandomGait {
    pub name: String,
    pub period_s: f64,
    pub duty: f64,
    pub joints: Vec<JointSpec>,
    pub slices: Vec<(u8, Vec<f64>, Vec<f64>)>,
}

pub fn random_gait(max_joints: usize, max_slices: usize) -> impl Strategy<Value = RandomGait> {
    (1..=max_joints, 1..=max_slices.min(MAX_SLICES.into())).prop_flat_map(|(nj, ns)| {
        let joint = (
            any::<bool>(),
            any::<bool>(),
            0u16..=4095,
            -3.2f64..0.0,
            0.0f64..3.2,
            0.1f64..100.0,
        );
        let joints = vec(joint, nj);
        // Fractions in [0, 1] place each angle between the joint's limits.
        let slice = (0u8..64, vec(0.0f64..=1.0, nj), vec(-32.0f64..32.0, nj));
        (
            "[a-z]{0,16}",
            0.001f64..100.0,
            0.01f64..0.99,
            joints,
            vec(slice, ns),
        )
            .prop_map(move |(name, period_s, duty, joints, slices)| {
                let joints: Vec<JointSpec> = joints
                    .into_iter()
                    .enumerate()
                    .map(|(j, (mx64, neg, zero, min, max, k))| JointSpec {
                        name: format!("J{j}"),
                        servo_id: j as u8 + 1,
                        model: if mx64 {
                            ServoModel::Mx64
                        } else {
                            ServoModel::Mx28
                        },
                        sign: if neg { Sign::Negative } else { Sign::Positive },
                        zero_offset: zero,
                        min_rad: min,
                        max_rad: max,
                        stiffness_nm_per_rad: k,
                        leg: None,
                    })
                    .collect();
                let slices = slices
                    .into_iter()
                    .map(|(stance, frac, torque)| {
                        let angles = frac
                            .iter()
                            .zip(&joints)
                            .map(|(f, j)| j.min_rad + f * (j.max_rad - j.min_rad))
                            .collect();
                        (stance, angles, torque)
                    })
                    .collect();
                RandomGait {
                    name,
                    period_s,
                    duty,
                    joints,
                    slices,
                }
            })
    })
}

impl RandomGait {
    pub fn builder(&self) -> GaitTableBuilder {
        let mut b =
            GaitTableBuilder::new(&self.name, self.period_s, self.duty, self.joints.clone());
        for (stance, a, t) in &self.slices {
            b.slice(*stance, a, t);
        }
        b
    }
}
