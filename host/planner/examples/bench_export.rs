//! Bench driver for `bench/run.sh`: plans the Drosophibot II step cycle (table 1, 100 slices,
//! flat ground), times our inverse dynamics, one leg's recursive dynamics and the IK, and exports
//! the same inputs for the Python peers: the URDFs, every slice's state, our answers, and the
//! paper's full per-body equation system (6 rows per body, 6 unknowns per joint + 3 per foot).
//!
//! Usage: `cargo run --release -p planner --example bench_export -- OUT_DIR [--scaling] [--profile N] [--quick]`
//! (`--profile N`: only solve the step cycle N times, for callgrind / perf; nothing written).

use std::hint::black_box;
use std::path::PathBuf;

use anyhow::{Context, Result};
use nalgebra::{Matrix3, Vector3};
use planner::dynamics::motion::body_motions;
use planner::dynamics::wrench::{backward_pass, required_wrenches};
use planner::dynamics::{
    Base, DynamicsOptions, SliceInput, ThoraxMotion, plan_inputs, solve_cycle, solve_slice,
};
use planner::kinematics::{IkOptions, LegChain};
use planner::model::{Actuation, Leg, Model, to_urdf};
use serde_json::{Value, json};

#[repr(C)]
struct Timespec {
    tv_sec: i64,
    tv_nsec: i64,
}

unsafe extern "C" {
    fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
}

/// CPU time of this thread, s (CLOCK_THREAD_CPUTIME_ID, the clock Python's `time.thread_time`
/// reads), so that other load on a shared machine does not count. Linux x86_64 / aarch64.
fn thread_cpu_s() -> f64 {
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut t = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec (two 64-bit fields on 64-bit Linux) to `t`.
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// `--quick` (bench/run.sh --quick, in the test command): one round of one call per timing, so
/// the whole export runs in a debug build in seconds; its times are not figures.
static QUICK: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Median thread CPU seconds per call of `f`, over `rounds` rounds of `reps` calls each.
fn time_per_call(rounds: usize, reps: usize, mut f: impl FnMut()) -> f64 {
    let (rounds, reps) = if QUICK.load(std::sync::atomic::Ordering::Relaxed) {
        (1, 1)
    } else {
        (rounds, reps)
    };
    f();
    let mut t: Vec<f64> = (0..rounds)
        .map(|_| {
            let s = thread_cpu_s();
            for _ in 0..reps {
                f();
            }
            (thread_cpu_s() - s) / reps as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn v3(v: &Vector3<f64>) -> Value {
    json!([v.x, v.y, v.z])
}

/// The paper's full system of one slice as sparse triplets (row, col, value), right side, and
/// the cost terms. Unknowns: per joint j, force (6j..6j+3) and moment about the joint origin
/// (6j+3..6j+6) that the parent exerts on the child; per foot f, its GRF at 6 n_j + 3 f.
/// Rows: per body b, force balance (6b..6b+3) and moment balance about the body origin
/// (6b+3..6b+6); then 3 rows GRF = 0 per swing foot.
fn full_system(model: &Model, input: &SliceInput) -> Value {
    let motions = body_motions(model, input);
    let required = required_wrenches(model, &motions, &input.gravity);
    let nj = model.joints.len();
    let mut trip: Vec<(usize, usize, f64)> = Vec::new();
    let put3 = |r: usize, c: usize, m: &Matrix3<f64>, t: &mut Vec<(usize, usize, f64)>| {
        for i in 0..3 {
            for k in 0..3 {
                if m[(i, k)] != 0.0 {
                    t.push((r + i, c + k, m[(i, k)]));
                }
            }
        }
    };
    let id = Matrix3::identity();
    for (j, joint) in model.joints.iter().enumerate() {
        let (c, p) = (joint.child, joint.parent);
        put3(6 * c, 6 * j, &id, &mut trip);
        put3(6 * c + 3, 6 * j + 3, &id, &mut trip);
        put3(6 * p, 6 * j, &-id, &mut trip);
        put3(6 * p + 3, 6 * j + 3, &-id, &mut trip);
        let lever = motions[c].origin - motions[p].origin;
        put3(6 * p + 3, 6 * j, &-lever.cross_matrix(), &mut trip);
    }
    let mut rows = 6 * model.bodies.len();
    for (f, foot) in model.feet.iter().enumerate() {
        let m = &motions[foot.body];
        let col = 6 * nj + 3 * f;
        put3(6 * foot.body, col, &id, &mut trip);
        put3(
            6 * foot.body + 3,
            col,
            &(m.rotation * foot.point).cross_matrix(),
            &mut trip,
        );
        if !input.stance[f] {
            put3(rows, col, &id, &mut trip);
            rows += 3;
        }
    }
    let mut rhs = vec![0.0; rows];
    for (b, (m, w)) in motions.iter().zip(&required).enumerate() {
        let moment = w.1 + (m.com - m.origin).cross(&w.0);
        for i in 0..3 {
            rhs[6 * b + i] = w.0[i];
            rhs[6 * b + 3 + i] = moment[i];
        }
    }
    let cost: Vec<Value> = model
        .joints
        .iter()
        .enumerate()
        .filter_map(|(j, joint)| match &joint.actuation {
            Actuation::Actuated { stiffness, .. } => {
                let spring = joint
                    .spring
                    .map_or(0.0, |s| -s.stiffness * (input.q[j] - s.equilibrium));
                let k = stiffness + joint.spring.map_or(0.0, |s| s.stiffness);
                Some(
                    json!({"col": 6 * j + 3, "axis": v3(&motions[joint.child].axis),
                            "spring": spring, "k": k}),
                )
            }
            Actuation::Fixed { .. } => None,
        })
        .collect();
    json!({
        "rows": rows, "cols": 6 * nj + 3 * model.feet.len(),
        "triplets": trip.iter().map(|t| json!([t.0, t.1, t.2])).collect::<Vec<_>>(),
        "rhs": rhs, "cost": cost,
    })
}

/// The thorax and one leg (bodies re-indexed), for the single-leg recursive dynamics.
fn one_leg(model: &Model, leg: Leg) -> Model {
    let chain = model.leg_chain(leg);
    let mut bodies = vec![model.bodies[0].clone()];
    let mut joints = Vec::new();
    let mut map = vec![usize::MAX; model.bodies.len()];
    map[0] = 0;
    for &j in &chain {
        let mut joint = model.joints[j].clone();
        bodies.push(model.bodies[joint.child].clone());
        map[joint.child] = bodies.len() - 1;
        joint.parent = map[joint.parent];
        joint.child = bodies.len() - 1;
        joints.push(joint);
    }
    let mut foot = model.foot(leg).expect("leg has a foot").clone();
    foot.body = map[foot.body];
    Model::of_parts(
        format!("{}_{}", model.name, leg.name()),
        bodies,
        joints,
        vec![foot],
    )
}

/// Our recursive Newton-Euler of a fixed-base model: axis moment of every joint.
fn rnea(model: &Model, input: &SliceInput) -> Vec<f64> {
    let motions = body_motions(model, input);
    let req = required_wrenches(model, &motions, &input.gravity);
    let zero = vec![Vector3::zeros(); model.feet.len()];
    let w = backward_pass(model, &motions, &req, &zero);
    model
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| motions[joint.child].axis.dot(&w.moment[j]))
        .collect()
}

fn ik_cycle(model: &Model, plan: &planner::plan::Plan) -> Vec<Vec<Vec<f64>>> {
    let opts = IkOptions::default();
    plan.legs
        .iter()
        .enumerate()
        .map(|(li, leg)| {
            let chain = LegChain::new(model, *leg).expect("chain");
            let rest: Vec<f64> = chain.actuated.iter().map(|&j| plan.posture.q[j]).collect();
            let targets: Vec<Vector3<f64>> = plan.feet.iter().map(|f| f[li]).collect();
            chain.solve_path(&targets, &rest, &rest, &opts).expect("ik")
        })
        .collect()
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(
        args.next()
            .context("usage: bench_export OUT_DIR [--scaling]")?,
    );
    let rest: Vec<String> = args.collect();
    let scaling = rest.iter().any(|a| a == "--scaling");
    QUICK.store(
        rest.iter().any(|a| a == "--quick"),
        std::sync::atomic::Ordering::Relaxed,
    );
    let model = planner::model::builtin("drosophibot2")?;
    let params = planner::gait::StepParams::table1("drosophibot2");
    let plan = planner::plan::plan(&model, &params)?;
    let inputs = plan_inputs(&plan);
    let opts = DynamicsOptions::default();
    if let Some(n) = rest
        .iter()
        .position(|a| a == "--profile")
        .and_then(|i| rest.get(i + 1)?.parse::<usize>().ok())
    {
        // Only the step cycle, n times: for callgrind / perf.
        for _ in 0..n {
            black_box(plan_inputs(black_box(&plan)));
            black_box(solve_cycle(&model, black_box(&inputs), &opts)?);
        }
        return Ok(());
    }
    std::fs::create_dir_all(&out)?;
    let cycle = solve_cycle(&model, &inputs, &opts)?;

    // Our timings (single thread).
    let t_cycle = time_per_call(15, 3, || {
        black_box(solve_cycle(&model, black_box(&inputs), &opts).unwrap());
    });
    let t_slices: Vec<f64> = inputs
        .iter()
        .enumerate()
        .map(|(i, inp)| {
            time_per_call(5, 50, || {
                black_box(solve_slice(&model, black_box(inp), &opts, i).unwrap());
            })
        })
        .collect();
    let clarabel_opts = DynamicsOptions {
        always_clarabel: true,
        ..Default::default()
    };
    let t_cycle_clarabel = time_per_call(7, 1, || {
        black_box(solve_cycle(&model, black_box(&inputs), &clarabel_opts).unwrap());
    });
    let cone_opts = DynamicsOptions {
        friction_cone: true,
        push_only: true,
        ..Default::default()
    };
    let t_cycle_cone = time_per_call(7, 1, || {
        black_box(solve_cycle(&model, black_box(&inputs), &cone_opts).unwrap());
    });
    let t_plan = time_per_call(7, 1, || {
        black_box(planner::plan::plan(&model, &params).unwrap());
    });
    let ik = ik_cycle(&model, &plan);
    let t_ik = time_per_call(7, 1, || {
        black_box(ik_cycle(&model, black_box(&plan)));
    });

    // One leg (right middle) on a fixed thorax, at slice 0 of the plan, standard gravity.
    let mut legs_out = Vec::new();
    for leg in [Leg::RM, Leg::RF] {
        let sub = one_leg(&model, leg);
        let chain = model.leg_chain(leg);
        let pick = |v: &[f64]| chain.iter().map(|&j| v[j]).collect::<Vec<_>>();
        // The leg alone at slice `s`: its joints' state, in swing, the thorax fixed.
        let leg_input = |s: usize| SliceInput {
            q: pick(&inputs[s].q),
            qd: pick(&inputs[s].qd),
            qdd: pick(&inputs[s].qdd),
            stance: vec![false],
            thorax: ThoraxMotion::default(),
            gravity: inputs[s].gravity,
            normals: vec![Vector3::z()],
        };
        let mut cases = Vec::new();
        for s in [0, 37, 71] {
            let input = leg_input(s);
            let tau = rnea(&sub, &input);
            cases.push(
                json!({"slice": s, "q": input.q, "qd": input.qd, "qdd": input.qdd,
                "gravity": v3(&input.gravity), "tau": tau}),
            );
        }
        let input0 = leg_input(0);
        let t = time_per_call(21, 20_000, || {
            black_box(rnea(&sub, black_box(&input0)));
        });
        let urdf = format!("leg_{}.urdf", leg.name());
        std::fs::write(out.join(&urdf), to_urdf(&sub))?;
        legs_out.push(json!({"leg": leg.name(), "urdf": urdf,
            "joints": sub.joints.iter().map(|j| json!({"name": j.name,
                "actuated": matches!(j.actuation, Actuation::Actuated{..})})).collect::<Vec<_>>(),
            "cases": cases, "time_s": t}));
    }

    std::fs::write(out.join("model.urdf"), to_urdf(&model))?;
    let slices: Vec<Value> = inputs
        .iter()
        .zip(&cycle.slices)
        .enumerate()
        .map(|(s, (inp, sol))| {
            json!({
                "q": inp.q, "qd": inp.qd, "qdd": inp.qdd, "stance": inp.stance,
                "gravity": v3(&inp.gravity),
                "thorax": {"v": v3(&inp.thorax.linear_velocity), "w": v3(&inp.thorax.angular_velocity),
                           "a": v3(&inp.thorax.linear_acceleration), "alpha": v3(&inp.thorax.angular_acceleration)},
                "ours": {"v_star": sol.v_star, "torque": sol.torque, "axis_moment": sol.axis_moment,
                         "spring": sol.spring_torque, "grf": sol.grf.iter().map(v3).collect::<Vec<_>>(),
                         "time_s": t_slices[s]},
                "full": full_system(&model, inp),
                "feet_targets": plan.feet[s].iter().map(v3).collect::<Vec<_>>(),
            })
        })
        .collect();
    let joints: Vec<Value> = model
        .joints
        .iter()
        .map(|j| {
            let (act, k) = match &j.actuation {
                Actuation::Actuated { stiffness, .. } => {
                    (true, stiffness + j.spring.map_or(0.0, |s| s.stiffness))
                }
                Actuation::Fixed { .. } => (false, 0.0),
            };
            json!({"name": j.name, "leg": j.leg.name(), "actuated": act, "k": k,
                   "limits": [j.limits.0, j.limits.1]})
        })
        .collect();
    let ik_json: Vec<Value> = plan
        .legs
        .iter()
        .enumerate()
        .map(|(li, leg)| {
            let chain = LegChain::new(&model, *leg).expect("chain");
            json!({"leg": leg.name(), "joints": chain.actuated.iter().map(|&j| &model.joints[j].name).collect::<Vec<_>>(),
                   "rest": chain.actuated.iter().map(|&j| plan.posture.q[j]).collect::<Vec<_>>(),
                   "length": chain.length, "q": ik[li]})
        })
        .collect();
    let mut doc = json!({
        "model": model.name, "n_bodies": model.bodies.len(), "n_joints": model.joints.len(),
        "feet": model.feet.iter().map(|f| f.leg.name()).collect::<Vec<_>>(),
        "plan_legs": plan.legs.iter().map(|l| l.name()).collect::<Vec<_>>(),
        "joints": joints, "slices": slices, "legs": legs_out, "ik": ik_json,
        "ours": {"cycle_s": t_cycle, "cycle_clarabel_s": t_cycle_clarabel,
                 "cycle_cone_s": t_cycle_cone, "plan_s": t_plan, "ik_cycle_s": t_ik,
                 "slice_median_s": median(&t_slices)},
    });
    if scaling {
        doc["scaling"] = scaling_study(&model, &params)?;
    }
    std::fs::write(out.join("export.json"), serde_json::to_string(&doc)?)?;
    eprintln!("wrote {}", out.join("export.json").display());
    Ok(())
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// How the cost of planning + dynamics grows with slices per step, legs and steps.
fn scaling_study(model: &Model, params: &planner::gait::StepParams) -> Result<Value> {
    let opts = DynamicsOptions::default();
    let mut per_slices = Vec::new();
    for n in [50, 100, 200, 400] {
        let p = planner::gait::StepParams {
            slices: n,
            ..params.clone()
        };
        let plan = planner::plan::plan(model, &p)?;
        let inputs = plan_inputs(&plan);
        let t_plan = time_per_call(5, 1, || {
            black_box(planner::plan::plan(model, &p).unwrap());
        });
        let t_dyn = time_per_call(5, 1, || {
            black_box(solve_cycle(model, &inputs, &opts).unwrap());
        });
        per_slices.push(json!({"slices": n, "plan_s": t_plan, "dynamics_s": t_dyn}));
    }
    // Legs: the thorax with the first k legs, bolted to a stand (with fewer than three legs a
    // floating thorax cannot be balanced), all feet in stance, slice 0 of the plan.
    let plan = planner::plan::plan(model, params)?;
    let inputs = plan_inputs(&plan);
    let fixed = DynamicsOptions {
        base: Base::Fixed,
        ..Default::default()
    };
    let mut per_legs = Vec::new();
    for k in 1..=6 {
        let legs: Vec<Leg> = model.legs().into_iter().take(k).collect();
        let mut bodies = vec![model.bodies[0].clone()];
        let mut joints = Vec::new();
        let mut feet = Vec::new();
        let mut q = Vec::new();
        for leg in &legs {
            let sub = one_leg(model, *leg);
            let off = bodies.len() - 1;
            bodies.extend(sub.bodies.into_iter().skip(1));
            for mut j in sub.joints {
                j.parent = if j.parent == 0 { 0 } else { j.parent + off };
                j.child += off;
                joints.push(j);
            }
            let mut f = sub.feet[0].clone();
            f.body += off;
            feet.push(f);
            q.extend(model.leg_chain(*leg).iter().map(|&j| inputs[0].q[j]));
        }
        let m = Model::of_parts(format!("{k} legs"), bodies, joints, feet);
        let input = SliceInput::still(&m, q);
        let t = time_per_call(7, 200, || {
            black_box(solve_slice(&m, black_box(&input), &fixed, 0).unwrap());
        });
        per_legs.push(json!({"legs": k, "joints": m.joints.len(), "slice_s": t}));
    }
    let mut per_steps = Vec::new();
    for steps in [1, 2, 4, 8] {
        let many: Vec<SliceInput> = (0..steps).flat_map(|_| inputs.iter().cloned()).collect();
        let t = time_per_call(3, 1, || {
            black_box(solve_cycle(model, &many, &opts).unwrap());
        });
        per_steps.push(json!({"steps": steps, "slices": many.len(), "dynamics_s": t}));
    }
    Ok(json!({"slices_per_step": per_slices, "legs": per_legs, "steps": per_steps}))
}
