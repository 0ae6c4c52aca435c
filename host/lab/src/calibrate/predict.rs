//! The plan's prediction at a standing trial's recorded goals: per bus cycle the static inverse
//! dynamics (`planner::dynamics::solve_slice`, every foot in stance, the QP's share of the load
//! among the feet) at the posture the board commanded, and the strain it predicts at every gauge
//! (`planner::strain::slice_readings`). Gravity is taken normal to the plane of the six feet at
//! that posture (they stand on flat ground), so a tilted thorax sees gravity tilted. Or
//! ([`replayed`]) what the trial's goals replayed on the model's body give
//! (`identify::rollout`): the actuators' torques and the simulated gauges.

use nalgebra::{Matrix3, Vector3};
use planner::dynamics::{DynamicsOptions, SliceInput, solve_slice};
use planner::model::{MjcfOptions, Model};
use planner::terrain::Ground;

use crate::bail;
use crate::error::{Context, Result};
use crate::identify::recording::Recording;

/// Farthest a foot may lie off the plane of the feet in a standing trial's posture, m.
pub const MAX_OFF_PLANE_M: f64 = 0.003;

/// The prediction at some cycles.
#[derive(Debug, Clone, PartialEq)]
pub struct Predicted {
    /// The cycles predicted, in order.
    pub cycles: Vec<usize>,
    /// `torque[k][traced joint]`, N m, joint direction, at `cycles[k]`.
    pub torque: Vec<Vec<f64>>,
    /// `strain[k][model gauge]`, microstrain.
    pub strain: Vec<Vec<f64>>,
}

/// Gravity in the thorax frame at posture `q`, normal to the plane of the feet (pointing away
/// from the thorax), and the largest distance of a foot from that plane.
fn gravity(model: &Model, q: &[f64]) -> (Vector3<f64>, f64) {
    let feet: Vec<Vector3<f64>> = planner::kinematics::forward(model, q)
        .feet
        .iter()
        .map(|p| p.coords)
        .collect();
    let n = feet.len().max(1) as f64;
    let centre = feet.iter().sum::<Vector3<f64>>() / n;
    let mut cov = Matrix3::zeros();
    for p in &feet {
        let d = p - centre;
        cov += d * d.transpose();
    }
    let eig = cov.symmetric_eigen();
    let (k, _) = eig.eigenvalues.argmin();
    let mut normal: Vector3<f64> = eig.eigenvectors.column(k).into();
    // The thorax (its origin) is above the ground: the upward normal points from the feet to it.
    if normal.dot(&-centre) < 0.0 {
        normal = -normal;
    }
    let off = feet
        .iter()
        .map(|p| normal.dot(&(p - centre)).abs())
        .fold(0.0, f64::max);
    (-planner::terrain::G * normal, off)
}

/// The prediction of `model` at `rec`'s goals in `cycles`.
pub fn predict(model: &Model, rec: &Recording, cycles: Vec<usize>) -> Result<Predicted> {
    let stance = MjcfOptions::stance(model, &Ground::Flat)
        .with_context(|| format!("the stance of the model {}", model.name))?
        .stance_q;
    let sites = planner::strain::sites(model)?;
    let options = DynamicsOptions::default();
    let mut out = Predicted {
        cycles: Vec::with_capacity(cycles.len()),
        torque: Vec::with_capacity(cycles.len()),
        strain: Vec::with_capacity(cycles.len()),
    };
    for c in cycles {
        let mut q = stance.clone();
        for jt in &rec.joints {
            q[jt.joint] = jt.goal[c];
        }
        let (g, off) = gravity(model, &q);
        if off > MAX_OFF_PLANE_M {
            bail!(
                "trial {}: at {:.2} s a foot is {:.1} mm off the plane of the feet: calibrate needs a \
                 standing trial, every foot on flat ground (`dbot excite --kind standing`)",
                rec.name,
                rec.t[c] - rec.t[0],
                off * 1e3
            );
        }
        let mut input = SliceInput::still(model, q);
        input.gravity = g;
        input.normals = vec![-g.normalize(); model.feet.len()];
        let sol = solve_slice(model, &input, &options, c)?;
        out.torque
            .push(rec.joints.iter().map(|jt| sol.torque[jt.joint]).collect());
        out.strain.push(
            planner::strain::slice_readings(model, &sites, &input, &sol.grf)
                .iter()
                .map(|r| r.microstrain)
                .collect(),
        );
        out.cycles.push(c);
    }
    Ok(out)
}

/// The replay of `rec`'s goals on `model`'s body (`identify::rollout::replay`, standing on
/// flat ground, settled from the first goals as the robot did) at `cycles`: each traced joint's
/// actuator torque (N m, joint direction) and every gauge's simulated strain. On servos with
/// friction, deadband and backlash how six feet share the weight depends on how the body took it
/// (each servo rests anywhere in its deadband, held by its friction); the replay's settling from
/// the goals is what makes the load calibrate (docs/identification.md, "Against the replay").
pub fn replayed(model: &Model, rec: &Recording, cycles: Vec<usize>) -> Result<Predicted> {
    let out = crate::identify::rollout::replay(model, rec)
        .with_context(|| format!("replaying trial {} on the model {}", rec.name, model.name))?;
    Ok(Predicted {
        torque: cycles
            .iter()
            .map(|&c| out.torque.iter().map(|t| t[c]).collect())
            .collect(),
        strain: cycles
            .iter()
            .map(|&c| out.strain.get(c).cloned().unwrap_or_default())
            .collect(),
        cycles,
    })
}
