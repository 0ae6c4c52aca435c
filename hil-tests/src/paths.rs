//! Where the HIL pieces live: the repository root, the firmware image, the Node runner.

use std::path::PathBuf;

/// The repository root (the workspace directory that holds `hil-tests/`).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("hil-tests lives one level below the repository root")
        .to_path_buf()
}

/// The release firmware ELF: `DBOT_HIL_ELF` if set, else what `(cd firmware && cargo build --release)`
/// leaves in the workspace target directory (`CARGO_TARGET_DIR` is honoured).
pub fn firmware_elf() -> PathBuf {
    if let Some(p) = std::env::var_os("DBOT_HIL_ELF") {
        return PathBuf::from(p);
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo_root().join("target"));
    target.join("thumbv6m-none-eabi/release/firmware")
}

/// The emulator runner's Node project.
pub fn runner_dir() -> PathBuf {
    repo_root().join("hil-tests/runner")
}
