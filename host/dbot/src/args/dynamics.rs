//! The inverse-dynamics flags of `dbot plan` (and the demo's fixed choice of them); what the
//! solved dynamics adds to the outputs is `lab::plan_dir_write`.

use anyhow::Result;
use planner::dynamics::DynamicsOptions;
use planner::plan::Plan;

use lab::plan_dir_write::PlanDynamics;

/// Inverse dynamics options (section 2.2.2 of the paper, solved as a QP per slice).
#[derive(Debug, Clone, clap::Args)]
pub struct DynamicsArgs {
    /// Skip the inverse dynamics (kinematics only).
    #[arg(long)]
    pub no_dynamics: bool,
    /// Keep each stance foot's GRF inside a friction cone |F_t| <= mu F_n (implies push-only).
    #[arg(long)]
    pub friction_cone: bool,
    /// Stance feet only push on the ground (F_n >= 0).
    #[arg(long)]
    pub push_only: bool,
    /// Friction coefficient for --friction-cone and the slip report (an assumed value).
    #[arg(long, default_value_t = 0.5)]
    pub mu: f64,
    /// Keep actuator torques within MX-28 2.5 N m and MX-64 6.0 N m.
    #[arg(long)]
    pub torque_limits: bool,
    /// Solve the slices on all cores.
    #[arg(long)]
    pub parallel: bool,
}

impl DynamicsArgs {
    /// The choice of the physics walks (`demo`, `paper-robot`): `dbot plan`'s defaults, the
    /// dynamics solved, the walks' mu for the slip report (`lab::walk::walk_dynamics`).
    pub const WALK: Self = Self {
        no_dynamics: false,
        friction_cone: false,
        push_only: false,
        mu: lab::walk::WALK_MU,
        torque_limits: false,
        parallel: false,
    };

    pub fn options(&self) -> DynamicsOptions {
        DynamicsOptions {
            friction_cone: self.friction_cone,
            push_only: self.push_only,
            mu: self.mu,
            enforce_torque_limits: self.torque_limits,
            parallel: self.parallel,
            ..DynamicsOptions::default()
        }
    }

    /// Solve the plan's inverse dynamics unless --no-dynamics.
    pub fn solve(&self, plan: &Plan) -> Result<Option<PlanDynamics>> {
        if self.no_dynamics {
            return Ok(None);
        }
        // mu: a friction coefficient (estimate of the physical range: no real contact exceeds 10).
        if !(self.mu.is_finite() && self.mu > 0.0 && self.mu <= 10.0) {
            anyhow::bail!(
                "--mu {}: must be a friction coefficient in (0, 10]",
                self.mu
            );
        }
        Ok(Some(PlanDynamics::solve(plan, self.options())?))
    }
}
