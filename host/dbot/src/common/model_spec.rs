//! `--model SPEC`: a built-in model name, a .toml model file or an AnimatLab .aproj project.

use std::path::Path;

use anyhow::{Context, Result};
use planner::model::{self, ImportOptions, Model};

/// Loads a model from a built-in name, a .toml file or an .aproj file.
pub fn load_model(spec: &str) -> Result<Model> {
    let path = Path::new(spec);
    match path.extension().and_then(|e| e.to_str()) {
        Some("toml") => model::load(path).with_context(|| format!("loading model file {spec}")),
        Some("aproj") => model::import_aproj_file(path, &ImportOptions::default())
            .with_context(|| format!("importing {spec}")),
        _ => {
            model::builtin(spec).context("--model takes a built-in name, a .toml or an .aproj file")
        }
    }
}
