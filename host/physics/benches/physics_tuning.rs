//! Solver settings against speed and the walk's figures: the planner's tripod walked 4 cycles
//! under the firmware with MuJoCo options from the environment (DT in s, ITER, TOL, LS_ITER,
//! NOSLIP, NOSLIP_TOL, SOLVER 0 PGS / 1 CG / 2 Newton, DISABLE and ENABLE flag bits), thread CPU
//! time. Run: `DT=0.001 cargo bench -p physics --bench physics_tuning`.

use std::time::Duration;

use board::link::Board;
use nix::time::{ClockId, clock_gettime};
use physics::PhysicsRobot;
use planner::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use planner::gait::StepParams;
use planner::model::builtin;
use protocol::{Direction, PlayCommand, Steps};

fn cpu_now() -> Duration {
    let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("thread CPU clock");
    Duration::new(t.tv_sec() as u64, t.tv_nsec() as u32)
}

fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}

fn main() {
    let cycles: u32 = env("CYCLES").unwrap_or(4);
    let model = builtin("drosophibot2").unwrap();
    let params = StepParams::table1(&model.name);
    let plan = planner::plan::plan(&model, &params).unwrap();
    let cycle = solve_cycle(&model, &plan_inputs(&plan), &DynamicsOptions::default()).unwrap();
    let torques = planner::dynamics::output::torque_rows(&cycle);
    let table = planner::plan::table::step_table(&plan, Some(&torques), "dbII tripod").unwrap();
    let mut options = PhysicsRobot::options(&model, "flat").unwrap();
    if let Some(dt) = env("DT") {
        options.timestep_s = dt;
    }
    let mut robot = PhysicsRobot::with_options(&model, &options, "flat").unwrap();
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
        if let Some(v) = env::<i32>("DISABLE") {
            o.disableflags |= v;
        }
        if let Some(v) = env::<i32>("ENABLE") {
            o.enableflags |= v;
        }
    }
    let t0 = cpu_now();
    let mut b = Board::connect(robot.into_transport()).unwrap();
    b.upload(0, &table, |_, _| {}).unwrap();
    b.play(PlayCommand {
        slot: 0,
        direction: Direction::Forward,
        period_scale: 1000,
        steps: Steps::Count(cycles),
    })
    .unwrap();
    b.wait(Duration::from_secs_f64(
        plan.period_s * f64::from(cycles) + 1.0,
    ))
    .unwrap();
    let cpu = (cpu_now() - t0).as_secs_f64();
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
