//! How much faster than real time the physics robot runs with the firmware in the loop: the
//! planner's tripod (table 1, 1.25 s cycles) uploaded over the board link and walked for
//! `CYCLES` cycles on flat ground, MuJoCo 3.17.0 at the MJCF's 0.5 ms timestep (20 steps per 10 ms
//! bus cycle), everything on this thread. Also the MuJoCo plant alone, to show where time goes.
//!
//! Times are CPU time of this thread (CLOCK_THREAD_CPUTIME_ID): the machines are shared and wall
//! time mostly measures other processes. Run: `cargo bench -p physics --bench physics_robot`.

use std::time::Duration;

use board::link::Board;
use nix::time::{ClockId, clock_gettime};
use physics::{PhysicsRobot, Plant};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;
use protocol::{Direction, PlayCommand, Steps};

const CYCLES: u32 = 8;
const REPEATS: usize = 3;

fn cpu_now() -> Duration {
    let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("thread CPU clock");
    Duration::new(t.tv_sec() as u64, t.tv_nsec() as u32)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let model = builtin("drosophibot2").unwrap();
    let params = StepParams::table1(&model.name);
    let plan = planner::plan::plan(&model, &params).unwrap();
    let cycle = solve_cycle(&model, &plan_inputs(&plan), &DynamicsOptions::default()).unwrap();
    let torques = planner::dynamics::output::torque_rows(&cycle);
    let table = planner::plan::table::step_table(&plan, Some(&torques), "dbII tripod").unwrap();
    let options = PhysicsRobot::options(&model, "flat").unwrap();

    let mut full = Vec::new();
    let mut sim_s = 0.0;
    for _ in 0..REPEATS {
        let robot = PhysicsRobot::with_options(&model, &options, "flat").unwrap();
        let t0 = cpu_now();
        let mut b = Board::connect(robot.into_transport()).unwrap();
        b.upload(0, &table, |_, _| {}).unwrap();
        b.play(PlayCommand {
            slot: 0,
            direction: Direction::Forward,
            period_scale: 1000,
            steps: Steps::Count(CYCLES),
        })
        .unwrap();
        b.wait(Duration::from_secs_f64(
            plan.period_s * f64::from(CYCLES) + 1.0,
        ))
        .unwrap();
        let cpu = (cpu_now() - t0).as_secs_f64();
        sim_s = b.transport().robot().now_us() as f64 * 1e-6;
        full.push(sim_s / cpu);
    }

    let mut plant_only = Vec::new();
    for _ in 0..REPEATS {
        let mut plant = Plant::new(&model, &options).unwrap();
        for i in 0..plant.joints().len() {
            let j = plant.joints()[i].clone();
            plant.set_goal(i, options.stance_q[j.joint], true);
        }
        let t0 = cpu_now();
        plant.advance_to(sim_s);
        plant_only.push(sim_s / (cpu_now() - t0).as_secs_f64());
    }
    println!(
        "physics robot, firmware in the loop: {:.1} s simulated, {:.1}x real time (median of {REPEATS}; runs {:?})",
        sim_s,
        median(full.clone()),
        full.iter().map(|x| format!("{x:.1}")).collect::<Vec<_>>()
    );
    println!(
        "MuJoCo plant alone (standing, same span): {:.1}x real time; timestep {} ms, MuJoCo 3.17.0",
        median(plant_only),
        options.timestep_s * 1e3
    );
}
