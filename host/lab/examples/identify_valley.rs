//! Where the fit of the stand-in stops, against the truth (docs/identification.md, "Why TrF1 and
//! FTi miss"): for each joint of the one-leg run, the cost of its own suspended trial (squared
//! position residuals per tick and velocity residuals per 4 units of 0.229 rev/min, as the fit
//! counts them) replayed on the stand-in's values (the truth), on the fitted values, with one
//! field at a time moved from the truth to its fitted value, and along the straight line from
//! the truth to the fitted values in 20 equal steps: how much the line rises and the largest
//! change between neighbouring points (the cost's unevenness at that scale).
//!
//! Reads the folder `identify_stand_in` and `dbot identify` wrote (stand-in.toml, fitted.toml,
//! the trial folders `sus-<kind>`):
//!
//! ```sh
//! cargo run --release -p lab --example identify_valley -- out/identify-stand-in
//! ```

use lab::identify::fit;
use lab::identify::params::MOTION;
use lab::identify::recording::Recording;
use lab::identify::rollout;
use planner::model::{Model, ServoParams, ServoParamsEntry};

/// The one-leg run's joints; each is moved by the trial `sus-<kind>`.
const JOINTS: [&str; 5] = ["LF_ThC1", "LF_ThC3", "LF_CTr", "LF_TrF1", "LF_FTi"];
/// Points on the line from the truth to the fitted values, after the truth.
const STEPS: usize = 20;

/// The joint's cost of `rec` replayed on `model`.
fn cost(model: &Model, rec: &Recording, j: usize) -> Result<f64, Box<dyn std::error::Error>> {
    let out = rollout::replay(model, rec)?;
    let t = rec
        .joints
        .iter()
        .position(|jt| jt.joint == j)
        .ok_or("the trial does not trace the joint")?;
    Ok(fit::residuals(&out, t, &rec.joints[t])
        .map(|(position, velocity)| position.powi(2) + velocity.powi(2))
        .sum())
}

/// `base` with joint `j`'s motion fields (and the no-load speed) each at `truth`'s value plus
/// `s[i]` of the way to `fitted`'s.
fn between(base: &Model, j: usize, truth: &ServoParams, fitted: &ServoParams, s: &[f64]) -> Model {
    let mut m = base.clone();
    let name = m.joints[j].name.clone();
    let mut e: ServoParamsEntry = m
        .servo_dynamics
        .of_joint(&name)
        .copied()
        .unwrap_or_default();
    for (i, f) in MOTION.iter().enumerate() {
        let (a, b) = ((f.get)(truth), (f.get)(fitted));
        (f.set)(&mut e, a + s[i] * (b - a));
    }
    // The no-load speed follows the stall torque (the fit keeps the torque-speed slope).
    let k = MOTION
        .iter()
        .position(|f| f.name == "stall_torque_nm")
        .expect("the stall torque is fitted");
    let a = truth.no_load_speed_rad_s;
    e.no_load_speed_rad_s = Some(a + s[k] * (fitted.no_load_speed_rad_s - a));
    m.servo_dynamics.set_joint(&name, e);
    m
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/identify-stand-in".into()),
    );
    let truth_model = planner::model::load(&dir.join("stand-in.toml"))?;
    let fitted = planner::model::load(&dir.join("fitted.toml"))?;
    let names: Vec<&str> = MOTION.iter().map(|f| f.name).collect();
    println!(
        "| joint | truth | fitted | {} | line: rise | largest step |",
        names.join(" | ")
    );
    println!("|---|---|---|{}---|---|", "---|".repeat(names.len()));
    for joint in JOINTS {
        let kind = joint.split_once('_').map_or(joint, |(_, k)| k);
        let j = fitted
            .joints
            .iter()
            .position(|x| x.name == joint)
            .ok_or("the joint is not in the fitted model")?;
        let rec = Recording::read(&dir.join(format!("sus-{kind}")), &fitted)?;
        let tp = truth_model.servo_params(j).ok_or("a servo joint")?;
        let fp = fitted.servo_params(j).ok_or("a servo joint")?;
        let at = |s: &[f64]| cost(&between(&fitted, j, &tp, &fp, s), &rec, j);
        let n = MOTION.len();
        let c_truth = at(&vec![0.0; n])?;
        let c_fitted = at(&vec![1.0; n])?;
        let mut alone = Vec::new();
        for i in 0..n {
            let mut s = vec![0.0; n];
            s[i] = 1.0;
            alone.push(format!("{:.1}", at(&s)?));
        }
        let mut line = vec![c_truth];
        for k in 1..=STEPS {
            line.push(at(&vec![k as f64 / STEPS as f64; n])?);
        }
        let step = line
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        println!(
            "| {joint} | {c_truth:.1} | {c_fitted:.1} | {} | {:+.1} | {step:.1} |",
            alone.join(" | "),
            line[STEPS] - line[0],
        );
        eprintln!(
            "{joint}: the line from the truth: {}",
            line.iter()
                .map(|c| format!("{c:.2}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
    }
    Ok(())
}
