//! Finds MuJoCo where scripts/setup.d/20-mujoco.sh puts it (MUJOCO_DYNAMIC_LINK_DIR, set in
//! .cargo/config.toml) and bakes that folder into this package's binaries, tests and benches as an
//! rpath, so they run without LD_LIBRARY_PATH. (An rpath does not reach binaries of other packages:
//! a binary crate that links `physics` adds the same line to its own build script.)

use std::path::PathBuf;

fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    let dir = std::env::var("MUJOCO_DYNAMIC_LINK_DIR").map(PathBuf::from);
    let so = dir.as_ref().map(|d| d.join("libmujoco.so.3.17.0"));
    match (&dir, &so) {
        (Ok(dir), Ok(so)) if so.is_file() => {
            println!("cargo::rerun-if-changed={}", so.display());
            println!("cargo::rustc-link-arg=-Wl,-rpath,{}", dir.display());
        }
        _ => panic!(
            "MuJoCo 3.17.0 is not installed: run scripts/setup.d/20-mujoco.sh (it unpacks the official \
             wheel's libmujoco.so.3.17.0 into .mujoco/; MUJOCO_DYNAMIC_LINK_DIR = {dir:?})"
        ),
    }
}
