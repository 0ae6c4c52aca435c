//! `--spring` and `--spring-equilibrium`: parallel elasticity on a whole model (paper section
//! 3.1.2), shared by `dbot plan` and `dbot compare`, and recorded in plan.json so that
//! `dbot upload --plan` re-plans the same model.

use anyhow::{Context, Result};
use planner::model::{EquilibriumSource, Model, SpringSpec};

/// Where the equilibrium of `--spring` comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Equilibrium {
    /// The joint's angle in the resting posture.
    Rest,
    /// The middle of the joint's range over the planned step (paper section 2.2.1).
    StepMidrange,
    /// A proxy for the paper's newly-dead-fly posture (section 2.2.1; it lists no angles): CTr at
    /// -35 deg, FTi 20 deg below its smallest angle over the step (the original solver's), the
    /// other joints at the middle of their range over the step.
    DeadFly,
}

impl Equilibrium {
    pub fn source(self) -> EquilibriumSource {
        match self {
            Equilibrium::Rest => EquilibriumSource::RestingPosture,
            Equilibrium::StepMidrange => EquilibriumSource::StepMidrange,
            Equilibrium::DeadFly => EquilibriumSource::DeadFly,
        }
    }
    fn name(self) -> &'static str {
        match self {
            Equilibrium::Rest => "rest",
            Equilibrium::StepMidrange => "step-midrange",
            Equilibrium::DeadFly => "dead-fly",
        }
    }
}

/// Parallel elasticity flags.
#[derive(Debug, Clone, clap::Args)]
pub struct SpringArgs {
    /// Parallel spring on every actuated joint, replacing the model's own: `none`, `paper` (the
    /// paper's value for the model: 1 N m/rad for drosophibot2, 3.8e-8 N m/rad for
    /// scale-drosophila), a preset name (`drosophibot2`, `scale-drosophila`) or a stiffness in
    /// N m/rad. Default: the springs in the model file.
    #[arg(long)]
    pub spring: Option<String>,
    /// Equilibrium angle of --spring's springs.
    #[arg(long, value_enum, default_value_t = Equilibrium::Rest)]
    pub spring_equilibrium: Equilibrium,
}

impl SpringArgs {
    /// `model` with the springs these flags ask for.
    pub fn apply(&self, model: Model) -> Result<Model> {
        match &self.spring {
            None => Ok(model),
            Some(spec) => {
                let s = SpringSpec::parse(spec).map_err(|e| anyhow::anyhow!("--spring: {e}"))?;
                s.apply(&model, self.spring_equilibrium.source())
                    .with_context(|| format!("--spring {spec} on model {}", model.name))
            }
        }
    }

    /// The `spring_args` of plan.json (none without --spring).
    pub fn options(&self) -> Option<planner::plan_dir::SpringOptions> {
        self.spring
            .as_ref()
            .map(|spec| planner::plan_dir::SpringOptions {
                spring: spec.clone(),
                spring_equilibrium: self.spring_equilibrium.name().to_string(),
            })
    }
}
