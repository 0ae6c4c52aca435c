//! Bounded work: how many slices a step may have. A step table must fit one gait slot of the
//! board (the gait store's bank, less its record header), so planning and building refuse more
//! slices than that before any work: `plan --slices 10000000` used to grow to the machine's whole
//! memory with no output, and `table` accepted 10 000 slices that no slot can hold (issue #19).

use crate::robot::{FLASH_SECTORS, SLOTS, VirtualFlash};

use super::RuleError;

/// Bytes of the largest table one slot of the board holds: asked of the firmware's own gait
/// store, mounted on an erased flash of the board's gait-store size.
pub fn slot_capacity_bytes() -> usize {
    firmware::store::GaitStore::mount(VirtualFlash::new(FLASH_SECTORS), SLOTS).max_table_len()
        as usize
}

/// Most slices per step a table of `joints` joints may have to fit a slot.
pub fn max_slices(joints: usize) -> usize {
    let fixed = protocol::gait::table_len(joints, 0);
    slot_capacity_bytes().saturating_sub(fixed) / protocol::gait::slice_len(joints)
}

/// Joints a step table of `model` carries: the actuated ones (22 on Drosophibot II).
pub fn table_joints(model: &planner::model::Model) -> usize {
    model
        .joints
        .iter()
        .filter(|j| matches!(j.actuation, planner::model::Actuation::Actuated { .. }))
        .count()
}

/// Refuses `slices` beyond [`max_slices`], naming `what` (a flag or a file) and the limit.
pub fn check_slices(what: &str, slices: usize, joints: usize) -> Result<(), RuleError> {
    let max = max_slices(joints);
    if slices > max {
        return Err(RuleError::TooManySlices {
            what: what.to_owned(),
            slices,
            max,
            capacity: slot_capacity_bytes(),
            joints,
            per_slice: protocol::gait::slice_len(joints),
        });
    }
    Ok(())
}
