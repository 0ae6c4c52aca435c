//! What a refusal says travels as words, not Rust (issue 25 item 6): the state and the setting are
//! named as the usage guide names them.

use protocol::{ProtocolError, RunState, Setting};

#[test]
fn a_refusal_names_the_state_and_the_setting_in_words() {
    let e = ProtocolError::WrongState {
        state: RunState::Fault,
    };
    assert_eq!(e.to_string(), "not allowed in state Fault (torque off)");
    let e = ProtocolError::InvalidSetting {
        setting: Setting::CycleRate,
        value: 700,
    };
    assert_eq!(e.to_string(), "cycle rate = 700 out of range");
}

#[test]
fn a_bad_joint_record_names_its_field_in_words() {
    let e = protocol::TableError::BadJoint {
        joint: 3,
        field: protocol::gait::JointField::Model,
    };
    assert_eq!(e.to_string(), "joint 3: invalid servo model");
}
