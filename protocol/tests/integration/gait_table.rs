//! Gait table validation and the builder's errors: each bad input is refused with an error that names
//! the problem and the place. Tables are tampered from the hand-laid golden table.

use protocol::gait::{GaitTable, JointField, TableError};
use protocol::*;

use crate::common;
use common::golden_table::GOLDEN_TABLE;

/// Applies `edit` to the golden table and rewrites its CRC so only the edit is wrong.
fn tampered(edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut t = GOLDEN_TABLE.to_vec();
    edit(&mut t);
    let n = t.len();
    let crc = protocol::crc32::checksum(&t[..n - 4]);
    t[n - 4..].copy_from_slice(&crc.to_le_bytes());
    t
}

#[test]
fn every_kind_of_bad_table_has_its_error() {
    let cases: Vec<(Vec<u8>, TableError)> = vec![
        (
            GOLDEN_TABLE[..39].to_vec(),
            TableError::Truncated {
                len: 39,
                needed: 40,
            },
        ),
        (
            GOLDEN_TABLE[..61].to_vec(),
            TableError::Truncated {
                len: 61,
                needed: 62,
            },
        ),
        (
            tampered(|t| t[0] = b'X'),
            TableError::BadMagic { found: *b"XBGT" },
        ),
        (
            tampered(|t| t[4] = 2),
            TableError::UnsupportedVersion {
                found: 2,
                supported: 1,
            },
        ),
        (
            tampered(|t| t[6] = 0),
            TableError::BadJointCount { count: 0 },
        ),
        (
            tampered(|t| t[6] = 33),
            TableError::BadJointCount { count: 33 },
        ),
        (tampered(|t| t[7] = 1), TableError::Reserved { offset: 7 }),
        (
            tampered(|t| t[8] = 0),
            TableError::BadSliceCount { count: 0 },
        ),
        (
            tampered(|t| t[10..12].copy_from_slice(&10_000u16.to_le_bytes())),
            TableError::BadDuty { duty: 10_000 },
        ),
        (tampered(|t| t[12..16].fill(0)), TableError::BadPeriod),
        // Two slices declared, the length field still says one.
        (
            tampered(|t| t[8] = 2),
            TableError::LengthMismatch {
                declared: 62,
                computed: 68,
            },
        ),
        (tampered(|t| t[36] = 253), joint_0(JointField::ServoId)),
        (tampered(|t| t[37] = 2), joint_0(JointField::Model)),
        (tampered(|t| t[38] = 0), joint_0(JointField::Sign)),
        (tampered(|t| t[39] = 7), joint_0(JointField::Leg)),
        (tampered(|t| t[46] = 1), joint_0(JointField::Reserved)),
        (
            tampered(|t| t[40..42].copy_from_slice(&4096u16.to_le_bytes())),
            joint_0(JointField::ZeroOffset),
        ),
        // min 1.5 rad > max 1.5 rad - 1 unit
        (
            tampered(|t| t[42..44].copy_from_slice(&15001i16.to_le_bytes())),
            joint_0(JointField::Limits),
        ),
        (
            tampered(|t| t[48..52].fill(0)),
            joint_0(JointField::Stiffness),
        ),
        // 16 and 565 700 mN m/rad: beyond what the golden joint's MX-64 P gain 1 ..= 16383
        // holds (17 ..= 565 699, hand computed in protocol::limits); a table used to pass with
        // any non-zero stiffness.
        (
            tampered(|t| t[48..52].copy_from_slice(&16u32.to_le_bytes())),
            joint_0(JointField::Stiffness),
        ),
        (
            tampered(|t| t[48..52].copy_from_slice(&565_700u32.to_le_bytes())),
            joint_0(JointField::Stiffness),
        ),
        (
            tampered(|t| t[52] = 0x40),
            TableError::BadStance {
                slice: 0,
                bits: 0x40,
            },
        ),
        (
            tampered(|t| t[53] = 1),
            TableError::BadStance { slice: 0, bits: 1 },
        ),
        (
            tampered(|t| t[54..56].copy_from_slice(&15001i16.to_le_bytes())),
            TableError::AngleOutOfLimits {
                slice: 0,
                joint: 0,
                angle: 15001,
            },
        ),
    ];
    for (bytes, expected) in cases {
        assert_eq!(GaitTable::parse(&bytes), Err(expected));
    }
    let mut t = GOLDEN_TABLE.to_vec();
    t[56] ^= 1; // a torque bit, CRC not fixed
    assert!(matches!(
        GaitTable::parse(&t),
        Err(TableError::Crc {
            stored: 0x8567_F1A7,
            ..
        })
    ));
}

/// The first joint's entry is refused for its `field`.
fn joint_0(field: JointField) -> TableError {
    TableError::BadJoint { joint: 0, field }
}

fn joint(name: &str, id: u8) -> JointSpec {
    JointSpec {
        name: name.into(),
        servo_id: id,
        model: ServoModel::Mx28,
        sign: Sign::Positive,
        zero_offset: 2048,
        min_rad: -1.0,
        max_rad: 1.0,
        stiffness_nm_per_rad: 8.4,
        leg: None,
    }
}

fn two_joint_builder() -> GaitTableBuilder {
    GaitTableBuilder::new(
        "wave",
        0.5,
        0.75,
        vec![joint("LF_ThC1", 1), joint("LF_CTr", 2)],
    )
}

#[test]
fn builder_names_slice_joint_and_field_of_a_bad_sample() {
    let mut b = two_joint_builder();
    b.slice(0, &[0.0, 0.0], &[0.0, 0.0]);
    b.slice(0, &[0.0, 1.2], &[0.0, 0.0]);
    let e = b.build().unwrap_err();
    assert_eq!(
        e,
        BuildError::Sample {
            slice: 1,
            joint: "LF_CTr".into(),
            field: gait::Field::Angle,
            value: 1.2,
            min: -1.0,
            max: 1.0
        }
    );
    let text = e.to_string();
    assert!(
        text.contains("slice 1") && text.contains("LF_CTr") && text.contains("angle"),
        "{text}"
    );

    // 40 N m does not fit an i16 of mN m (max 32.767 N m): an error, not a wrap to -25.5 N m.
    let mut b = two_joint_builder();
    b.slice(0, &[0.0, 0.0], &[40.0, 0.0]);
    assert!(matches!(
        b.build(),
        Err(BuildError::Sample { slice: 0, ref joint, field: gait::Field::Torque, .. }) if joint == "LF_ThC1"
    ));
    let mut b = two_joint_builder();
    b.slice(0, &[f64::NAN, 0.0], &[0.0, 0.0]);
    assert!(matches!(
        b.build(),
        Err(BuildError::Sample {
            field: gait::Field::Angle,
            ..
        })
    ));
    let mut b = two_joint_builder();
    b.slice(0, &[0.0], &[0.0, 0.0]);
    assert_eq!(
        b.build(),
        Err(BuildError::SampleCount {
            slice: 0,
            what: "angle",
            got: 1,
            joints: 2
        })
    );
    let mut b = two_joint_builder();
    b.slice(0b100_0000, &[0.0, 0.0], &[0.0, 0.0]);
    assert_eq!(
        b.build(),
        Err(BuildError::Stance {
            slice: 0,
            bits: 0x40
        })
    );
}

#[test]
fn builder_refuses_bad_joints_and_headers() {
    let build = |joints: Vec<JointSpec>, period: f64, duty: f64, name: &str| {
        let n = joints.len();
        let mut b = GaitTableBuilder::new(name, period, duty, joints);
        b.slice(0, &vec![0.0; n], &vec![0.0; n]);
        b.build()
    };
    let ok = || vec![joint("A", 1)];
    assert!(build(ok(), 1.0, 0.5, "x").is_ok());
    assert!(matches!(
        build(ok(), 0.0, 0.5, "x"),
        Err(BuildError::Header {
            field: gait::Field::StepPeriod,
            ..
        })
    ));
    assert!(matches!(
        build(ok(), 1.0, 1.0, "x"),
        Err(BuildError::Header {
            field: gait::Field::Duty,
            ..
        })
    ));
    assert!(matches!(
        build(ok(), 1.0, 0.0, "x"),
        Err(BuildError::Header {
            field: gait::Field::Duty,
            ..
        })
    ));
    assert_eq!(
        build(ok(), 1.0, 0.5, "a-name-of-17-byte"),
        Err(BuildError::NameTooLong { len: 17, max: 16 })
    );
    assert_eq!(
        build(vec![], 1.0, 0.5, "x"),
        Err(BuildError::JointCount { count: 0, max: 32 })
    );
    let many: Vec<_> = (0..33).map(|i| joint("J", i)).collect();
    assert_eq!(
        build(many, 1.0, 0.5, "x"),
        Err(BuildError::JointCount { count: 33, max: 32 })
    );
    assert_eq!(
        build(vec![joint("A", 1), joint("B", 1)], 1.0, 0.5, "x"),
        Err(BuildError::DuplicateServo {
            joint: "B".into(),
            other: "A".into(),
            servo_id: 1
        })
    );
    let with = |f: fn(&mut JointSpec)| {
        let mut j = joint("RH_FTi", 7);
        f(&mut j);
        build(vec![j], 1.0, 0.5, "x")
    };
    let field_of = |r: Result<Vec<u8>, BuildError>| match r {
        Err(BuildError::Joint { joint, field, .. }) => {
            assert_eq!(joint, "RH_FTi");
            field
        }
        other => panic!("expected a joint error, got {other:?}"),
    };
    assert_eq!(field_of(with(|j| j.servo_id = 253)), gait::Field::ServoId);
    assert_eq!(
        field_of(with(|j| j.zero_offset = 4096)),
        gait::Field::ZeroOffset
    );
    assert_eq!(field_of(with(|j| j.min_rad = -3.3)), gait::Field::MinAngle);
    assert_eq!(field_of(with(|j| j.max_rad = -1.5)), gait::Field::MaxAngle);
    assert_eq!(
        field_of(with(|j| j.stiffness_nm_per_rad = 0.0)),
        gait::Field::Stiffness
    );
    assert_eq!(
        field_of(with(|j| j.stiffness_nm_per_rad = f64::INFINITY)),
        gait::Field::Stiffness
    );
    // What the MX-28's P gain cannot hold (0.0072 ..= 235.7 N m/rad): the builder refuses as
    // the parse and the board do.
    for f in [
        (|j: &mut JointSpec| j.stiffness_nm_per_rad = 0.001) as fn(&mut JointSpec),
        |j| j.stiffness_nm_per_rad = 0.006,
        |j| j.stiffness_nm_per_rad = 236.0,
    ] {
        assert_eq!(field_of(with(f)), gait::Field::Stiffness);
    }
}

#[test]
fn slices_are_refused_beyond_max_slices() {
    let mut b = GaitTableBuilder::new("long", 1.0, 0.5, vec![joint("A", 1)]);
    for _ in 0..=gait::MAX_SLICES {
        b.slice(0, &[0.0], &[0.0]);
    }
    assert_eq!(
        b.build(),
        Err(BuildError::SliceCount {
            count: 10_001,
            max: 10_000
        })
    );
}

#[test]
fn joint_map_converts_angles_to_ticks_by_hand() {
    let map = |sign, zero| JointMap {
        servo_id: 1,
        model: ServoModel::Mx28,
        sign,
        zero_offset: zero,
        min: -30000,
        max: 30000,
        stiffness: 1,
        leg: None,
    };
    // pi/2 = 15708 units is a quarter turn, 1024 ticks, subtracted for a negative sign.
    assert_eq!(map(Sign::Positive, 2048).angle_to_ticks(15708), 3072);
    assert_eq!(map(Sign::Negative, 2048).angle_to_ticks(15708), 1024);
    assert_eq!(map(Sign::Negative, 2048).ticks_to_angle(1024), 15708);
    // 4000 ticks with zero at 100 is 196 ticks below the zero after wrapping a turn:
    // -196 * 2 pi / 4096 = -0.300 66 rad = -3007 units.
    assert_eq!(map(Sign::Positive, 100).ticks_to_angle(4000), -3007);
    assert_eq!(map(Sign::Negative, 100).ticks_to_angle(4000), 3007);
}

#[test]
fn a_joints_leg_is_written_as_its_index_plus_one_and_read_back() {
    let mut specs = vec![joint("RF_ThC1", 1), joint("LF_CTr", 2)];
    specs[0].leg = Some(3);
    let mut b = GaitTableBuilder::new("legs", 0.5, 0.75, specs.clone());
    b.slice(0, &[0.0, 0.0], &[0.0, 0.0]);
    let bytes = b.build().unwrap();
    // The format: +3 of each 16-byte joint record after the 36-byte header, 0 = not given.
    assert_eq!((bytes[36 + 3], bytes[36 + 16 + 3]), (4, 0));
    let t = GaitTable::parse(&bytes).unwrap();
    assert_eq!(t.joint(0).unwrap().leg, Some(3));
    assert_eq!(t.joint(1).unwrap().leg, None);
    // A seventh leg is refused, naming the joint and the field.
    specs[0].leg = Some(6);
    let mut b = GaitTableBuilder::new("legs", 0.5, 0.75, specs);
    b.slice(0, &[0.0, 0.0], &[0.0, 0.0]);
    let e = b.build().unwrap_err();
    assert_eq!(
        e.to_string(),
        "joint RF_ThC1: leg (0 ..= 5 in LF, LM, LH, RF, RM, RH) = 6 outside 0 ..= 5"
    );
}
