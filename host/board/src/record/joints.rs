//! What the recorder knows about each joint: a name, and from the step table the servo model and
//! direction (to turn load registers into joint torques), the modelled torque per slice, and
//! when its leg's stance is (for the plots' stance shading).

use protocol::{GaitTable, ServoModel};

/// One joint of a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMeta {
    /// `LF_ThC1`, or `J<n>` when no name is known.
    pub name: String,
    pub model: Option<ServoModel>,
    /// +1 or -1: joint angle direction against servo ticks.
    pub sign: i32,
    /// Modelled torque per slice of the step, N m (empty when the table is unknown).
    pub modelled_nm: Vec<f64>,
    /// Planned angle per slice of the step, rad (empty when the table is unknown).
    pub planned_rad: Vec<f64>,
    /// Stiffness the board's torque bias divides by, N m/rad: the table's joint map, replaced by
    /// the board's setting when it is known ([`held_stiffness`]); 0: the bias is off.
    pub stiffness_nm_per_rad: Option<f64>,
    /// Whether the joint's leg (the `LF` of `LF_ThC1`) is in stance, per slice of the step
    /// (empty when the table or the leg is unknown).
    pub stance: Vec<bool>,
}

/// The joints of a step table, named `names[j]` where given (else `J<j>`).
pub fn joints_of_table(table: &GaitTable<'_>, names: &[String]) -> Vec<JointMeta> {
    (0..table.joint_count())
        .map(|j| {
            let map = table.joint(j);
            JointMeta {
                name: names.get(j).cloned().unwrap_or_else(|| format!("J{j}")),
                model: map.map(|m| m.model),
                sign: map.map_or(1, |m| m.sign.as_i32()),
                modelled_nm: (0..table.slice_count())
                    .filter_map(|s| table.torque(s, j))
                    .map(protocol::units::torque_to_nm)
                    .collect(),
                stiffness_nm_per_rad: map
                    .map(|m| f64::from(m.stiffness) / protocol::units::STIFFNESS_PER_NM_RAD),
                planned_rad: (0..table.slice_count())
                    .filter_map(|s| table.angle(s, j))
                    .map(protocol::units::angle_to_rad)
                    .collect(),
                stance: names.get(j).map_or_else(Vec::new, |n| leg_stance(table, n)),
            }
        })
        .collect()
}

/// Makes each joint's stiffness the one the board holds (`settings`, read once the walk has
/// started: a `dbot set --stiffness` since the upload, 0 included, is what the bias divides by),
/// so `planned_rad` and the tracking error follow the board, not the table. Joints the settings
/// do not cover keep theirs.
pub fn held_stiffness(joints: &mut [JointMeta], settings: &protocol::Settings) {
    for (m, s) in joints.iter_mut().zip(&settings.joints) {
        m.stiffness_nm_per_rad =
            Some(f64::from(s.stiffness) / protocol::units::STIFFNESS_PER_NM_RAD);
    }
}

/// Stance per slice of the leg that `joint_name` starts with (bit i of a slice's stance byte is
/// leg i of `Leg::ALL`, as the planner writes it); empty for a name of no leg.
fn leg_stance(table: &GaitTable<'_>, joint_name: &str) -> Vec<bool> {
    let leg = planner::model::Leg::ALL.iter().position(|l| {
        joint_name
            .strip_prefix(l.name())
            .is_some_and(|r| r.starts_with('_'))
    });
    let Some(bit) = leg else {
        return Vec::new();
    };
    (0..table.slice_count())
        .filter_map(|s| table.stance(s))
        .map(|b| b & (1 << bit) != 0)
        .collect()
}

impl JointMeta {
    /// A joint known only by its name (no table: raw registers, no modelled torque).
    pub fn named(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            model: None,
            sign: 1,
            modelled_nm: Vec::new(),
            planned_rad: Vec::new(),
            stiffness_nm_per_rad: None,
            stance: Vec::new(),
        }
    }

    /// Joint torque in N m of a load register value (ESTIMATE, see
    /// `dynamixel::units::load_to_torque_nm`); `None` without a known servo model.
    pub fn torque_estimate_nm(&self, load: i16) -> Option<f64> {
        let model = self.model?;
        Some(f64::from(dynamixel::units::load_to_torque_nm(model, load)) * f64::from(self.sign))
    }
}
