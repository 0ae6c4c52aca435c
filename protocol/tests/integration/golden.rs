//! Golden bytes, derived by hand from the postcard 1.x wire specification, COBS and the CRC-32
//! catalogue, not from this crate's encoder. If one of these fails, the wire format changed: make
//! that deliberate and bump `PROTOCOL_VERSION` (and `gait::FORMAT_VERSION` for the table).
//!
//! postcard rules used below (postcard wire spec, "Serde Data Model" section):
//! * enum variant: its index as a varint (u32); unit variants are just that;
//! * u16/u32/u64: LEB128 varint, 7 bits per byte, low group first, 0x80 = more follows;
//! * i16: zigzag ((n << 1) ^ (n >> 15)) then varint;
//! * Option: 0x00 for None, 0x01 then the value for Some;
//! * seq (heapless::Vec): varint length then the elements; u8: one raw byte; struct: fields in order.
//!
//! Frame = COBS(message ++ CRC-32/ISO-HDLC(message) little-endian) ++ 0x00. The CRCs were computed
//! with Python's `zlib.crc32` (the same algorithm; its check value for "123456789" is 0xCBF43926,
//! asserted here too against the crate). COBS: each block is a code byte (1 + number of non-zero
//! bytes up to the next zero or the end) followed by those bytes; the zero itself is dropped.

use crate::common;
use common::golden_table::GOLDEN_TABLE;
use protocol::gait::GaitTable;
use protocol::*;

/// The bytes of a dump written as the e-manual writes them: hex pairs separated by spaces.
fn hex(dump: &str) -> Vec<u8> {
    dump.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap_or_else(|_| panic!("{b:?} in {dump:?}")))
        .collect()
}

fn frame_of<T: serde::Serialize>(msg: &T) -> Vec<u8> {
    protocol::frame::encode_frame_vec(msg).unwrap()
}

fn assert_golden<T>(msg: T, postcard_bytes: &str, frame: &str)
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let (postcard_bytes, frame) = (hex(postcard_bytes), hex(frame));
    assert_eq!(
        postcard::to_allocvec(&msg).unwrap(),
        postcard_bytes,
        "postcard bytes of {msg:?}"
    );
    assert_eq!(frame_of(&msg), frame, "frame of {msg:?}");
    let mut acc = FrameAccumulator::new();
    let decoded: Vec<_> = acc.messages::<T>(&frame).collect();
    assert_eq!(decoded, vec![Ok(msg)]);
}

#[test]
fn protocol_version_is_the_one_these_bytes_belong_to() {
    // 2: FaultKind::ServoStuck appended (no existing byte changed; see the crate's Versioning).
    // 3: RunState::Boot appended (a board still looking for its servos no longer reads as Idle).
    // 4: SlotInfo::lost (a damaged copy the slot fell back from), Request::GetJointMap and
    //    Response::JointMap appended.
    // 5: Request::QueueGait / ClearQueue and ProtocolError::Switch appended (gait switching).
    // 6: Request::SetSteerFamily / Steer and ProtocolError::Steer appended (the descending
    //    command).
    // 7: Request::SetPlatform / ClearPlatform / GetPlatform, Response::Platform,
    //    ProtocolError::Platform appended, Telemetry::platform added at the end (the perturbation
    //    platform's servo).
    // 8: Telemetry::state added at the end (the run state of every recorded cycle, so a
    //    recording shows a fault); Request::SetHealthLimits, Setting::HealthLimits appended;
    //    Telemetry::health, Status::health_warning / health_stop, Settings::health added at the
    //    end (heat and supply of the servos).
    // 9: Counters::rate_limited added at the end of the counters (inside Status: the bytes of
    //    every later Status field move); Request::ReadServo / GetServoRead, Response::ServoRead
    //    and Setting::ServoRead appended (servo reads through the board).
    assert_eq!(PROTOCOL_VERSION, 9);
    assert_eq!(gait::FORMAT_VERSION, 1);
}

#[test]
fn frame_crc_is_crc32_iso_hdlc() {
    assert_eq!(protocol::crc32::checksum(b"123456789"), 0xCBF4_3926);
}

#[test]
fn get_status_with_seq_300() {
    // HostMessage::Request = variant 0 -> 00
    // seq 300 = 0b10_0101100 -> low 7 bits 0x2C | 0x80 = AC, then 300 >> 7 = 2 -> 02
    // Request::GetStatus = variant 1 -> 01
    // CRC-32 of 00 AC 02 01 = 0xB417290C -> LE 0C 29 17 B4
    // COBS of 00 AC 02 01 0C 29 17 B4: block "" before the zero -> 01; block of 7 bytes -> 08 ...
    assert_golden(
        HostMessage::Request {
            seq: 300,
            request: Request::GetStatus,
        },
        "00 AC 02 01",
        "01 08 AC 02 01 0C 29 17 B4 00",
    );
}

#[test]
fn steer_right_150_mrad_at_half_speed() {
    // 00 (Request) 07 (seq 7) 1A (Steer = variant 26 of Request)
    // heading -150: zigzag (-150 << 1) ^ (-150 >> 15) = -300 ^ -1 = 299 = 0x12B -> AB 02
    // speed 500 = 0x1F4 -> F4 03
    // CRC-32 of the 7 bytes (zlib.crc32) = 0xDA0E5F8C -> 8C 5F 0E DA
    // COBS: the leading zero -> 01; then 11 non-zero bytes -> 0B ...
    assert_golden(
        HostMessage::Request {
            seq: 7,
            request: Request::Steer(SteerCommand {
                heading_mrad: -150,
                speed_permille: 500,
            }),
        },
        "00 07 1A AB 02 F4 03",
        "01 0B 07 1A AB 02 F4 03 8C 5F 0E DA 00",
    );
}

#[test]
fn set_platform_the_labs_rise_at_step_3() {
    // 00 (Request) 09 (seq 9) 1B (SetPlatform = variant 27 of Request)
    // servo_id 22 -> 16 (raw u8)
    // rest 2020 = 15 * 128 + 100 -> E4 0F; rise 2330 = 18 * 128 + 26 -> 9A 12;
    // fall 1570 = 12 * 128 + 34 -> A2 0C; profile velocity 240 = 128 + 112 -> F0 01
    // moves Rise = variant 0 -> 00; step 3 -> 03; hold_cycles 2 -> 02
    // CRC-32 (zlib.crc32) = 0x5CF1DF77 -> 77 DF F1 5C
    // COBS: 01 (leading zero), 0C + 11 bytes up to Rise's zero, 07 + the last 6 bytes
    assert_golden(
        HostMessage::Request {
            seq: 9,
            request: Request::SetPlatform(PlatformSetup::lab(PlatformMove::Rise, 3)),
        },
        "00 09 1B 16 E4 0F 9A 12 A2 0C F0 01 00 03 02",
        "01 0C 09 1B 16 E4 0F 9A 12 A2 0C F0 01 07 03 02 77 DF F1 5C 00",
    );
}

#[test]
fn platform_requests_and_the_error_are_appended() {
    // ClearPlatform = variant 28, GetPlatform = 29 of Request; Response::Platform = variant 9;
    // ProtocolError::Platform = variant 13, PlatformError::NotAnswering = variant 5.
    let req = |request| postcard::to_allocvec(&request).unwrap();
    assert_eq!(req(Request::ClearPlatform), [0x1C]);
    assert_eq!(req(Request::GetPlatform), [0x1D]);
    assert_eq!(
        postcard::to_allocvec(&Response::Platform(None)).unwrap(),
        [0x09, 0x00]
    );
    assert_eq!(
        postcard::to_allocvec(&ProtocolError::Platform(PlatformError::NotAnswering {
            servo_id: 22
        }))
        .unwrap(),
        [0x0D, 0x05, 0x16]
    );
}

#[test]
fn set_steer_family_0_1_2_over_300_mrad() {
    // 00 (Request) 08 (seq 8) 19 (SetSteerFamily = variant 25) 00 01 02 (slots, raw u8)
    // range 300 = 0x12C -> AC 02; CRC-32 = 0x2590E39F -> 9F E3 90 25
    // COBS: 01 (leading zero) 03 08 19 (two bytes to the slot-0 zero) 09 01 02 AC 02 9F E3 90 25
    assert_golden(
        HostMessage::Request {
            seq: 8,
            request: Request::SetSteerFamily(SteerFamily {
                straight: 0,
                left: 1,
                right: 2,
                range_mrad: 300,
            }),
        },
        "00 08 19 00 01 02 AC 02",
        "01 03 08 19 09 01 02 AC 02 9F E3 90 25 00",
    );
}

#[test]
fn play_backward_ten_steps_at_1_5_period() {
    // 00 (Request) 05 (seq 5) 08 (Play = 9th variant of Request)
    // PlayCommand { slot 2 -> 02, Backward = variant 1 -> 01, period_scale 1500 = 0x5DC:
    //   0x5C | 0x80 = DC, 1500 >> 7 = 11 -> 0B, Steps::Count = variant 1 -> 01, 10 -> 0A }
    // CRC-32 = 0x74B7ED89 -> 89 ED B7 74; COBS: leading zero -> 01, then 12 non-zero bytes -> 0D.
    assert_golden(
        HostMessage::Request {
            seq: 5,
            request: Request::Play(PlayCommand {
                slot: 2,
                direction: Direction::Backward,
                period_scale: 1500,
                steps: Steps::Count(10),
            }),
        },
        "00 05 08 02 01 DC 0B 01 0A",
        "01 0D 05 08 02 01 DC 0B 01 0A 89 ED B7 74 00",
    );
}

#[test]
fn out_of_order_chunk_error_reply() {
    // DeviceMessage::Reply = 0 -> 00, seq 7 -> 07, Response::Error = variant 7 -> 07,
    // ProtocolError::Upload = variant 7 -> 07, UploadError::OutOfOrder = variant 9 -> 09,
    // offset 1024 = 0x400 -> 80 08, expected 512 = 0x200 -> 80 04.
    // CRC-32 = 0xE6DACA21 -> 21 CA DA E6; COBS: 01 then 12 non-zero bytes -> 0D.
    assert_golden(
        DeviceMessage::Reply {
            seq: 7,
            response: Response::Error(ProtocolError::Upload(UploadError::OutOfOrder {
                offset: 1024,
                expected: 512,
            })),
        },
        "00 07 07 07 09 80 08 80 04",
        "01 0D 07 07 07 09 80 08 80 04 21 CA DA E6 00",
    );
}

#[test]
fn slots_reply_with_a_lost_copy() {
    // DeviceMessage::Reply = 0 -> 00, seq 5 -> 05, Response::Slots = variant 4 -> 04, 1 slot -> 01;
    // slot 0 -> 00, gait None -> 00, lost Some -> 01: seq Some(7) -> 01 07,
    // crc Some(0x11223344) -> 01 then its varint: 7-bit groups low first 0x44, 0x66, 0x08, 0x09,
    // 0x01 -> C4 E6 88 89 01; reason LossReason::TableChecksum = variant 0 -> 00; name None -> 00.
    // CRC-32 = 0xCA085AC5 -> C5 5A 08 CA; COBS blocks: 01 | 04 05 04 01 | 01 | 0A (9 bytes up to
    // the next zero) | 01 | 05 + C5 5A 08 CA, then the delimiter.
    assert_golden(
        DeviceMessage::Reply {
            seq: 5,
            response: Response::Slots(
                heapless::Vec::from_slice(&[SlotInfo {
                    slot: 0,
                    gait: None,
                    lost: Some(LostCopy {
                        seq: Some(7),
                        crc: Some(0x1122_3344),
                        reason: LossReason::TableChecksum,
                        name: None,
                    }),
                }])
                .unwrap(),
            ),
        },
        "00 05 04 01 00 00 01 01 07 01 C4 E6 88 89 01 00 00",
        "01 04 05 04 01 01 0A 01 01 07 01 C4 E6 88 89 01 01 05 C5 5A 08 CA 00",
    );
}

#[test]
fn get_joint_map_request_and_reply() {
    // HostMessage::Request = 00, seq 1 -> 01, Request::GetJointMap = variant 22 -> 16, slot None
    // -> 00. CRC-32 = 0x3C1E00FC -> FC 00 1E 3C (a zero inside the CRC); COBS blocks: 01 | 03 01 16
    // | 02 FC | 03 1E 3C, then the delimiter.
    assert_golden(
        HostMessage::Request {
            seq: 1,
            request: Request::GetJointMap { slot: None },
        },
        "00 01 16 00",
        "01 03 01 16 02 FC 03 1E 3C 00",
    );
    // DeviceMessage::Reply = 00, seq 2 -> 02, Response::JointMap = variant 8 -> 08, Some -> 01,
    // slot 1 -> 01, 2 servo IDs -> 02, 11 -> 0B, 12 -> 0C. CRC-32 = 0x72F44376 -> 76 43 F4 72;
    // COBS: 01, then 0C and the 11 non-zero bytes, then the delimiter.
    assert_golden(
        DeviceMessage::Reply {
            seq: 2,
            response: Response::JointMap(Some(JointIds {
                slot: 1,
                servo_ids: heapless::Vec::from_slice(&[11, 12]).unwrap(),
            })),
        },
        "00 02 08 01 01 02 0B 0C",
        "01 0C 02 08 01 01 02 0B 0C 76 43 F4 72 00",
    );
}

#[test]
fn streaming_setpoint_with_negative_angle_and_feed_forward() {
    // HostMessage::Setpoint = variant 1 -> 01; seq 1 -> 01; 2 joints -> 02;
    // joint 0: angle -1 -> zigzag 1 -> 01, torque None -> 00;
    // joint 1: angle 15708 -> zigzag 31416 = 0x7AB8 -> B8 F5 01, torque Some -> 01,
    //          -300 -> zigzag 599 = 0x257 -> D7 04.
    // CRC-32 = 0xA1B0F9AC -> AC F9 B0 A1.
    // COBS: "01 01 02 01" before the zero -> 05 01 01 02 01; then 10 bytes to the end -> 0B ...
    assert_golden(
        HostMessage::Setpoint(Setpoint {
            seq: 1,
            joints: [
                JointSetpoint {
                    angle: -1,
                    torque: None,
                },
                JointSetpoint {
                    angle: 15708,
                    torque: Some(-300),
                },
            ]
            .into_iter()
            .collect(),
        }),
        "01 01 02 01 00 B8 F5 01 01 D7 04",
        "05 01 01 02 01 0B B8 F5 01 01 D7 04 AC F9 B0 A1 00",
    );
}

#[test]
fn builder_writes_the_hand_laid_table() {
    let mut b = GaitTableBuilder::new(
        "tripod",
        1.0,
        0.5,
        vec![JointSpec {
            name: "LF_CTr".into(),
            servo_id: 1,
            model: ServoModel::Mx64,
            sign: Sign::Negative,
            zero_offset: 2048,
            min_rad: -1.5,
            max_rad: 1.5,
            stiffness_nm_per_rad: 8.4,
            leg: None,
        }],
    );
    b.slice(0b0000_1001, &[0.25], &[-1.2]);
    assert_eq!(b.build().unwrap(), GOLDEN_TABLE);
}

#[test]
fn view_reads_the_hand_laid_table() {
    let t = GaitTable::parse(&GOLDEN_TABLE).unwrap();
    let h = t.header();
    assert_eq!(
        (h.joint_count, h.slice_count, h.duty, h.step_period_us),
        (1, 1, 5000, 1_000_000)
    );
    assert_eq!(h.name_str(), Some("tripod"));
    assert_eq!(h.table_len(), 62);
    assert_eq!(
        t.joint(0),
        Some(JointMap {
            servo_id: 1,
            model: ServoModel::Mx64,
            sign: Sign::Negative,
            zero_offset: 2048,
            min: -15000,
            max: 15000,
            stiffness: 8400,
            leg: None,
        })
    );
    assert_eq!(t.stance(0), Some(0b1001));
    assert_eq!(t.angle(0, 0), Some(2500));
    assert_eq!(t.torque(0, 0), Some(-1200));
    assert_eq!(t.crc(), 0x8567_F1A7);
}

#[test]
fn peek_reads_the_header_of_a_damaged_table_but_not_of_other_bytes() {
    // The last slice byte flipped: the table's CRC fails, its header (bytes 0..36) is intact.
    let mut bytes = GOLDEN_TABLE.to_vec();
    bytes[40] ^= 0x01;
    assert!(GaitTable::parse(&bytes).is_err());
    let h = GaitHeader::peek(&bytes).unwrap();
    assert_eq!(h.name_str(), Some("tripod"));
    assert_eq!((h.joint_count, h.slice_count, h.duty), (1, 1, 5000));
    // A broken magic, another format version, zero joints, or too few bytes: not a header.
    for (at, value) in [(0, b'X'), (4, 9), (6, 0)] {
        let mut b = GOLDEN_TABLE.to_vec();
        b[at] = value;
        assert_eq!(GaitHeader::peek(&b), None, "byte {at} = {value}");
    }
    assert_eq!(GaitHeader::peek(&GOLDEN_TABLE[..35]), None);
    assert_eq!(GaitHeader::peek(&[0xFF; 64]), None);
}
