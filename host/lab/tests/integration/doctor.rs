//! The bring-up check (`lab::doctor`) against the robot's virtual servo chain with faults put in
//! (a missing servo, a wrong model, a wrong baud rate, two swapped IDs, the factory Return Delay
//! Time), the strain board's test double with a channel stuck at 0 counts, and a healthy robot
//! (the in-process virtual robot and a virtual strain board) passing. Model numbers are the
//! e-manual's (MX-28: 30, MX-64: 311); the rates its Baud Rate table's.

use board::robot::{robot_chain, robot_servos};
use board::strain::port::open_virtual;
use board::strain::source::Shared;
use board::strain::{Channel, VirtualStrainBoard};
use dynamixel::ServoModel;
use dynamixel::control_table as ct;
use dynamixel::sim::{Faults, SimWire, VirtualChain, WireConfig};
use lab::doctor::{self, Item, Outcome, SimBus};

const BAUD: u32 = 1_000_000;

fn model() -> planner::model::Model {
    planner::model::builtin("drosophibot2").unwrap()
}

/// The items of the servo check on the robot's chain (Return Delay 0, 1 Mbit/s) after `change`.
fn check(change: impl FnOnce(&mut VirtualChain)) -> Vec<Item> {
    let mut chain = robot_chain(BAUD);
    change(&mut chain);
    check_chain(chain)
}

fn check_chain(chain: VirtualChain) -> Vec<Item> {
    let wire = SimWire::new(
        chain,
        WireConfig {
            baud: BAUD,
            echo: true,
        },
    );
    let mut bus = SimBus::new("test bus", wire, BAUD);
    doctor::check_servos(&mut bus, &doctor::expected_servos(&model()))
}

fn item<'a>(items: &'a [Item], name_start: &str) -> &'a Item {
    items
        .iter()
        .find(|i| i.name.starts_with(name_start))
        .unwrap_or_else(|| panic!("no item {name_start}: {items:#?}"))
}

fn failed(items: &[Item]) -> Vec<&str> {
    items
        .iter()
        .filter(|i| i.outcome == Outcome::Fail)
        .map(|i| i.name.as_str())
        .collect()
}

#[test]
fn a_healthy_chain_passes_every_servo_and_the_supply() {
    let items = check(|_| {});
    // 22 servos in the model file, then the supply.
    assert_eq!(items.len(), 23, "{items:#?}");
    assert!(failed(&items).is_empty(), "{items:#?}");
    let ctr = item(&items, "servo ID 3 ");
    assert!(
        ctr.detail.contains("MX-64(2.0) (model number 311)"),
        "{}",
        ctr.detail
    );
    // The virtual servos report 12.0 V (register 144 = 120, 0.1 V units).
    let supply = item(&items, "supply voltage");
    assert!(supply.detail.contains("12.0 V"), "{}", supply.detail);
}

#[test]
fn a_missing_servo_fails_naming_it_and_what_to_check() {
    let items = check(|c| c.set_faults(5, Faults::SILENT).unwrap());
    let i = item(&items, "servo ID 5 ");
    assert_eq!(failed(&items), [i.name.as_str()]);
    assert!(i.detail.starts_with("missing"), "{}", i.detail);
    assert!(
        i.fix.as_deref().unwrap().contains("scan --baud auto"),
        "{i}"
    );
}

#[test]
fn a_wrong_model_fails_with_both_models() {
    // An MX-28 where the model file has the MX-64 of ID 3 (LF CTr).
    let servos: Vec<_> = robot_servos()
        .into_iter()
        .map(|(id, m)| (id, if id == 3 { ServoModel::Mx28 } else { m }))
        .collect();
    assert!(robot_servos().contains(&(3, ServoModel::Mx64)));
    let mut chain = VirtualChain::new(&servos, BAUD).unwrap();
    chain.set_return_delay_all(0);
    let items = check_chain(chain);
    assert_eq!(failed(&items).len(), 1, "{items:#?}");
    let i = item(&items, "servo ID 3 ");
    assert!(
        i.detail
            .contains("answers as MX-28(2.0) (model number 30), the model file has MX-64(2.0) (model number 311)"),
        "{}",
        i.detail
    );
    assert!(i.detail.contains("wrong model"), "{}", i.detail);
}

#[test]
fn a_servo_at_another_baud_is_found_there_and_named() {
    // Baud Rate code 1 = 57 600 bit/s, the factory rate.
    let items = check(|c| c.servo_mut(7).unwrap().put(ct::BAUD_RATE, 1));
    assert_eq!(failed(&items).len(), 1, "{items:#?}");
    let i = item(&items, "servo ID 7 ");
    assert!(
        i.detail
            .contains("answers at 57600 bit/s, not at the bus's 1000000 bit/s (wrong baud rate)"),
        "{}",
        i.detail
    );
    assert!(
        i.fix.as_deref().unwrap().contains("--new-baud 1000000"),
        "{i}"
    );
}

#[test]
fn two_swapped_ids_are_called_swapped() {
    // ID 3 carries an MX-64 (LF CTr), ID 4 an MX-28: the two servos trade IDs.
    let items = check(|c| {
        let s = c.servos_mut();
        let a = s.iter().position(|v| v.id() == 3).unwrap();
        let b = s.iter().position(|v| v.id() == 4).unwrap();
        s[a].put(ct::ID, 4);
        s[b].put(ct::ID, 3);
    });
    assert_eq!(failed(&items).len(), 2, "{items:#?}");
    for (id, other) in [(3, 4), (4, 3)] {
        let i = item(&items, &format!("servo ID {id} "));
        let fix = i.fix.as_deref().unwrap();
        assert!(
            fix.contains(&format!("IDs {id} and {other} look swapped")),
            "{i}"
        );
    }
}

#[test]
fn the_factory_return_delay_fails_with_the_setup_command() {
    // Factory Return Delay Time: 250 = 500 us.
    let items = check(|c| c.servo_mut(9).unwrap().put(ct::RETURN_DELAY_TIME, 250));
    assert_eq!(failed(&items).len(), 1, "{items:#?}");
    let i = item(&items, "servo ID 9 ");
    assert!(
        i.detail.contains("Return Delay Time 250 (500 us"),
        "{}",
        i.detail
    );
    assert!(
        i.fix.as_deref().unwrap().contains("--return-delay-us 0"),
        "{i}"
    );
}

#[test]
fn a_low_supply_fails() {
    // A 9.5 V supply: below the MX's 10 V (the virtual servos read the chain's supply, less the
    // line drop, in Present Input Voltage).
    let items = check(|c| {
        c.supply = dynamixel::sim::thermal::Supply {
            volts: 9.5,
            line_ohm: 0.0,
        }
    });
    let i = item(&items, "supply voltage");
    assert_eq!(i.outcome, Outcome::Fail, "{i}");
    assert!(i.detail.contains("9.5 V (ID "), "{}", i.detail);
}

#[test]
fn a_strain_channel_stuck_at_zero_fails_naming_it() {
    let feed = Shared::default();
    let stuck = Channel::at_column(7).unwrap();
    let mut strain = [0.0; 36];
    // Far below what the 10-bit ADC reads from the 300-count baseline: the channel sits at 0.
    strain[7] = -1.0e6;
    feed.set(strain);
    let io = open_virtual(VirtualStrainBoard::new(Box::new(feed), Vec::new(), false)).unwrap();
    let i = doctor::check_strain_io(io, "test strain board", 0.05);
    assert_eq!(i.outcome, Outcome::Fail, "{i}");
    assert!(
        i.detail
            .contains(&format!("{} stuck at 0 counts", stuck.describe())),
        "{}",
        i.detail
    );
}

#[test]
fn the_healthy_virtual_robot_and_strain_board_pass() {
    let report = doctor::run(
        &model(),
        &doctor::Options {
            port: Some("virtual".into()),
            strain: Some("virtual".into()),
            strain_seconds: 0.05,
            ..Default::default()
        },
    );
    assert!(report.ok(), "{}", report.text());
    let names: Vec<&str> = report.items.iter().map(|i| i.name.as_str()).collect();
    // The board first, then its bus, the servos, the supply, the strain board.
    assert_eq!(
        &names[..4],
        ["board", "board state", "board bus", "servo bus"]
    );
    assert_eq!(names[names.len() - 2..], ["supply voltage", "strain board"]);
    assert_eq!(names.len(), 4 + 22 + 2);
    assert!(
        report
            .text()
            .ends_with("28 passed, 0 failed, 0 not checked\n"),
        "{}",
        report.text()
    );
}

/// The servo items through a board's own bus (reads passed through it, `ReadServo`) on the
/// in-process virtual robot built on `chain`.
fn check_through_a_board(chain: VirtualChain) -> Vec<Item> {
    use board::robot::{FLASH_SECTORS, VirtualFlash, VirtualRobot, VirtualTransport};
    let robot = VirtualRobot::with_parts(
        VirtualFlash::new(FLASH_SECTORS),
        chain,
        board::robot::PlannedLoads,
    );
    let mut b = board::link::Board::connect(VirtualTransport::new(robot)).unwrap();
    let mut bus = doctor::BoardBus::new(&mut b, BAUD);
    doctor::check_servos(&mut bus, &doctor::expected_servos(&model()))
}

#[test]
fn through_a_board_every_servo_is_read_and_a_wrong_or_missing_one_named() {
    // Healthy: the same 22 servos and supply as on a bus of its own.
    let items = check_through_a_board(robot_chain(BAUD));
    assert_eq!(items.len(), 23, "{items:#?}");
    assert!(failed(&items).is_empty(), "{items:#?}");
    assert!(
        item(&items, "servo ID 3 ")
            .detail
            .contains("MX-64(2.0) (model number 311)")
    );
    // An MX-28 at ID 3 and servo 5 silent: both named; the silent one not looked for at other
    // rates, which the board's bus cannot change to, and the item says so.
    let servos: Vec<_> = robot_servos()
        .into_iter()
        .map(|(id, m)| (id, if id == 3 { ServoModel::Mx28 } else { m }))
        .collect();
    let mut chain = VirtualChain::new(&servos, BAUD).unwrap();
    chain.set_return_delay_all(0);
    chain.set_faults(5, Faults::SILENT).unwrap();
    let items = check_through_a_board(chain);
    let (three, five) = (item(&items, "servo ID 3 "), item(&items, "servo ID 5 "));
    assert_eq!(failed(&items), [three.name.as_str(), five.name.as_str()]);
    assert!(
        three
            .detail
            .contains("answers as MX-28(2.0) (model number 30)"),
        "{three}"
    );
    assert!(
        five.detail
            .starts_with("missing: no answer at 1000000 bit/s (the board's bus runs at"),
        "{five}"
    );
}
