//! The servos' Position P Gain on the simulated wire: the whole board (link, controller, bus loop,
//! bus master) writes each joint's stiffness into the 22 virtual servos' registers at torque-on and
//! after `SetStiffness`, leaves them alone for stiffness 0, and the cycle that carries the extra
//! write keeps the default rate's budget.

use dynamixel::control_table::POSITION_P_GAIN;
use dynamixel::sim::SimWire;
use protocol::{Client, Request, Response};

use crate::safety::State;
use crate::testkit::rig::{SimBoard, cycle, walking};
use crate::testkit::{JOINTS, SyntheticGait};

/// Every virtual servo's Position P Gain register, in joint order (ID j + 1).
fn gains(wire: &SimWire) -> Vec<u32> {
    wire.with_chain(|c| {
        (1..=JOINTS as u8)
            .map(|id| c.servo(id).unwrap().get(POSITION_P_GAIN))
            .collect()
    })
}

/// The testkit's 8.4 N m/rad as each model's P gain, by hand: 1 P unit = (1/128) / 885 x stall
/// torque x 4096 / (2 pi) = 0.014387 N m/rad (MX-28, 2.5 N m), 0.034529 (MX-64, 6.0 N m);
/// 8.4 / 0.014387 = 583.86 -> 584, 8.4 / 0.034529 = 243.28 -> 243; each joint's model is the
/// testkit gait's.
fn table_gains() -> Vec<u32> {
    let gait = SyntheticGait::new(2, 1.0);
    assert_eq!(gait.joints.len(), JOINTS);
    gait.joints
        .iter()
        .map(|j| match j.model {
            dynamixel::ServoModel::Mx28 => 584,
            dynamixel::ServoModel::Mx64 => 243,
        })
        .collect()
}

fn set_stiffness(board: &mut SimBoard, client: &mut Client, joint: u8, stiffness: u32) {
    let r = crate::testkit::rig::ask(board, client, Request::SetStiffness { joint, stiffness });
    assert_eq!(r, Response::Ack);
}

#[test]
fn the_p_gain_registers_hold_the_joints_stiffness_after_torque_on_and_set_stiffness() {
    // Default rate and baud: 100 Hz, 1 Mbit/s.
    let (mut board, wire, mut client) =
        walking(1_000_000, 100, &SyntheticGait::new(100, 1.0).build());
    assert_eq!(gains(&wire), table_gains(), "after torque-on");

    // While walking: joint 0 (MX-28) to 4.2 N m/rad -> 4.2 / 0.014387 = 291.93 -> 292; joint 2
    // (ID 3, MX-64) to 16.8 N m/rad -> 16.8 / 0.034529 = 486.56 -> 487.
    board.schedule.timing = Default::default();
    set_stiffness(&mut board, &mut client, 0, 4200);
    set_stiffness(&mut board, &mut client, 2, 16_800);
    cycle(&mut board, &wire);
    let mut want = table_gains();
    want[0] = 292;
    want[2] = 487;
    assert_eq!(gains(&wire), want, "one cycle after SetStiffness");
    // The cycle with the extra Sync Write (14 + 3 x 22 bytes = 80 bytes, 0.8 ms at 1 Mbit/s on
    // top of the 6.23 ms walking cycle) fits the 10 ms period: no overrun, the walk goes on.
    let busy = board.timing().max_busy_us;
    eprintln!("cycle with the gain write: {busy} us of the 10000 us period");
    assert!(busy < 10_000, "{busy} us");
    for _ in 0..20 {
        cycle(&mut board, &wire);
    }
    assert_eq!(board.timing().overruns, 0);
    assert_eq!(board.controller.borrow().state(), State::Walking);

    // Stiffness 0 (torque bias off): the servo keeps the gain it has, not a limp 0.
    set_stiffness(&mut board, &mut client, 0, 0);
    for _ in 0..5 {
        cycle(&mut board, &wire);
    }
    assert_eq!(gains(&wire), want, "after stiffness 0 on joint 0");
}
