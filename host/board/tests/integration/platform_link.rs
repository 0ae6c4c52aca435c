//! `Board::set_platform` against the in-process virtual robot (the firmware library over a
//! simulated bus): with a platform servo on the chain (ID 23, after the model's joints 1-22) the
//! set-up is checked, the run's telemetry carries the platform's goal (rise at the first cycle of
//! the chosen step, rest two cycles later: the synthetic gait's 1 s step at 100 Hz is 100 cycles)
//! and its servo follows; without one the error names the ID; the lab's ID 22 is a joint's here
//! and is refused before anything is sent.

use std::time::Duration;

use board::link::{Board, LinkError};
use board::platform::Perturb;
use board::robot::{FLASH_SECTORS, VirtualFlash, VirtualRobot, VirtualTransport, robot_servos};
use dynamixel::ServoModel;
use dynamixel::sim::VirtualChain;
use firmware::testkit::SyntheticGait;
use protocol::{PlatformError, PlayCommand, RunState, Steps};

fn board_with_platform_servo() -> Board<VirtualTransport> {
    let mut servos = robot_servos();
    servos.push((23, ServoModel::Mx28));
    let mut chain = VirtualChain::new(&servos, 1_000_000).unwrap();
    chain.set_return_delay_all(0);
    let robot = VirtualRobot::with_parts(
        VirtualFlash::new(FLASH_SECTORS),
        chain,
        board::robot::PlannedLoads,
    );
    Board::connect(VirtualTransport::new(robot)).unwrap()
}

fn play(steps: u32) -> PlayCommand {
    PlayCommand::forward(0, Steps::Count(steps))
}

#[test]
fn the_platform_rises_in_the_telemetry_at_its_step_and_its_servo_follows() {
    let mut b = board_with_platform_servo();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    let p = Perturb::parse("RM:1:rise", 23).unwrap();
    b.set_platform(p.setup).unwrap();
    b.set_telemetry(1).unwrap();
    // Selecting the gait boots the board again to find its servos: play once it is Idle.
    loop {
        match gate::play(&mut b, play(3)) {
            Ok(()) => break,
            Err(LinkError::Device { .. }) => b.wait(Duration::from_millis(20)).unwrap(),
            Err(e) => panic!("{e}"),
        }
    }
    let mut goals = vec![];
    while b.status().unwrap().state != RunState::Standing {
        b.wait(Duration::from_millis(100)).unwrap();
        while let Some(t) = b.telemetry(Duration::ZERO).unwrap() {
            if let Some(pl) = t.platform {
                goals.push((t.step, pl.goal, pl.present));
            }
        }
    }
    let risen: Vec<&(u32, u16, u16)> = goals.iter().filter(|g| g.1 == 2330).collect();
    assert_eq!(risen.len(), 2, "{risen:?}");
    assert!(risen.iter().all(|g| g.0 == 1), "{risen:?}");
    // The first record of step 1 is the first at rise.
    let first_of_step1 = goals.iter().position(|g| g.0 == 1).unwrap();
    assert_eq!(goals[first_of_step1].1, 2330);
    assert_eq!(goals[first_of_step1 + 2].1, 2020);
    // The servo moved towards rise (its own lag model: 310 ticks take longer than two cycles).
    let peak = goals.iter().map(|g| g.2).max().unwrap();
    assert!(peak > 2030, "the platform servo never left rest: {peak}");
}

#[test]
fn a_missing_platform_servo_and_a_joints_id_are_named() {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    gate::upload(&mut b, 0, &SyntheticGait::new(100, 1.0).build()).unwrap();
    let e = b
        .set_platform(Perturb::parse("LF:0:rise", 23).unwrap().setup)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "virtual: perturbation platform: platform servo ID 23 does not answer (ping, profile \
         velocity or position read failed): check its cable and ID"
    );
    // The uploaded gait is the board's joint map: the lab's ID 22 is joint 21's servo.
    let e = b
        .set_platform(Perturb::parse("LF:0:rise", 22).unwrap().setup)
        .unwrap_err();
    assert!(
        matches!(
            e,
            LinkError::Platform {
                error: PlatformError::JointId {
                    servo_id: 22,
                    joint: 21
                },
                ..
            }
        ),
        "{e}"
    );
}

use crate::gate;
