//! Errors from loading, importing and validating organism models. Each names the place: the file,
//! the field, the body or the joint.

use std::path::PathBuf;

/// A model could not be loaded, imported or validated.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    #[error("{file}: cannot read: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: TOML syntax or type error: {message}")]
    Toml { file: String, message: String },
    #[error("{file}: XML error: {message}")]
    Xml { file: String, message: String },
    /// A field has a value that cannot be right (negative mass, limits reversed, ...).
    #[error("{file}: {place}: field `{field}`: {problem}")]
    Field {
        file: String,
        /// e.g. `joint LF_ThC1` or `body LF_Femur`.
        place: String,
        field: String,
        problem: String,
    },
    /// A name refers to a body or joint that does not exist.
    #[error("{file}: {place}: unknown {what} `{name}`")]
    Unknown {
        file: String,
        place: String,
        what: &'static str,
        name: String,
    },
    #[error("unknown built-in model `{name}` (known: {known})")]
    UnknownBuiltin { name: String, known: String },
}

/// Shorthand for a field error.
pub(crate) fn field(
    file: &str,
    place: impl Into<String>,
    field: &str,
    problem: impl Into<String>,
) -> ModelError {
    ModelError::Field {
        file: file.to_string(),
        place: place.into(),
        field: field.to_string(),
        problem: problem.into(),
    }
}
