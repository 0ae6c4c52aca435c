//! Prototype of the improvement the step-cycle profile suggested (docs/performance.md): the reduced
//! QP's Hessian P = B^T W B is block diagonal per stance foot, because a foot's force only loads the
//! joints of its own leg. So the equality-constrained QP (min 1/2 x'Px + q'x, A x = b) is solved by
//! Cholesky of the 3x3 blocks and a 6x6 Schur complement on the thorax equilibrium, instead of the
//! Gram eigen-decomposition + null space of `host::qp`. Both are timed on the same 100 slices (thread
//! CPU time) and the answers compared. Usage: `cargo run --release -p host --example bench_schur`.

use std::hint::black_box;

use anyhow::{Context, Result, bail};
use host::dynamics::{DynamicsOptions, plan_inputs, slice_problem};
use host::qp::{self, Backend, QpProblem};
use nalgebra::{DMatrix, DVector, Matrix3};

#[repr(C)]
struct Timespec {
    tv_sec: i64,
    tv_nsec: i64,
}

unsafe extern "C" {
    fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
}

/// CPU time of this thread, s (CLOCK_THREAD_CPUTIME_ID; 64-bit Linux).
fn thread_cpu_s() -> f64 {
    let mut t = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec (two 64-bit fields on 64-bit Linux) to `t`.
    let rc = unsafe { clock_gettime(3, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

fn per_call(reps: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<f64> = (0..5)
        .map(|_| {
            let s = thread_cpu_s();
            for _ in 0..reps {
                f();
            }
            (thread_cpu_s() - s) / reps as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[2]
}

/// Block-diagonal Schur solve; `None` if P is not block diagonal or a block is not positive definite.
fn schur(p: &QpProblem) -> Option<DVector<f64>> {
    let n = p.q.len();
    let blocks = n / 3;
    for i in 0..n {
        for j in 0..n {
            if i / 3 != j / 3 && p.p[(i, j)] != 0.0 {
                return None;
            }
        }
    }
    let m = p.a.nrows();
    // Y = P^-1 [A^T | q] block by block.
    let mut y = DMatrix::zeros(n, m + 1);
    for k in 0..blocks {
        let pk: Matrix3<f64> = p.p.fixed_view::<3, 3>(3 * k, 3 * k).into_owned();
        let ch = pk.cholesky()?;
        for c in 0..m {
            let col = ch.solve(&p.a.fixed_view::<1, 3>(c, 3 * k).transpose());
            y.fixed_view_mut::<3, 1>(3 * k, c).copy_from(&col);
        }
        let col = ch.solve(&p.q.fixed_rows::<3>(3 * k).into_owned());
        y.fixed_view_mut::<3, 1>(3 * k, m).copy_from(&col);
    }
    let ay = &p.a * &y; // m x (m + 1): [A P^-1 A^T | A P^-1 q]
    let s = ay.columns(0, m).into_owned();
    let rhs = -(&p.b + ay.column(m));
    let lambda = s.cholesky()?.solve(&rhs);
    // x = -P^-1 (q + A^T lambda)
    Some(-(y.columns(0, m) * lambda + y.column(m)))
}

fn main() -> Result<()> {
    let model = host::model::builtin("drosophibot2")?;
    let params = host::gait::StepParams::table1("drosophibot2");
    let plan = host::plan::plan(&model, &params)?;
    let inputs = plan_inputs(&plan);
    let opts = DynamicsOptions::default();
    let (mut t_build, mut t_ours, mut t_schur, mut worst) = (0.0, 0.0, 0.0, 0.0f64);
    for (i, input) in inputs.iter().enumerate() {
        let prob = slice_problem(&model, input, &opts, i)?;
        let p = &prob.qp;
        if p.cones.len() != 1 {
            bail!("slice {i}: expected equalities only");
        }
        let x_ref = qp::solve(p, Backend::Auto)?.x;
        let x = schur(p).with_context(|| format!("slice {i}: P not block diagonal / not PD"))?;
        let f = |x: &DVector<f64>| 0.5 * x.dot(&(&p.p * x)) + p.q.dot(x) + prob.cost_constant;
        worst = worst.max((f(&x) - f(&x_ref)).abs() / f(&x_ref).abs());
        worst = worst.max((&x - &x_ref).amax() / x_ref.amax());
        t_build += per_call(50, || {
            black_box(slice_problem(&model, black_box(input), &opts, i).unwrap());
        });
        t_ours += per_call(50, || {
            black_box(qp::solve(black_box(p), Backend::Auto).unwrap());
        });
        t_schur += per_call(50, || {
            black_box(schur(black_box(p)).unwrap());
        });
    }
    let n = inputs.len() as f64;
    println!(
        "{} slices: build {:.2} us/slice; QP solve host::qp {:.2} us/slice, block Schur {:.2} us/slice \
         ({:.1}x); worst relative difference (objective, x) {:.1e}",
        inputs.len(),
        t_build / n * 1e6,
        t_ours / n * 1e6,
        t_schur / n * 1e6,
        t_ours / t_schur,
        worst
    );
    Ok(())
}
