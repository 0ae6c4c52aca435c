//! The plan directory: one typed, versioned format that `lab::plan_dir_write` writes (for
//! `dbot plan`, `dbot demo` and Python's `Plan.write`) and `dbot table`, `dbot compare`,
//! `dbot upload --plan` and Python read.
//!
//! Files: plan.json ([`PlanJson`], with [`FORMAT_VERSION`]), model.toml (the planned model, so
//! the directory is read without the model's source), model.urdf, joints.csv and feet.csv (columns
//! named once in [`columns`]), and with the inverse dynamics their torque and force columns and
//! joint_forces.csv. A directory of another format version, or without one, is refused with an
//! error naming the version and the file; one that contradicts itself ([`consistency`]) naming
//! the field, slice and leg.

pub mod columns;
mod consistency;
mod csv_out;
mod error;
mod json;
mod read;
mod table;

pub use csv_out::{ExtraColumn, ReportError, write_feet_csv, write_joints_csv};
pub use error::PlanDirError;
pub use json::{FORMAT_VERSION, FRAMES, PlanJson, SpringOptions, table_name_of};
pub use read::{PlanDir, read, read_json};
