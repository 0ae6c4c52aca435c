//! Inverse dynamics of one planned step cycle of Drosophibot II (built-in model, table 1
//! parameters, 100 slices, tripod, flat ground): all outputs of every slice, without contact
//! constraints, with friction cones + push-only feet, and across cores.

use criterion::{Criterion, criterion_group, criterion_main};
use host::dynamics::{DynamicsOptions, plan_inputs, solve_cycle};
use std::hint::black_box;

fn cycle(c: &mut Criterion) {
    let model = host::model::builtin("drosophibot2").expect("built-in model");
    let params = host::gait::StepParams::table1("drosophibot2");
    let plan = host::plan::plan(&model, &params).expect("plan");
    let inputs = plan_inputs(&plan);
    assert_eq!(inputs.len(), 100);
    let cases = [
        ("step cycle 100 slices, no contact constraints", DynamicsOptions::default()),
        (
            "step cycle 100 slices, friction cones + push-only",
            DynamicsOptions { friction_cone: true, push_only: true, ..Default::default() },
        ),
        (
            "step cycle 100 slices, no contact constraints, Clarabel",
            DynamicsOptions { always_clarabel: true, ..Default::default() },
        ),
        ("step cycle 100 slices, no contact constraints, rayon", DynamicsOptions { parallel: true, ..Default::default() }),
    ];
    for (name, opts) in cases {
        c.bench_function(name, |b| b.iter(|| solve_cycle(black_box(&model), black_box(&inputs), &opts).expect("solve")));
    }
}

criterion_group!(benches, cycle);
criterion_main!(benches);
