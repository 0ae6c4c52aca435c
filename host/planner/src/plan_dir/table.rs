//! The step table of a plan directory: the one path from a plan on disk to `protocol::GaitTable`
//! bytes (`dbot table --plan`, `dbot upload --plan`, `dbot demo`, Python all come through here), so
//! the same directory always gives the same gait name and CRC.

use super::{PlanDir, PlanDirError};
use crate::plan::gait_table::{gait_table, stance_bits};

impl PlanDir {
    /// The names of the joints the step table holds, in table order.
    pub fn servo_joint_names(&self) -> Vec<String> {
        crate::plan::table::servo_joints(&self.model)
            .into_iter()
            .map(|j| self.model.joints[j].name.clone())
            .collect()
    }

    /// The gait name of its step table: plan.json's `table_name`, else the directory's name (as
    /// given, or of its canonical path for `.`), cut to the table's 16 bytes.
    pub fn table_name(&self) -> String {
        let name = self.json.table_name.clone().or_else(|| {
            let named =
                |p: &std::path::Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
            named(&self.path).or_else(|| named(&self.path.canonicalize().ok()?))
        });
        super::table_name_of(name.as_deref().unwrap_or("gait"))
    }

    /// The step table bytes: the planned angles and modelled torques of every servo per slice,
    /// stance bits, period and duty, named `name` or else [`Self::table_name`].
    pub fn step_table(&self, name: Option<&str>) -> Result<Vec<u8>, PlanDirError> {
        let torque = self.torques("the step table")?;
        let stance: Vec<u8> = self
            .stance
            .iter()
            .map(|s| stance_bits(&self.json.legs, s))
            .collect();
        gait_table(
            &self.model,
            name.unwrap_or(&self.table_name()),
            self.json.period_s,
            self.json.parameters.duty,
            &self.angle,
            torque,
            &stance,
        )
        .map_err(|source| PlanDirError::Table {
            dir: self.path.clone(),
            source,
        })
    }
}
