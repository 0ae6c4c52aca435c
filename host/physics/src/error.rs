//! Why a physics robot could not be built.

/// Errors of the physics crate; each names the model, scene or joint at fault.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PhysicsError {
    #[error("scene `{scene}` for model {model}: {source}")]
    Scene {
        model: String,
        scene: String,
        #[source]
        source: planner::plan::PlanError,
    },
    /// The source names the scene already.
    #[error("{source}")]
    Substrate {
        scene: String,
        #[source]
        source: board::substrate::SubstrateError,
    },
    #[error("MuJoCo refused the MJCF of model {model}: {message}")]
    Load { model: String, message: String },
    #[error("model {model}: MuJoCo's model has no {kind} named `{name}`")]
    Missing {
        model: String,
        kind: &'static str,
        name: String,
    },
    #[error(
        "model {model}: actuated joint {joint} has no servo (the physics robot needs a servo map)"
    )]
    NoServo { model: String, joint: String },
    #[error(
        "model {model}: a {timestep_ms} ms timestep is unstable: joint {joint}'s actuator (stiffness {kp:.3e} N m/rad on {inertia:.3e} kg m^2) rings at {omega_rad_s:.0} rad/s; at most {stable_ms:.3} ms is stable for this model (omega x timestep <= {limit})"
    )]
    Timestep {
        model: String,
        joint: String,
        timestep_ms: f64,
        kp: f64,
        inertia: f64,
        omega_rad_s: f64,
        stable_ms: f64,
        /// The largest omega x timestep accepted (`MAX_OMEGA_DT` of the timestep rule).
        limit: f64,
    },
    #[error("port `{spec}`: {problem} (expected physics or physics:SCENE)")]
    Port { spec: String, problem: String },
    #[error("{what} is not supported")]
    Unsupported { what: String },
}
