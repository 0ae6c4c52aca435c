//! The perturbation platform's servo on the physics robot's bus: the firmware, set up through
//! `Board::set_platform`, writes the platform's Goal Position in its Sync Write (standing, the
//! rest position), and the box's slide follows it. Against a hand calculation: the top settles at
//! (goal - LEVEL_TICKS) x HEIGHT_PER_TICK_M less the slide's static sag under its own weight
//! (m g / kp), and the servo's Present Position reads that height back in ticks.

use crate::support;
use std::time::Duration;

use board::link::Board;
use dynamixel::control_table as ct;
use physics::platform::{HEIGHT_PER_TICK_M, LEVEL_TICKS, PLATFORM_KP_N_PER_M, PLATFORM_MASS_KG};
use physics::{PhysicsRobot, PlatformPlace, Substrate};
use planner::model::builtin;
use planner::terrain::Ground;
use protocol::{PlatformMove, PlatformSetup, ServoSelect};

#[test]
fn the_platform_slide_follows_the_goal_position_the_firmware_writes() {
    let model = builtin("drosophibot2").unwrap();
    let (_, _, table) = support::tripod(&model);
    // The box 1 m from the robot: no foot on it, only its own weight.
    let robot = PhysicsRobot::with_platform(
        &Ground::Flat,
        Substrate::Sandpaper,
        23,
        PlatformPlace::At([1.0, 1.0]),
    )
    .unwrap();
    let mut b = Board::connect(robot.into_transport()).unwrap();
    gate::upload(&mut b, 0, &table).unwrap();
    b.set_torque(ServoSelect::All, true).unwrap();
    // Rest 2330 ticks: standing, every cycle's Sync Write carries the platform's rest goal.
    let setup = PlatformSetup {
        servo_id: 23,
        rest: 2330,
        rise: 2400,
        ..PlatformSetup::lab(PlatformMove::Rise, 0)
    };
    b.set_platform(setup).unwrap();
    // 310 ticks at 115 mm/s (profile velocity 240) take 83 ms; the slide settles within
    // 1 s (critically damped, time constant 2 m / kv = 4.4 ms).
    b.wait(Duration::from_secs(1)).unwrap();
    assert_eq!(b.status().unwrap().fault, None);
    let robot = b.transport().robot();
    let (goal, h) = robot.servos().platform_state().unwrap();
    assert_eq!(goal, 2330);
    // (2330 - 2020) x 20 mm x 2 pi / 4096 = 9.5115 mm, less the sag 0.2 kg x 9.81 / 1e4 N/m =
    // 0.196 mm: 9.315 mm.
    let level = f64::from(2330 - LEVEL_TICKS) * HEIGHT_PER_TICK_M;
    let sag = PLATFORM_MASS_KG * 9.81 / PLATFORM_KP_N_PER_M;
    assert!((level - 9.5115e-3).abs() < 1e-6 && (sag - 1.962e-4).abs() < 1e-6);
    assert!(
        (h - (level - sag)).abs() < 2e-5,
        "top at {:.4} mm, hand calculation {:.4} mm",
        h * 1e3,
        (level - sag) * 1e3
    );
    // Present Position: 9.315 mm / 0.03068 mm per tick = 303.6 ticks above level: 2324.
    let present = robot.with_chain(|c| c.servo(23).unwrap().get(ct::PRESENT_POSITION));
    assert_eq!(present, 2324);
}

use support::gate;
