//! How much faster than real time the physics robot runs with the firmware in the loop: the
//! planner's tripod (table 1, 1.25 s cycles) uploaded over the board link and walked on flat
//! ground, MuJoCo 3.17.0 at `physics::TIMESTEP_S` (1 ms, 10 steps per 10 ms bus cycle),
//! everything on this thread. Also the MuJoCo plant alone, to show where time goes.
//!
//! Two modes in one bench (they share the walk):
//! - speed (default): `CYCLES` (8) cycles, `REPEATS` (5) runs, median and spread of each.
//! - tuning: any of DT (s), JACOBIAN (0 dense / 1 sparse / 2 auto), ITER, TOL, LS_ITER, NOSLIP, NOSLIP_TOL, SOLVER (0 PGS / 1 CG /
//!   2 Newton), DISABLE, ENABLE (flag bits) set: one walk of `CYCLES` (4) cycles under those MuJoCo
//!   options, printing speed and the walk's figures (distance, heading, sag, tilt, slip), to
//!   weigh solver settings against what they change.
//!
//! Times are CPU time of this thread (CLOCK_THREAD_CPUTIME_ID): the machines are shared and wall
//! time mostly measures other processes. Run: `cargo bench -p physics --bench physics_robot`
//! (tuning: `DT=0.0005 NOSLIP=5 cargo bench -p physics --bench physics_robot`).

use planner::terrain::Ground;
use std::time::Duration;

use board::link::Board;
use nix::time::{ClockId, clock_gettime};
use physics::{PhysicsRobot, Plant};
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::{MjcfOptions, Model, builtin};
use protocol::{PlayCommand, Steps};

/// The MuJoCo options the tuning mode reads from the environment.
const TUNING: [&str; 10] = [
    "DT",
    "JACOBIAN",
    "ITER",
    "TOL",
    "LS_ITER",
    "NOSLIP",
    "NOSLIP_TOL",
    "SOLVER",
    "DISABLE",
    "ENABLE",
];

fn cpu_now() -> Duration {
    let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("thread CPU clock");
    Duration::new(t.tv_sec() as u64, t.tv_nsec() as u32)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}

/// The tripod and what walking it needs.
struct Walk {
    model: Model,
    table: Vec<u8>,
    period_s: f64,
}

impl Walk {
    fn tripod() -> Self {
        let model = builtin("drosophibot2").unwrap();
        let params = StepParams::table1(&model.name);
        let plan = planner::plan::plan(&model, &params).unwrap();
        let cycle = solve_cycle(&model, &plan_inputs(&plan), &DynamicsOptions::default()).unwrap();
        let torques = planner::dynamics::output::torque_rows(&cycle);
        let table = planner::plan::table::step_table(&plan, Some(&torques), "dbII tripod").unwrap();
        Self {
            model,
            table,
            period_s: plan.period_s,
        }
    }

    /// Uploads the tripod to `robot` and walks `cycles` cycles: the board after the stop and the
    /// thread CPU time it took, s.
    fn run(&self, robot: PhysicsRobot, cycles: u32) -> (Board<physics::PhysicsTransport>, f64) {
        let t0 = cpu_now();
        let mut b = Board::connect(robot.into_transport()).unwrap();
        gate::upload(&mut b, 0, &self.table).unwrap();
        gate::play(&mut b, PlayCommand::forward(0, Steps::Count(cycles))).unwrap();
        b.wait(Duration::from_secs_f64(
            self.period_s * f64::from(cycles) + 1.0,
        ))
        .unwrap();
        (b, (cpu_now() - t0).as_secs_f64())
    }
}

fn main() {
    let walk = Walk::tripod();
    let options = PhysicsRobot::options(&walk.model, &Ground::Flat).unwrap();
    if TUNING.iter().any(|v| std::env::var_os(v).is_some()) {
        tuning(&walk, options);
    } else {
        speed(&walk, &options);
    }
}

fn speed(walk: &Walk, options: &MjcfOptions) {
    let cycles: u32 = env("CYCLES").unwrap_or(8);
    let repeats: usize = env("REPEATS").unwrap_or(5);
    let mut full = Vec::new();
    let mut plant_only = Vec::new();
    let mut sim_s = 0.0;
    // Interleaved, so a change in the machine's load hits both alike.
    for _ in 0..repeats {
        let robot = PhysicsRobot::with_options(&walk.model, options, &Ground::Flat).unwrap();
        let (b, cpu) = walk.run(robot, cycles);
        sim_s = b.transport().robot().now_us() as f64 * 1e-6;
        full.push(sim_s / cpu);

        let mut plant = Plant::new(&walk.model, options).unwrap();
        for i in 0..plant.joints().len() {
            let j = plant.joints()[i].clone();
            plant.set_goal(i, options.stance_q[j.joint], true);
        }
        let t0 = cpu_now();
        plant.advance_to(sim_s);
        plant_only.push(sim_s / (cpu_now() - t0).as_secs_f64());
    }
    let runs = |v: &[f64]| v.iter().map(|x| format!("{x:.1}")).collect::<Vec<_>>();
    println!(
        "physics robot, firmware in the loop: {sim_s:.1} s simulated, {:.1}x real time (median of {repeats}; runs {:?})",
        median(full.clone()),
        runs(&full)
    );
    println!(
        "MuJoCo plant alone (standing, same span): {:.1}x real time (runs {:?}); timestep {} ms, MuJoCo 3.17.0",
        median(plant_only.clone()),
        runs(&plant_only),
        options.timestep_s * 1e3
    );
}

fn tuning(walk: &Walk, mut options: MjcfOptions) {
    let cycles: u32 = env("CYCLES").unwrap_or(4);
    if let Some(dt) = env("DT") {
        options.timestep_s = dt;
    }
    let mut robot = PhysicsRobot::with_options(&walk.model, &options, &Ground::Flat).unwrap();
    {
        let o = robot.plant_mut().option_mut();
        if let Some(v) = env("ITER") {
            o.iterations = v;
        }
        if let Some(v) = env("LS_ITER") {
            o.ls_iterations = v;
        }
        if let Some(v) = env("TOL") {
            o.tolerance = v;
        }
        if let Some(v) = env("NOSLIP") {
            o.noslip_iterations = v;
        }
        if let Some(v) = env("NOSLIP_TOL") {
            o.noslip_tolerance = v;
        }
        if let Some(v) = env("SOLVER") {
            o.solver = v;
        }
        if let Some(v) = env("JACOBIAN") {
            o.jacobian = v;
        }
        if let Some(v) = env::<i32>("DISABLE") {
            o.disableflags |= v;
        }
        if let Some(v) = env::<i32>("ENABLE") {
            o.enableflags |= v;
        }
    }
    let (b, cpu) = walk.run(robot, cycles);
    let r = b.transport().robot();
    let sim = r.now_us() as f64 * 1e-6;
    let f = r.servos().figures().unwrap();
    let slip: Vec<String> = f
        .slip_m
        .iter()
        .map(|(_, s)| format!("{:.2}", s * 1e3))
        .collect();
    println!(
        "dt {:.2} ms: {:.1}x real time ({sim:.1} s in {cpu:.2} s CPU, {:.1} us/step); forward {:.2} mm, heading {:.3} deg, lowest {:.2} mm, tilt {:.2} deg, slip mm {:?}",
        options.timestep_s * 1e3,
        sim / cpu,
        cpu / (sim / options.timestep_s) * 1e6,
        f.forward_m * 1e3,
        f.heading_rad.to_degrees(),
        f.height_min_m * 1e3,
        f.tilt_max_rad.to_degrees(),
        slip
    );
}

#[path = "../../board/tests/gate/mod.rs"]
mod gate;
