//! Writing an output file so that an interrupted or failed run never leaves it half written: every
//! command's outputs go through a scratch file renamed over the old one when complete.

use std::path::Path;

use anyhow::{Context, Result};

/// Writes the output `name` in `dir` through a scratch file next to it (`.partial-NAME`, same
/// extension, so plotters picks the same format), renamed over `name` only once complete: a run
/// that fails or is killed leaves the previous file whole (and at worst a scratch file). The error
/// names the file.
pub fn replace(dir: &Path, name: &str, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let path = dir.join(name);
    let scratch = dir.join(format!(".partial-{name}"));
    let done = write(&scratch).and_then(|()| Ok(std::fs::rename(&scratch, &path)?));
    if done.is_err() {
        let _ = std::fs::remove_file(&scratch);
    }
    done.with_context(|| format!("writing {}", path.display()))
}

/// [`replace`] for an output named by its whole path (`--out FILE`): the scratch file sits next to it.
pub fn replace_file(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file name", path.display()))?
        .to_string_lossy()
        .into_owned();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    replace(dir, &name, write)
}
