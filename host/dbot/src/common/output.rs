//! Writing an output file so that an interrupted or failed run never leaves it half written:
//! every command's outputs go through the board library's one atomic write
//! (`board::files::write_atomically`: a scratch file beside the target, synced, renamed over it
//! when complete; a read-only or hard-linked target refused, a symbolic link followed).

use std::path::Path;

use anyhow::{Context, Result};

/// Writes the output `name` in `dir` through [`replace_file`].
pub fn replace(dir: &Path, name: &str, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    replace_file(&dir.join(name), write)
}

/// Writes the output `path` by calling `write` on a scratch file beside it (same extension, so
/// plotters picks the same format), renamed over `path` only once complete: a run that fails or
/// is killed leaves the previous file whole. The error names the file.
pub fn replace_file(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    board::files::write_atomically(path, |p| write(p).map_err(Into::into))
        .with_context(|| format!("writing {}", path.display()))
}
