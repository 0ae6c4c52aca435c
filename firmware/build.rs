//! Build script of the firmware: copies ../memory.x where the linker finds it, checks that its regions
//! do not overlap (the gait store above all), hands the gait store bounds to the code as constants,
//! hands the build id (the git commit built, `build_id.rs`) to the code, and passes the
//! cortex-m-rt / defmt linker scripts when building for the RP2040.

use std::{
    env, fs,
    path::{Path, PathBuf},
    process::Command,
};

/// One `NAME : ORIGIN = a, LENGTH = b` line of memory.x.
#[derive(Debug)]
struct Region {
    name: String,
    origin: u64,
    length: u64,
}

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let memory_x = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap()).join("../memory.x");
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");
    let text = fs::read_to_string(&memory_x)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", memory_x.display()));
    let regions = parse_regions(&text);
    check_layout(&regions);

    let gaits = find(&regions, "GAITS");
    let flash = find(&regions, "FLASH");
    let boot2 = find(&regions, "BOOT2");
    let ram = find(&regions, "RAM");
    fs::write(
        out.join("memory_map.rs"),
        format!(
            "/// Start of the XIP flash window (BOOT2 origin).\n\
             pub const FLASH_BASE: u32 = {:#x};\n\
             /// Bytes reserved for the firmware image (BOOT2 + FLASH).\n\
             pub const IMAGE_CAPACITY: u32 = {:#x};\n\
             /// Offset of the gait store from the start of flash.\n\
             pub const GAIT_STORE_OFFSET: u32 = {:#x};\n\
             /// Size of the gait store in bytes.\n\
             pub const GAIT_STORE_SIZE: u32 = {:#x};\n\
             /// Size of RAM in bytes.\n\
             pub const RAM_SIZE: u32 = {:#x};\n",
            boot2.origin,
            flash.origin + flash.length - boot2.origin,
            gaits.origin - boot2.origin,
            gaits.length,
            ram.length,
        ),
    )
    .unwrap();

    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap());
    fs::write(
        out.join("build_id.rs"),
        format!(
            "/// The first 8 hex digits of the git commit this firmware was built from; 0: unknown\n\
             /// (built outside a git checkout without `DBOT_BUILD_ID`).\n\
             pub const BUILD_ID: u32 = {:#010x};\n",
            build_id(&manifest)
        ),
    )
    .unwrap();

    let target = env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv6m") {
        fs::copy(&memory_x, out.join("memory.x")).unwrap();
        println!("cargo:rustc-link-search={}", out.display());
        println!("cargo:rustc-link-arg-bins=--nmagic");
        println!("cargo:rustc-link-arg-bins=-Tlink.x");
        println!("cargo:rustc-link-arg-bins=-Tlink-rp.x");
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
}

fn find<'a>(regions: &'a [Region], name: &str) -> &'a Region {
    regions
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("memory.x has no {name} region"))
}

/// Regions must be disjoint, and the gait store must lie wholly after the image in flash.
fn check_layout(regions: &[Region]) {
    for (i, a) in regions.iter().enumerate() {
        for b in &regions[i + 1..] {
            let disjoint = a.origin + a.length <= b.origin || b.origin + b.length <= a.origin;
            assert!(
                disjoint,
                "memory.x: regions {} and {} overlap",
                a.name, b.name
            );
        }
    }
    let flash = find(regions, "FLASH");
    let gaits = find(regions, "GAITS");
    assert!(
        flash.origin + flash.length <= gaits.origin,
        "memory.x: the gait store must follow the firmware image in flash"
    );
    assert!(
        gaits.origin.is_multiple_of(4096) && gaits.length.is_multiple_of(4096),
        "memory.x: the gait store must be aligned to 4 KB flash sectors"
    );
    assert!(
        gaits.origin + gaits.length <= 0x1000_0000 + 2 * 1024 * 1024,
        "memory.x: the gait store runs past the end of the 2 MB flash"
    );
}

/// Reads the `MEMORY { ... }` block: `NAME : ORIGIN = <expr>, LENGTH = <expr>` per line.
fn parse_regions(text: &str) -> Vec<Region> {
    let start = text.find("MEMORY").expect("memory.x has no MEMORY block");
    let body = &text[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find('}').unwrap()];
    body.lines()
        .filter_map(|line| {
            let (name, rest) = line.split_once(':')?;
            let origin = rest.split("ORIGIN").nth(1)?.split(',').next()?;
            let length = rest.split("LENGTH").nth(1)?;
            Some(Region {
                name: name.trim().to_string(),
                origin: eval(origin.trim_start_matches([' ', '='])),
                length: eval(length.trim_start_matches([' ', '='])),
            })
        })
        .collect()
}

/// Evaluates the `a + b - c` sums of hex, decimal and K/M literals that memory.x uses.
fn eval(expr: &str) -> u64 {
    let mut total: i64 = 0;
    let mut sign = 1;
    for token in expr
        .replace('+', " + ")
        .replace('-', " - ")
        .split_whitespace()
    {
        match token {
            "+" => sign = 1,
            "-" => sign = -1,
            t => {
                let (digits, scale) = match t.strip_suffix('K') {
                    Some(d) => (d, 1024),
                    None => match t.strip_suffix('M') {
                        Some(d) => (d, 1024 * 1024),
                        None => (t, 1),
                    },
                };
                let value = match digits.strip_prefix("0x") {
                    Some(hex) => i64::from_str_radix(&hex.replace('_', ""), 16),
                    None => digits.replace('_', "").parse(),
                }
                .unwrap_or_else(|e| panic!("memory.x: cannot read number {t:?}: {e}"));
                total += sign * value * scale;
            }
        }
    }
    u64::try_from(total).expect("memory.x: negative address")
}

/// The build id: `DBOT_BUILD_ID` (hex) when set, else the first 8 hex digits of the checkout's git
/// commit (`git rev-parse HEAD`), else 0 (unknown: not a git checkout, or no git). Uncommitted
/// changes are not part of it. Asks cargo to run this again when the commit moves (HEAD, the
/// branch's ref, packed refs), so the id never names an older commit.
fn build_id(manifest: &Path) -> u32 {
    println!("cargo:rerun-if-env-changed=DBOT_BUILD_ID");
    if let Ok(given) = env::var("DBOT_BUILD_ID") {
        let hex = given.trim().trim_start_matches("0x");
        return u32::from_str_radix(hex, 16).unwrap_or_else(|_| {
            panic!("DBOT_BUILD_ID {given:?}: give up to 8 hex digits (e.g. 1a2b3c4d)")
        });
    }
    let git = |args: &[&str]| -> Option<String> {
        let out = Command::new("git")
            .arg("-C")
            .arg(manifest)
            .args(args)
            .output()
            .ok()?;
        out.status
            .success()
            .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
    };
    let Some(commit) = git(&["rev-parse", "HEAD"]) else {
        return 0;
    };
    let mut watched = vec!["HEAD".to_owned(), "packed-refs".to_owned()];
    if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
        watched.push(branch);
    }
    for name in watched {
        // Only files that exist: cargo reruns a script on every build for a missing one.
        if let Some(path) = git(&["rev-parse", "--path-format=absolute", "--git-path", &name])
            && Path::new(&path).exists()
        {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    commit
        .get(..8)
        .and_then(|h| u32::from_str_radix(h, 16).ok())
        .unwrap_or(0)
}
