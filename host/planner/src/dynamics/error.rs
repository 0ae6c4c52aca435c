//! Errors of the inverse dynamics, each naming the slice (and joint or foot) it concerns.

/// Why a slice has no inverse-dynamics solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    #[error("slice {slice}: `{field}` has {got} entries, the model has {expected}")]
    InputLength {
        slice: usize,
        field: &'static str,
        expected: usize,
        got: usize,
    },
    #[error("slice {slice}: `{field}` is not finite")]
    NotFinite { slice: usize, field: String },
    #[error("slice {slice}: contact normal of foot {leg} has zero length")]
    ZeroNormal { slice: usize, leg: String },
    #[error(
        "joint {joint}: joint stiffness {stiffness} N m/rad (actuator + parallel spring) must be positive"
    )]
    Stiffness { joint: String, stiffness: f64 },
    #[error(
        "model: joint {joint} has parent body {parent} which is not the thorax or an earlier joint's child"
    )]
    JointOrder { joint: String, parent: usize },
    #[error("model: foot {leg} is on body {body}, the model has {bodies} bodies")]
    FootBody {
        leg: String,
        body: usize,
        bodies: usize,
    },
    #[error(
        "slice {slice}: the stance feet [{stance}] cannot hold the body in the required motion \
         (equilibrium residual {residual:.3e}, relative to the load)"
    )]
    Unbalanced {
        slice: usize,
        stance: String,
        residual: f64,
    },
    #[error(
        "slice {slice}: the load sharing between stance feet [{stance}] is not unique \
         (a stance leg is in a singular pose or has too few actuated joints; condition {condition:.3e})"
    )]
    NotUnique {
        slice: usize,
        stance: String,
        condition: f64,
    },
    #[error("slice {slice}: QP solver failed: {reason}")]
    Solver { slice: usize, reason: String },
    #[error(
        "slices {slices}: no load sharing meets the {constraints}: without them {need}. \
         To make it feasible: {advice}"
    )]
    Infeasible {
        /// e.g. `10-14, 60-65`.
        slices: String,
        constraints: String,
        /// What the unconstrained optimum asks of the feet and joints.
        need: String,
        advice: String,
    },
}
