//! The names of a recording's joints: `LF_ThC1` and so on, wherever the robot's model can say
//! which joint a servo drives; `J<n>` only when nothing can.

use protocol::GaitTable;

use planner::model::Model;
use planner::plan::table::servo_joints;

/// Names of the board's `count` joints (its joint-map order). With the step table being played,
/// each table joint is the model joint whose servo has the table joint's servo ID. Without a table,
/// the board's joint map is the model's servo joints in model order (as every table `dbot` builds
/// lays them out), so those names are used when the counts agree. Any joint left is `J<n>`.
pub fn joint_names(model: &Model, table: Option<&GaitTable<'_>>, count: usize) -> Vec<String> {
    let by_order = servo_joints(model);
    (0..count)
        .map(|j| {
            let by_id = table.and_then(|t| t.joint(j)).and_then(|m| {
                model
                    .joints
                    .iter()
                    .find(|mj| mj.servo.is_some_and(|s| s.id == m.servo_id))
            });
            match (by_id, table) {
                (Some(mj), _) => mj.name.clone(),
                (None, None) if by_order.len() == count => model.joints[by_order[j]].name.clone(),
                (None, _) => format!("J{j}"),
            }
        })
        .collect()
}

/// Names of joints driven by the servos `ids` (the board's joint map, `GetJointMap`): each the
/// model joint whose servo has that ID, `J<n>` where the model has none.
pub fn joint_names_by_ids(model: &Model, ids: &[u8]) -> Vec<String> {
    ids.iter()
        .enumerate()
        .map(|(j, &id)| {
            model
                .joints
                .iter()
                .find(|mj| mj.servo.is_some_and(|s| s.id == id))
                .map_or_else(|| format!("J{j}"), |mj| mj.name.clone())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner::model::builtin;

    #[test]
    fn names_follow_servo_ids_and_fall_back_to_j() {
        let m = builtin("drosophibot2").unwrap();
        let servos = servo_joints(&m);
        let names = joint_names(&m, None, servos.len());
        // The board's joint 0 is the model's first servo joint: the left front ThC1.
        assert_eq!(names[0], "LF_ThC1");
        assert!(names.iter().all(|n| !n.starts_with('J')));
        // A board with another joint count than the model: no guessing.
        assert_eq!(joint_names(&m, None, 3), ["J0", "J1", "J2"]);
    }

    #[test]
    fn names_by_servo_ids_follow_the_model_in_any_order() {
        let m = builtin("drosophibot2").unwrap();
        let id_of = |name: &str| {
            m.joints
                .iter()
                .find(|j| j.name == name)
                .and_then(|j| j.servo)
                .unwrap()
                .id
        };
        // The board's map in another order than the model's, and an ID no model joint has.
        let ids = [id_of("RH_FTi"), id_of("LF_ThC1"), 250];
        assert_eq!(joint_names_by_ids(&m, &ids), ["RH_FTi", "LF_ThC1", "J2"]);
    }
}
