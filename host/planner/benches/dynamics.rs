//! Inverse dynamics of one planned step cycle of Drosophibot II (built-in model, table 1
//! parameters, 100 slices, tripod, flat ground): all outputs of every slice, without contact
//! constraints, with friction cones + push-only feet, and across cores.
//!
//! The single-core cases are measured in CPU time of the benchmarking thread
//! (CLOCK_THREAD_CPUTIME_ID), because the machines this runs on are shared and wall time there
//! mostly measures other processes; the rayon case can only be measured in wall time.

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{Criterion, criterion_group, criterion_main};
use nix::time::{ClockId, clock_gettime};
use planner::dynamics::{DynamicsOptions, SliceInput, plan_inputs, solve_cycle};
use planner::model::Model;
use std::hint::black_box;
use std::time::Duration;

/// CPU time consumed by the calling thread.
struct ThreadCpuTime;

fn thread_cpu_now() -> Duration {
    let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("thread CPU clock");
    Duration::new(t.tv_sec() as u64, t.tv_nsec() as u32)
}

static WALL: WallTime = WallTime;

impl Measurement for ThreadCpuTime {
    type Intermediate = Duration;
    type Value = Duration;
    fn start(&self) -> Duration {
        thread_cpu_now()
    }
    fn end(&self, i: Duration) -> Duration {
        thread_cpu_now().saturating_sub(i)
    }
    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, v: &Duration) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        WALL.formatter()
    }
}

fn problem() -> (Model, Vec<SliceInput>) {
    let model = planner::model::builtin("drosophibot2").expect("built-in model");
    let params = planner::gait::StepParams::table1("drosophibot2");
    let plan = planner::plan::plan(&model, &params).expect("plan");
    let inputs = plan_inputs(&plan);
    assert_eq!(inputs.len(), 100);
    assert_eq!(
        (model.bodies.len(), model.actuated_joints().len()),
        (33, 22)
    );
    (model, inputs)
}

fn one_core(c: &mut Criterion<ThreadCpuTime>) {
    let (model, inputs) = problem();
    let cases = [
        (
            "cpu: step cycle 100 slices, no contact constraints",
            DynamicsOptions::default(),
        ),
        (
            "cpu: step cycle 100 slices, friction cones + push-only",
            DynamicsOptions {
                friction_cone: true,
                push_only: true,
                ..Default::default()
            },
        ),
        (
            "cpu: step cycle 100 slices, no contact constraints, Clarabel",
            DynamicsOptions {
                always_clarabel: true,
                ..Default::default()
            },
        ),
    ];
    for (name, opts) in cases {
        c.bench_function(name, |b| {
            b.iter(|| solve_cycle(black_box(&model), black_box(&inputs), &opts).expect("solve"))
        });
    }
}

fn all_cores(c: &mut Criterion) {
    let (model, inputs) = problem();
    for (name, parallel) in [
        ("wall: step cycle 100 slices, one thread", false),
        ("wall: step cycle 100 slices, rayon", true),
    ] {
        let opts = DynamicsOptions {
            parallel,
            ..Default::default()
        };
        c.bench_function(name, |b| {
            b.iter(|| solve_cycle(black_box(&model), black_box(&inputs), &opts).expect("solve"))
        });
    }
}

criterion_group! {
    name = cpu;
    // No HTML plots: plotters is built with `ab_glyph` and no registered font here.
    config = Criterion::default().with_measurement(ThreadCpuTime).without_plots();
    targets = one_core
}
criterion_group! {
    name = wall;
    config = Criterion::default().without_plots();
    targets = all_cores
}
criterion_main!(cpu, wall);
