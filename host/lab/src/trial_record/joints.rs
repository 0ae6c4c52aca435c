//! The recorded joints named from the model (`LF_ThC1`, ...), for `dbot record` and
//! `Board.record_trial` alike.

use board::link::{Board, Transport};
use board::record::{JointMeta, joint_names, joints_of_table};
use planner::model::Model;
use protocol::GaitTable;

use crate::error::Result;

/// The board's joints named from `model`: by the table's servo IDs; without a table by the servo
/// IDs the board reports for the slot to be played (or its selected gait), and only when it
/// knows none by its joint-map order (see [`board::record::joint_names`]). Refused when the
/// board reports no joints at all.
pub fn named_joints<T: Transport>(
    board: &mut Board<T>,
    model: &Model,
    table: Option<&GaitTable<'_>>,
    play: Option<u8>,
) -> Result<Vec<JointMeta>> {
    let mut joints = match table {
        Some(t) => joints_of_table(t, &joint_names(model, Some(t), t.joint_count())),
        None if let Some(ids) = board.joint_map(play)? => {
            board::record::joint_names_by_ids(model, &ids.servo_ids)
                .into_iter()
                .map(JointMeta::named)
                .collect()
        }
        None => {
            let count = board.settings()?.joints.len();
            joint_names(model, None, count)
                .into_iter()
                .map(JointMeta::named)
                .collect()
        }
    };
    if joints.is_empty() {
        joints = (0..board.settings()?.joints.len())
            .map(|j| JointMeta::named(format!("J{j}")))
            .collect();
    }
    if joints.is_empty() {
        crate::bail!(
            "{}: the board reports no joints (no gait selected): nothing to record; upload a table and give --play SLOT (Python: play=SLOT)",
            board.port()
        );
    }
    Ok(joints)
}
