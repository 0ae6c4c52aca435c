//! The refusals of a trial request that need no board: in the CLI they come before any port is
//! opened, and [`super::record_trial`] makes them again before anything moves.

use std::path::Path;

use board::platform::Perturb;
use board::trial::PlanMeta;
use protocol::GaitTable;

use super::{TrialRequest, library, platform_id};
use crate::error::{Context, Result};

/// A request that passed [`TrialRequest::check`]: its table parsed, its plan's metadata read,
/// its perturbation parsed.
#[derive(Debug)]
pub struct Checked<'a> {
    pub table: Option<GaitTable<'a>>,
    pub plan: Option<PlanMeta>,
    pub perturb: Option<Perturb>,
}

impl TrialRequest {
    /// Refuses, in the CLI's words: seconds that are not a positive number, a table that is not
    /// a step table, a plan directory that cannot be read, a perturbation whose leg is not a leg
    /// or whose step is beyond the steps played, a substrate that is not known (or that
    /// disagrees with the physics scene of `servo_port`), a strain port that is the servos'.
    pub fn check(&self, servo_port: Option<&str>) -> Result<Checked<'_>> {
        if let Some(s) = self.seconds
            && !(s.is_finite() && s > 0.0)
        {
            crate::bail!("seconds {s}: must be a positive number of seconds");
        }
        let table = match &self.table {
            Some(t) => Some(
                GaitTable::parse(&t.bytes)
                    .with_context(|| format!("table {} is not a step table", t.path.display()))?,
            ),
            None => None,
        };
        let plan = self.plan_meta()?;
        let perturb = match &self.perturb {
            Some(spec) => Some(
                Perturb::parse(spec, platform_id(self))
                    .and_then(|p| p.check_steps(self.play.and_then(|p| p.steps)).map(|()| p))
                    .with_context(|| format!("perturb {spec}"))?,
            ),
            None => None,
        };
        match servo_port {
            Some(port) => board::port::trial_substrate(port, self.substrate.as_deref())
                .map(drop)
                .map_err(library)?,
            None => {
                if let Some(name) = &self.substrate {
                    board::substrate::Substrate::parse(name, "substrate").map_err(library)?;
                }
            }
        }
        if let (Some(strain), Some(servo)) = (&self.strain, servo_port) {
            board::strain::port::check_not_servo_port(strain, servo)
                .with_context(|| format!("strain board {strain}"))?;
        }
        Ok(Checked {
            table,
            plan,
            perturb,
        })
    }

    /// The plan directory's metadata: `plan`, or the table's folder when it is a plan directory.
    fn plan_meta(&self) -> Result<Option<PlanMeta>> {
        let dir = match (&self.plan, &self.table) {
            (Some(d), _) => Some(d.clone()),
            (None, Some(t)) => t
                .path
                .parent()
                .filter(|d| d.join("plan.json").is_file())
                .map(Path::to_owned),
            (None, None) => None,
        };
        dir.map(|d| PlanMeta::read(&d).map_err(library)).transpose()
    }
}
