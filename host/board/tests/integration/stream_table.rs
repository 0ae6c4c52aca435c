//! The two host pieces the Python bindings add: SI setpoints to wire units (`link::stream`) and a
//! plan as a step table (`plan::table`), checked against hand-computed fixed-point values.

use board::link::{SetpointError, setpoint_from_si};
use planner::model::Leg;
use planner::model::builtin;
use planner::plan::table::{servo_joints, stance_bits, step_table};
use protocol::GaitTable;
use protocol::gait::Sign;

#[test]
fn setpoint_angles_and_torques_in_wire_units() {
    // 1e-4 rad and mN m per unit: 0.1234 rad -> 1234, -1.5 rad -> -15000, 0.25 N m -> 250.
    let sp = setpoint_from_si(7, &[0.1234, -1.5], Some(&[0.25, -0.001])).unwrap();
    assert_eq!(sp.seq, 7);
    assert_eq!(sp.joints[0].angle, 1234);
    assert_eq!(sp.joints[1].angle, -15000);
    assert_eq!(sp.joints[0].torque, Some(250));
    assert_eq!(sp.joints[1].torque, Some(-1));
    let none = setpoint_from_si(1, &[0.0], None).unwrap();
    assert_eq!(none.joints[0].torque, None);
}

#[test]
fn setpoint_out_of_range_names_the_joint() {
    // i16 of 1e-4 rad reaches 3.2767 rad.
    let e = setpoint_from_si(1, &[0.0, 0.0, 3.3], None).unwrap_err();
    assert!(
        matches!(e, SetpointError::OutOfRange { joint: 2, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("joint 2"));
    let e = setpoint_from_si(1, &[f64::NAN], None).unwrap_err();
    assert!(matches!(e, SetpointError::OutOfRange { joint: 0, .. }));
    let e = setpoint_from_si(1, &[0.0, 0.0], Some(&[0.0])).unwrap_err();
    assert_eq!(
        e,
        SetpointError::TorqueCount {
            angles: 2,
            torques: 1
        }
    );
    let e = setpoint_from_si(1, &[0.0; 40], None).unwrap_err();
    assert_eq!(e, SetpointError::TooManyJoints { count: 40, max: 32 });
}

#[test]
fn stance_bits_follow_the_paper_leg_order() {
    // Bit i = Leg::ALL[i] (LF, LM, LH, RF, RM, RH): LF and RM in stance -> bits 0 and 4.
    let legs = [Leg::RM, Leg::LF, Leg::LH];
    assert_eq!(stance_bits(&legs, &[true, true, false]), 0b1_0001);
}

#[test]
fn a_plan_becomes_a_table_the_protocol_parses() {
    let mut model = builtin("drosophibot2").unwrap();
    // Flip one servo and offset its zero to check the tick arithmetic by hand:
    // angle 0 sits at 2048 - sign * offset * 4096 / 2 pi = 2048 + 0.5 * 651.9 = 2373.95 -> 2374.
    let j0 = servo_joints(&model)[0];
    let servo = model.joints[j0].servo.as_mut().unwrap();
    servo.sign = -1;
    servo.zero_offset = 0.5;
    let params = planner::gait::StepParams {
        slices: 20,
        ..planner::gait::StepParams::table1("drosophibot2")
    };
    let plan = planner::plan::plan(&model, &params).unwrap();
    let bytes = step_table(&plan, None, "t").unwrap();
    let table = GaitTable::parse(&bytes).unwrap();
    assert_eq!(table.joint_count(), 22);
    assert_eq!(table.slice_count(), 20);
    let map = table.joint(0).unwrap();
    assert_eq!(map.sign, Sign::Negative);
    assert_eq!(map.zero_offset, 2374);
    // Angles in 1e-4 rad, slice 5, the table's joint 3.
    let j3 = servo_joints(&model)[3];
    let want = (plan.q[5][j3] * 1e4).round() as i16;
    assert_eq!(table.angle(5, 3), Some(want));
    let e = step_table(&plan, Some(&[vec![0.0; 3]]), "t").unwrap_err();
    assert!(e.to_string().contains("torques has 3 entries"), "{e}");
}
