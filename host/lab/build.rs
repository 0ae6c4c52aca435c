//! `lab`'s tests walk the physics robot (crate `physics`, MuJoCo 3.17.0): bake MuJoCo's folder
//! (MUJOCO_DYNAMIC_LINK_DIR, set in .cargo/config.toml; filled by scripts/setup.d/20-mujoco.sh) into
//! them as an rpath, as host/physics/build.rs does for its own targets (rpaths do not pass from
//! one package's build script to another package's binaries).

fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    if let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR") {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
