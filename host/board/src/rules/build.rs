//! Step tables built under the rules: from a plan directory (`dbot table --plan`, `dbot upload
//! --plan`, Python `PlanDir.step_table`), a plan in memory (Python `Plan.step_table`) or an
//! excitation trial (`dbot excite`, Python `dbot.excitation`). Each checks
//! the slot capacity, servo feasibility (unless overridden) and what each servo's P gain can hold
//! before the bytes exist; a table file or bytes from elsewhere is checked by the same rules
//! ([`table_bytes`]). A [`CheckedTable`] is only made here and [`crate::link::Board::upload`] takes
//! nothing else, so every upload has passed them (or carries its override's warning).

use planner::model::Model;
use planner::plan::Plan;
use planner::plan_dir::PlanDir;

use super::error::plan_dir_what;
use super::feasibility::{enforce, of_plan_dir};
use super::slots::{check_slices, table_joints};
use super::stiffness::p_gain;
use super::{Overridden, Overrides, RuleError};

/// Step table bytes that passed the rules, and the warning of an override that let them through.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedTable {
    bytes: Vec<u8>,
    warning: Option<Overridden>,
}

impl CheckedTable {
    /// The table bytes (as `dbot table` writes them).
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    pub fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }

    /// What `Overrides::allow_infeasible` let through, to show before the table is used.
    pub fn warning(&self) -> Option<&Overridden> {
        self.warning.as_ref()
    }
}

/// The step table of the plan directory `plan`, named `name` or else its `table_name()`.
pub fn plan_dir_table(
    plan: &PlanDir,
    name: Option<&str>,
    overrides: Overrides,
) -> Result<CheckedTable, RuleError> {
    check_slices(
        &format!(
            "{}: slices",
            plan.path
                .join(planner::plan_dir::columns::JOINTS_CSV)
                .display()
        ),
        plan.angle.len(),
        table_joints(&plan.model),
    )?;
    let what = plan_dir_what(&plan.path);
    let warning = enforce(&of_plan_dir(plan), &what, overrides)?;
    let bytes = plan.step_table(name)?;
    check_stiffness(&bytes, &plan.model, &what)?;
    Ok(CheckedTable { bytes, warning })
}

/// The step table of `plan`, named `name`, with `torques` (`[slice][model joint]`, N m) as the
/// bias feed-forward or zero torques; the torques are checked against the servos when given.
pub fn plan_table(
    plan: &Plan,
    torques: Option<&[Vec<f64>]>,
    name: &str,
    overrides: Overrides,
) -> Result<CheckedTable, RuleError> {
    check_slices("slices", plan.slices(), table_joints(&plan.model))?;
    let what = format!("plan of {}", plan.model.name);
    let f = planner::plan::feasibility::check(&plan.model, &plan.q, torques, plan.dt);
    let warning = enforce(&f, &what, overrides)?;
    let bytes = planner::plan::table::step_table(plan, torques, name).map_err(|source| {
        RuleError::Table {
            what: what.clone(),
            source,
        }
    })?;
    check_stiffness(&bytes, &plan.model, &what)?;
    Ok(CheckedTable { bytes, warning })
}

/// The step table of an excitation trial (`planner::excitation`, `dbot excite`, Python
/// `dbot.excitation`): the slot capacity, servo feasibility (no override: an excitation is made to
/// be followed) and the P gain's stiffness, as any gait's.
pub fn excitation_table(
    model: &Model,
    trial: &planner::excitation::ExcitationTrial,
) -> Result<CheckedTable, RuleError> {
    let what = format!("excitation {} of {}", trial.name, model.name);
    check_slices(
        &format!("{what}: slices"),
        trial.slices(),
        table_joints(model),
    )?;
    let f = planner::plan::feasibility::check(model, &trial.q, None, trial.dt_s);
    let warning = enforce(&f, &what, Overrides::default())?;
    let bytes = trial.step_table(model).map_err(|source| RuleError::Table {
        what: what.clone(),
        source,
    })?;
    check_stiffness(&bytes, model, &what)?;
    Ok(CheckedTable { bytes, warning })
}

/// The step table `bytes` read from a file or given as bytes (`dbot upload --table FILE`, `dbot
/// run --table`, `dbot record --table`, Python `Board.upload(slot, bytes)`), named `what` in
/// messages, its joints named by `model`: checked as a table built here would be (slot capacity,
/// what the servos can follow at its planned period unless overridden, what each servo's P gain can
/// hold), so a table built with `--allow-infeasible` needs the override again to reach a board.
pub fn table_bytes(
    bytes: Vec<u8>,
    what: &str,
    model: &Model,
    overrides: Overrides,
) -> Result<CheckedTable, RuleError> {
    let table = protocol::GaitTable::parse(&bytes).map_err(|source| RuleError::BadTable {
        what: what.to_owned(),
        source,
    })?;
    check_slices(
        &format!("{what}: slices"),
        table.slice_count(),
        table.joint_count(),
    )?;
    let names = crate::record::joint_names(model, Some(&table), table.joint_count());
    let f = super::period::table_feasibility(&table, &names, 1.0);
    let warning = enforce(&f, what, overrides)?;
    check_stiffness(&bytes, model, what)?;
    Ok(CheckedTable { bytes, warning })
}

/// Refuses a table joint whose stiffness its servo's P gain register cannot hold (the firmware
/// writes the gain from the table's stiffness when the gait plays).
fn check_stiffness(bytes: &[u8], model: &Model, what: &str) -> Result<(), RuleError> {
    let table = protocol::GaitTable::parse(bytes).map_err(|source| RuleError::BadTable {
        what: what.to_owned(),
        source,
    })?;
    let names = crate::record::joint_names(model, Some(&table), table.joint_count());
    for (j, name) in names.into_iter().enumerate() {
        let Some(joint) = table.joint(j) else {
            continue;
        };
        let k = f64::from(joint.stiffness) / protocol::units::STIFFNESS_PER_NM_RAD;
        p_gain(joint.model, k).map_err(|source| RuleError::TableStiffness {
            what: what.to_owned(),
            joint: name,
            source,
        })?;
    }
    Ok(())
}
