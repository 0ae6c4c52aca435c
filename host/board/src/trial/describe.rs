//! The parts of a trial's metadata read from what the board and the files say: the firmware's
//! versions ([`protocol::DeviceInfo`]), its settings ([`protocol::Settings`]), the gait (a slot's
//! [`protocol::GaitSummary`] or a step table) and the plan directory a table was built from.

use std::path::Path;

use super::error::TrialError;
use super::meta::{BoardSettings, FirmwareMeta, GaitMeta, JointSetting, PlanMeta};

impl FirmwareMeta {
    pub fn of(info: &protocol::DeviceInfo) -> Self {
        let v = info.firmware;
        Self {
            version: format!("{}.{}.{}", v.major, v.minor, v.patch),
            protocol_version: info.protocol_version,
            table_format_version: info.table_format_version,
            build_id: info.build_id,
        }
    }
}

impl BoardSettings {
    pub fn of(s: &protocol::Settings) -> Self {
        Self {
            bus_baud: s.baud,
            cycle_hz: s.cycle_hz,
            telemetry_every: s.telemetry_every,
            joints: s
                .joints
                .iter()
                .map(|j| JointSetting {
                    stiffness_mnm_per_rad: j.stiffness,
                    min_1e4_rad: j.min,
                    max_1e4_rad: j.max,
                    torque_enabled: j.torque_enabled,
                })
                .collect(),
        }
    }
}

impl GaitMeta {
    /// The gait of a header and its CRC (from a slot when `slot` is given, else a step table).
    pub fn of(header: &protocol::GaitHeader, crc: u32, slot: Option<u8>) -> Self {
        Self {
            slot,
            // A name that is not UTF-8 is shown escaped, never as raw bytes.
            name: header.name_str().map_or_else(
                || format!("{:?}", header.name.escape_ascii().to_string()),
                str::to_owned,
            ),
            crc,
            joints: header.joint_count,
            slices: header.slice_count,
            step_period_s: f64::from(header.step_period_us) / 1e6,
            duty: f64::from(header.duty) / 1e4,
        }
    }
}

impl PlanMeta {
    /// What the plan directory `dir` says of its plan (plan.json and the CRC of model.toml).
    pub fn read(dir: &Path) -> Result<Self, TrialError> {
        let json_path = dir.join("plan.json");
        let json = planner::plan_dir::read_json(&json_path)
            .map_err(|source| TrialError::Plan { source })?;
        let model_path = dir.join("model.toml");
        let model = std::fs::read(&model_path).map_err(|source| TrialError::Read {
            path: model_path,
            source,
        })?;
        Ok(Self {
            dir: dir.display().to_string(),
            model: json.model,
            model_source: json.model_source,
            model_crc: format!("{:08x}", protocol::crc32::checksum(&model)),
            parameters: serde_json::to_value(&json.parameters).map_err(|source| {
                TrialError::Json {
                    path: json_path,
                    source,
                }
            })?,
            period_s: json.period_s,
        })
    }
}
