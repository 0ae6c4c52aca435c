//! Uploading under the rules: a [`CheckedTable`] (which only [`super::build`] makes), or a plan
//! directory built into one first, as `dbot upload --plan` and Python `Board.upload_plan` do.

use planner::plan_dir::PlanDir;

use super::build::{CheckedTable, plan_dir_table};
use super::{Overrides, RuleError};
use crate::link::{Board, Transport, UploadReport, Uploaded};

/// Uploads `table` into `slot` ([`Board::upload_unless`]: progress after every chunk, given up
/// before the next chunk once `interrupted()`).
pub fn upload_checked<T: Transport>(
    board: &mut Board<T>,
    slot: u8,
    table: &CheckedTable,
    progress: impl FnMut(u32, u32),
    interrupted: impl FnMut() -> bool,
) -> Uploaded {
    board.upload_unless(slot, table, progress, interrupted)
}

/// Builds the step table of `plan` under the rules ([`plan_dir_table`]) and uploads it into
/// `slot`; returns the table (with its override warning) and what the upload did.
pub fn upload_plan_dir<T: Transport>(
    board: &mut Board<T>,
    slot: u8,
    plan: &PlanDir,
    name: Option<&str>,
    overrides: Overrides,
    progress: impl FnMut(u32, u32),
    interrupted: impl FnMut() -> bool,
) -> Result<(CheckedTable, UploadReport), RuleError> {
    let table = plan_dir_table(plan, name, overrides)?;
    let report = upload_checked(board, slot, &table, progress, interrupted)?;
    Ok((table, report))
}
