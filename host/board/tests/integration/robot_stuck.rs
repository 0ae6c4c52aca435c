//! The firmware's stuck-servo rule (firmware/src/safety/stuck.rs) on the virtual robot walking the
//! built-in Drosophibot II tripod gait (planned, with its inverse-dynamics torques as the torque
//! bias and as each servo's load): ten steps raise no fault, and a jammed joint is reported by name.

use std::time::Duration;

use board::link::Board;
use board::robot::{VirtualRobot, VirtualTransport};
use dynamixel::sim::Faults;
use planner::dynamics::{DynamicsOptions, output, plan_inputs, solve_cycle};
use protocol::{FaultKind, PlayCommand, RunState, Steps, Telemetry};

/// The step table `dbot demo` builds: the paper's table 1 parameters on flat ground.
fn tripod_table() -> Vec<u8> {
    let model = planner::model::builtin("drosophibot2").unwrap();
    let params = planner::gait::StepParams::table1(&model.name);
    let plan = planner::plan::plan(&model, &params).unwrap();
    let cycle = solve_cycle(
        &plan.model,
        &plan_inputs(&plan),
        &DynamicsOptions::default(),
    )
    .unwrap();
    planner::plan::table::step_table(&plan, Some(&output::torque_rows(&cycle)), "dbII tripod")
        .unwrap()
}

fn walking(table: &[u8], steps: Steps) -> Board<VirtualTransport> {
    let mut b = Board::connect(VirtualTransport::new(VirtualRobot::new())).unwrap();
    gate::upload(&mut b, 0, table).unwrap();
    gate::play(&mut b, PlayCommand::forward(0, steps)).unwrap();
    b
}

/// One tick in telemetry units (1e-4 rad).
const TICK: f64 = std::f64::consts::TAU / 4096.0 * 1e4;

#[test]
fn ten_loaded_steps_of_the_tripod_gait_raise_no_stuck_fault() {
    let table = tripod_table();
    let mut b = walking(&table, Steps::Count(10));
    let mut records: Vec<Telemetry> = Vec::new();
    let mut last_step = 0;
    while let Some(t) = b.telemetry(Duration::from_secs(1)).unwrap() {
        last_step = t.step;
        records.push(t);
        if records.len().is_multiple_of(50) {
            let s = b.status().unwrap();
            assert!(s.fault.is_none(), "{:?}", s.fault);
            if s.state == RunState::Standing {
                break;
            }
        }
        assert!(records.len() < 3000, "the walk did not end");
    }
    let s = b.status().unwrap();
    assert_eq!(
        (s.state, s.fault, last_step),
        (RunState::Standing, None, 10)
    );
    // The margin, from the telemetry: over every 50 consecutive records in which a joint's
    // command moved over more than 40 ticks, how little did that joint move?
    let n = records[0].joints.len();
    let range = |v: &[i16]| {
        f64::from(i32::from(*v.iter().max().unwrap()) - i32::from(*v.iter().min().unwrap())) / TICK
    };
    let mut least = f64::MAX;
    for j in 0..n {
        let cmd: Vec<i16> = records.iter().map(|t| t.joints[j].commanded).collect();
        let pos: Vec<i16> = records.iter().map(|t| t.joints[j].present).collect();
        for k in 0..records.len() - 50 {
            if range(&cmd[k..k + 50]) > 40.0 {
                least = least.min(range(&pos[k..k + 50]));
            }
        }
    }
    eprintln!(
        "tripod, 10 loaded steps: {} records; least motion of a joint whose command moved > 40 ticks in 50 cycles: {least:.0} ticks",
        records.len()
    );
    assert!(least > 10.0, "{least:.1} ticks");
}

#[test]
fn a_jammed_joint_of_the_tripod_gait_is_reported_as_servo_stuck_naming_it() {
    let table = tripod_table();
    let t = protocol::GaitTable::parse(&table).unwrap();
    // The joint that swings most over the step, and its servo.
    let swing = |j: usize| {
        let a: Vec<i16> = (0..t.slice_count())
            .map(|s| t.angle(s, j).unwrap())
            .collect();
        i32::from(*a.iter().max().unwrap()) - i32::from(*a.iter().min().unwrap())
    };
    let joint = (0..t.joint_count()).max_by_key(|&j| swing(j)).unwrap();
    let id = t.joint(joint).unwrap().servo_id;
    let mut b = walking(&table, Steps::Continuous);
    while b.status().unwrap().state != RunState::Walking {
        b.wait(Duration::from_millis(100)).unwrap();
    }
    b.wait(Duration::from_secs(1)).unwrap();
    b.transport()
        .robot()
        .with_chain(|c| {
            c.set_faults(
                id,
                Faults {
                    stuck: true,
                    ..Faults::default()
                },
            )
        })
        .unwrap();
    let t0 = b.now();
    let fault = loop {
        b.wait(Duration::from_millis(50)).unwrap();
        if let Some(f) = b.status().unwrap().fault {
            break f;
        }
        assert!(b.now() - t0 < Duration::from_secs(3), "no fault");
    };
    let dt = b.now() - t0;
    eprintln!("joint {joint} (ID {id}): {fault:?} {dt:?} after the jam");
    // The rule checks each 50-cycle window (0.5 s at 100 Hz) that ends after the jam, and fires on
    // the first whole one in which the goal moved over 40 ticks. This joint swings most in the
    // swing phase and rests in stance (0.75 s of the 1.25 s step), so the bound is two windows plus
    // the stance rest, plus the 50 ms polling step here.
    assert!(dt <= Duration::from_millis(1000 + 750 + 50), "{dt:?}");
    assert_eq!(fault.joint, Some(joint as u8));
    assert!(
        matches!(fault.kind, FaultKind::ServoStuck { goal_range, present_range } if goal_range > 40 && present_range <= 2),
        "{fault:?}"
    );
    // What `dbot status` prints for it.
    let text = fault.to_string();
    assert!(
        text.starts_with(&format!("ServoStuck on joint {joint}: servo stuck")),
        "{text}"
    );
}

use crate::gate;
