//! Inverse kinematics speed: every leg of Drosophibot II (22 actuated joints) over 1000 slices of a
//! tripod step on flat ground, warm-started slice to slice as the planner does.

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Vector3;
use planner::gait::StepParams;
use planner::kinematics::{IkOptions, LegChain, resting_posture};
use planner::model::builtin;
use planner::plan::footpaths;
use planner::terrain::Terrain;
use std::hint::black_box;

fn ik_1000_slices(c: &mut Criterion) {
    let model = builtin("drosophibot2").unwrap();
    let mut p = StepParams::table1("drosophibot2");
    p.slices = 1000;
    let terrain = Terrain::Flat;
    let posture = resting_posture(&model, &terrain, &|l| p.foot_goal(l)).unwrap();
    let paths = footpaths(&p, &terrain, &posture);
    let dt = p.period_s() / p.slices as f64;
    let legs: Vec<(LegChain, Vec<f64>, Vec<Vector3<f64>>)> = paths
        .iter()
        .map(|fp| {
            let chain = LegChain::new(&model, fp.leg).unwrap();
            let rest: Vec<f64> = chain.actuated.iter().map(|&j| posture.q[j]).collect();
            let targets = (0..p.slices).map(|s| fp.at(s as f64 * dt).0).collect();
            (chain, rest, targets)
        })
        .collect();
    assert_eq!(legs.iter().map(|l| l.0.dof()).sum::<usize>(), 22);
    let opts = IkOptions::default();
    c.bench_function("ik_22_joints_1000_slices", |b| {
        b.iter(|| {
            for (chain, rest, targets) in &legs {
                black_box(
                    chain
                        .solve_path(black_box(targets), rest, rest, &opts)
                        .unwrap(),
                );
            }
        })
    });
}

// criterion's own plots need a system font that plotters' ab_glyph backend does not have.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = ik_1000_slices
}
criterion_main!(benches);
