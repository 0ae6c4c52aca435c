//! Round trips: every message survives frame encoding and reassembly from any chunking, and every
//! random gait table reads back what was planned (to the fixed-point resolution).

use crate::common;
use common::*;
use proptest::prelude::*;
use protocol::units::{
    ANGLE_PER_RAD, STIFFNESS_PER_NM_RAD, TORQUE_PER_NM, angle_to_rad, torque_to_nm,
};
use protocol::*;

/// Encodes `msg`, feeds the frame to a fresh accumulator in pieces cut at `cuts`, returns what came out.
fn through_link<T>(msg: &T, cuts: &[usize]) -> Vec<Result<T, FrameError>>
where
    T: serde::Serialize + serde::de::DeserializeOwned,
{
    let mut buf = [0u8; MAX_FRAME_LEN];
    let frame = encode_frame(msg, &mut buf).expect("every message fits MAX_FRAME_LEN");
    assert!(frame.len() <= MAX_FRAME_LEN);
    assert_eq!(frame.last(), Some(&0));
    assert!(
        !frame[..frame.len() - 1].contains(&0),
        "COBS leaves no zero inside a frame"
    );
    let mut acc = FrameAccumulator::new();
    let mut out = Vec::new();
    let mut start = 0;
    let mut cuts: Vec<usize> = cuts.iter().map(|c| c % (frame.len() + 1)).collect();
    cuts.sort_unstable();
    cuts.push(frame.len());
    for cut in cuts {
        out.extend(acc.messages::<T>(&frame[start..cut]));
        start = cut;
    }
    out
}

proptest! {
    #![proptest_config(common::config(512))]

    #[test]
    fn host_messages_round_trip(msg in host_message(), cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let out = through_link(&msg, &cuts);
        prop_assert_eq!(out, vec![Ok(msg)]);
    }

    #[test]
    fn device_messages_round_trip(msg in device_message(), cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let out = through_link(&msg, &cuts);
        prop_assert_eq!(out, vec![Ok(msg)]);
    }

    #[test]
    fn back_to_back_frames_come_out_in_order(msgs in proptest::collection::vec(host_message(), 1..6)) {
        let mut stream = Vec::new();
        for m in &msgs {
            stream.extend(protocol::frame::encode_frame_vec(m).unwrap());
        }
        let mut acc = FrameAccumulator::new();
        let out: Vec<_> = acc.messages::<HostMessage>(&stream).collect();
        prop_assert_eq!(out, msgs.into_iter().map(Ok).collect::<Vec<_>>());
    }

    #[test]
    fn random_gait_tables_read_back(g in random_gait(24, 40)) {
        let bytes = g.builder().build().unwrap();
        prop_assert_eq!(bytes.len(), gait::table_len(g.joints.len(), g.slices.len()));
        let t = GaitTable::parse(&bytes).unwrap();
        let h = t.header();
        prop_assert_eq!(h.name_str(), Some(g.name.as_str()));
        prop_assert!((f64::from(h.step_period_us) - g.period_s * 1e6).abs() <= 0.5);
        prop_assert!((f64::from(h.duty) - g.duty * 1e4).abs() <= 0.5);
        prop_assert_eq!(t.joint_count(), g.joints.len());
        prop_assert_eq!(t.slice_count(), g.slices.len());
        for (j, spec) in g.joints.iter().enumerate() {
            let m = t.joint(j).unwrap();
            prop_assert_eq!(m.servo_id, spec.servo_id);
            prop_assert_eq!(m.model, spec.model);
            prop_assert_eq!(m.sign, spec.sign);
            prop_assert_eq!(m.zero_offset, spec.zero_offset);
            prop_assert!((f64::from(m.min) - spec.min_rad * ANGLE_PER_RAD).abs() <= 0.5);
            prop_assert!((f64::from(m.max) - spec.max_rad * ANGLE_PER_RAD).abs() <= 0.5);
            prop_assert!((f64::from(m.stiffness) - spec.stiffness_nm_per_rad * STIFFNESS_PER_NM_RAD).abs() <= 0.5);
        }
        prop_assert!(t.joint(g.joints.len()).is_none());
        for (s, (stance, angles, torques)) in g.slices.iter().enumerate() {
            prop_assert_eq!(t.stance(s), Some(*stance));
            for j in 0..g.joints.len() {
                // Half a unit of rounding: 5e-5 rad and 0.5 mN m.
                prop_assert!((angle_to_rad(t.angle(s, j).unwrap()) - angles[j]).abs() <= 0.5 / ANGLE_PER_RAD + 1e-12);
                prop_assert!((torque_to_nm(t.torque(s, j).unwrap()) - torques[j]).abs() <= 0.5 / TORQUE_PER_NM + 1e-12);
            }
            prop_assert!(t.angle(s, g.joints.len()).is_none());
        }
        prop_assert!(t.slice(g.slices.len()).is_none());
        // A whole flash slot behind the table (erased flash reads 0xFF) does not change the view.
        let mut slot = bytes.clone();
        slot.resize(bytes.len() + 300, 0xFF);
        prop_assert_eq!(GaitTable::parse(&slot).unwrap().as_bytes(), &bytes[..]);
    }
}

#[test]
fn a_full_size_table_fits_100_kb() {
    // Issue 4: 22 joints x 1000 slices in under 100 KB (102 400 bytes); the layout gives 90 392.
    assert_eq!(
        gait::table_len(22, 1000),
        36 + 22 * 16 + 1000 * (2 + 22 * 4) + 4
    );
    assert!(gait::table_len(22, 1000) <= 100 * 1024);
}

/// The largest value of every variable-size message, each integer at its longest varint.
#[test]
fn the_largest_messages_fit_max_message_len() {
    let big_header = GaitHeader {
        joint_count: u8::MAX,
        slice_count: u16::MAX,
        step_period_us: u32::MAX,
        duty: u16::MAX,
        name: [0xFF; gait::NAME_LEN],
    };
    let full_fb = JointFeedback {
        commanded: i16::MIN,
        present: i16::MIN,
        velocity: i16::MIN,
        load: i16::MIN,
        error: u8::MAX,
        flags: u8::MAX,
    };
    let bus = BusStats {
        cycle_us: u32::MAX,
        timeouts: u32::MAX,
        crc_errors: u32::MAX,
        missed_deadlines: u32::MAX,
    };
    let slots = core::iter::repeat_n(
        SlotInfo {
            slot: u8::MAX,
            gait: Some(GaitSummary {
                header: big_header,
                crc: u32::MAX,
            }),
            lost: Some(LostCopy {
                seq: Some(u32::MAX),
                crc: Some(u32::MAX),
                reason: LossReason::TableChecksum,
                name: Some([0xFF; gait::NAME_LEN]),
            }),
        },
        MAX_SLOTS,
    )
    .collect::<heapless::Vec<_, MAX_SLOTS>>();
    let host = [
        HostMessage::Request {
            seq: u16::MAX,
            request: Request::UploadChunk {
                offset: u32::MAX,
                data: core::iter::repeat_n(0xFF, MAX_CHUNK_LEN).collect(),
            },
        },
        HostMessage::Setpoint(Setpoint {
            seq: u32::MAX,
            joints: core::iter::repeat_n(
                JointSetpoint {
                    angle: i16::MIN,
                    torque: Some(i16::MIN),
                },
                MAX_JOINTS,
            )
            .collect(),
        }),
    ];
    let device = [
        DeviceMessage::Telemetry(Telemetry {
            time_us: u64::MAX,
            cycle: u32::MAX,
            step: u32::MAX,
            slice: u16::MAX,
            joints: core::iter::repeat_n(full_fb, MAX_JOINTS).collect(),
            bus,
            platform: Some(PlatformFeedback {
                servo_id: u8::MAX,
                goal: u16::MAX,
                present: u16::MAX,
                flags: u8::MAX,
            }),
            state: RunState::Streaming,
            health: core::iter::repeat_n(
                ServoHealth {
                    temperature_c: u8::MAX,
                    voltage_dv: u16::MAX,
                },
                MAX_JOINTS,
            )
            .collect(),
        }),
        DeviceMessage::Proprioception(Proprioception {
            time_us: u64::MAX,
            cycle: u32::MAX,
            setpoint_seq: u32::MAX,
            setpoint_age: u16::MAX,
            joints: core::iter::repeat_n(full_fb, MAX_JOINTS).collect(),
            bus,
        }),
        DeviceMessage::Reply {
            seq: u16::MAX,
            response: Response::DeviceInfo(DeviceInfo {
                firmware: FirmwareVersion {
                    major: u16::MAX,
                    minor: u16::MAX,
                    patch: u16::MAX,
                },
                protocol_version: u16::MAX,
                table_format_version: u16::MAX,
                build_id: u32::MAX,
                capabilities: Capabilities(u32::MAX),
                slot_capacity: u32::MAX,
                max_chunk_len: u16::MAX,
                slots: slots.clone(),
            }),
        },
        DeviceMessage::Reply {
            seq: u16::MAX,
            response: Response::Slots(slots),
        },
        DeviceMessage::Reply {
            seq: u16::MAX,
            response: Response::Platform(Some(PlatformStatus {
                setup: PlatformSetup {
                    servo_id: u8::MAX,
                    rest: u16::MAX,
                    rise: u16::MAX,
                    fall: u16::MAX,
                    profile_velocity: u16::MAX,
                    moves: PlatformMove::Fall,
                    step: u32::MAX,
                    hold_cycles: u16::MAX,
                },
                state: PlatformState::Ready { present: u16::MAX },
            })),
        },
        DeviceMessage::Reply {
            seq: u16::MAX,
            response: Response::JointMap(Some(JointIds {
                slot: u8::MAX,
                servo_ids: core::iter::repeat_n(u8::MAX, MAX_JOINTS).collect(),
            })),
        },
        DeviceMessage::Reply {
            seq: u16::MAX,
            response: Response::Settings(Settings {
                baud: u32::MAX,
                cycle_hz: u16::MAX,
                telemetry_every: u16::MAX,
                joints: core::iter::repeat_n(
                    JointSettings {
                        stiffness: u32::MAX,
                        min: i16::MIN,
                        max: i16::MIN,
                        torque_enabled: true,
                    },
                    MAX_JOINTS,
                )
                .collect(),
                health: HealthLimits {
                    warn_temperature_c: u8::MAX,
                    stop_temperature_c: u8::MAX,
                    warn_low_dv: u16::MAX,
                    stop_low_dv: u16::MAX,
                    warn_high_dv: u16::MAX,
                    stop_high_dv: u16::MAX,
                },
            }),
        },
    ];
    for m in &host {
        let len = postcard::to_allocvec(m).unwrap().len();
        assert!(len <= MAX_MESSAGE_LEN, "{len} > {MAX_MESSAGE_LEN}");
        assert_eq!(through_link(m, &[]), vec![Ok(m.clone())]);
    }
    for m in &device {
        let len = postcard::to_allocvec(m).unwrap().len();
        assert!(len <= MAX_MESSAGE_LEN, "{len} > {MAX_MESSAGE_LEN}");
        assert_eq!(through_link(m, &[]), vec![Ok(m.clone())]);
    }
}
