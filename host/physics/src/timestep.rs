//! Which timestep a model's MJCF needs: an actuator's spring on its joint's inertia rings at
//! omega = sqrt(kp / M) (M: the joint's diagonal of the mass matrix in the stance, armature
//! included), and MuJoCo integrates the position term explicitly, so the timestep must keep
//! omega dt under [`MAX_OMEGA_DT`]. [`crate::Plant::new`] refuses a faster one; `dbot model export
//! --mjcf` writes a slower one for a model that needs it (the scale fly).

use mujoco_rs::prelude::*;
use mujoco_rs::wrappers::mj_model::MjtObjBase;
use planner::model::{MjcfOptions, Model, to_mjcf};

use crate::error::PhysicsError;

/// Largest product of an actuator's natural frequency sqrt(kp / M) (M: the joint's diagonal of the
/// mass matrix in the stance, armature included) and the timestep that [`crate::Plant::new`] accepts.
/// MuJoCo integrates the position term explicitly (implicitfast covers only the velocity terms),
/// so a spring on a tiny inertia is unstable past omega dt = 2 (semi-implicit Euler) and rings
/// long before: the scale fly's MJCF at 1 ms (omega dt 2.7) throws its thorax from 1.3 mm to
/// 20 mm within a second, at 0.5 ms (1.4) its joints still swing at 22 rad/s, at 0.1 ms (0.27) it
/// stands still (tests/integration/fly_timestep.rs). Drosophibot II's stiffest joint: 63 rad/s, 0.06 at 1 ms.
pub const MAX_OMEGA_DT: f64 = 0.3;

/// The actuated joint with the highest natural frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Stiffest {
    pub joint: String,
    /// The actuator's stiffness, N m/rad.
    pub kp: f64,
    /// The joint's diagonal of the mass matrix in the stance, kg m^2.
    pub inertia: f64,
    pub omega_rad_s: f64,
}

impl Stiffest {
    /// The largest timestep at which this joint does not ring, s.
    pub fn stable_timestep_s(&self) -> f64 {
        MAX_OMEGA_DT / self.omega_rad_s
    }
}

/// The stiffest actuated joint of `model` as [`to_mjcf`] writes it with `options`, in the
/// options' stance keyframe; `None` for a model without actuators.
pub fn stiffest_joint(
    model: &Model,
    options: &MjcfOptions,
) -> Result<Option<Stiffest>, PhysicsError> {
    let load = |message: String| PhysicsError::Load {
        model: model.name.clone(),
        message,
    };
    let mj = MjModel::from_xml_string(&to_mjcf(model, options)).map_err(|e| load(e.to_string()))?;
    let mut data = MjData::new(Box::new(mj));
    data.reset_keyframe(0)
        .map_err(|e| load(format!("keyframe `stance`: {e}")))?;
    data.forward();
    stiffest(model, &data)
}

fn stiffest(model: &Model, data: &MjData<Box<MjModel>>) -> Result<Option<Stiffest>, PhysicsError> {
    let m = data.model();
    let nv = m.ffi().nv as usize;
    let mut full = vec![0.0; nv * nv];
    data.full_m(&mut full).map_err(|e| PhysicsError::Load {
        model: model.name.clone(),
        message: format!("mass matrix: {e}"),
    })?;
    let mut worst: Option<(usize, f64, f64, f64)> = None;
    for a in 0..m.ffi().nu as usize {
        let jid = m.actuator_trnid()[a][0] as usize;
        let dof = m.jnt_dofadr()[jid] as usize;
        let kp = m.actuator_gainprm()[a][0];
        let inertia = full[dof * nv + dof];
        let omega = (kp / inertia).sqrt();
        if worst.is_none_or(|w| omega > w.1) {
            worst = Some((jid, omega, kp, inertia));
        }
    }
    Ok(worst.map(|(jid, omega_rad_s, kp, inertia)| Stiffest {
        joint: m
            .id_to_name(MjtObjBase::mjOBJ_JOINT, jid)
            .unwrap_or("?")
            .to_owned(),
        kp,
        inertia,
        omega_rad_s,
    }))
}

/// Refuses a timestep at which an actuator's spring on its joint's inertia is unstable or rings
/// ([`MAX_OMEGA_DT`]), naming the stiffest joint and the largest stable timestep.
pub(crate) fn check_timestep(
    model: &Model,
    data: &MjData<Box<MjModel>>,
) -> Result<(), PhysicsError> {
    let dt = data.model().opt().timestep;
    match stiffest(model, data)? {
        Some(s) if s.omega_rad_s * dt > MAX_OMEGA_DT => Err(PhysicsError::Timestep {
            model: model.name.clone(),
            timestep_ms: dt * 1e3,
            stable_ms: s.stable_timestep_s() * 1e3,
            joint: s.joint,
            kp: s.kp,
            inertia: s.inertia,
            omega_rad_s: s.omega_rad_s,
            limit: MAX_OMEGA_DT,
        }),
        _ => Ok(()),
    }
}
