//! The built-in models, embedded from host/planner/models/*.toml.

use super::error::ModelError;
use super::{Model, file};

/// Names accepted by [`builtin`].
pub const BUILTIN_NAMES: [&str; 2] = ["drosophibot2", "scale-drosophila"];

/// A built-in model by name: `drosophibot2` or `scale-drosophila`.
pub fn builtin(name: &str) -> Result<Model, ModelError> {
    let text = match name {
        "drosophibot2" => include_str!("../../models/drosophibot2.toml"),
        "scale-drosophila" => include_str!("../../models/scale-drosophila.toml"),
        _ => {
            return Err(ModelError::UnknownBuiltin {
                name: name.to_string(),
                known: BUILTIN_NAMES.join(", "),
            });
        }
    };
    file::from_toml_str(text, &format!("host/planner/models/{name}.toml"))
}
