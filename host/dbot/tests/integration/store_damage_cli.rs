//! A damaged gait store is reported, not played silently (issue #19, "The wrong gait, silently"),
//! run as processes on the virtual robot's store file: one byte flipped in the live table of slot 0
//! makes `gaits` and `run` say FELL BACK and name both gaits; random bytes over the whole file make
//! `gaits` say the store is damaged, not empty.

use crate::board_fakes;
use std::path::Path;

use board_fakes::cli::{run, strings};
use firmware::testkit::SyntheticGait;

/// The synthetic gait of `slices` slices named `name`, written to `dir/file`; returns the path and
/// the bytes.
fn named_table(dir: &Path, file: &str, slices: usize, name: &str) -> (String, Vec<u8>) {
    let t = SyntheticGait::new(slices, 0.5).build_named(name);
    let p = dir.join(file);
    std::fs::write(&p, &t).unwrap();
    (p.display().to_string(), t)
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let d = run(dir, &strings(args));
    assert!(d.status.success(), "{args:?}: {}{}", d.stdout, d.stderr);
    d.stdout
}

#[test]
fn a_flipped_byte_in_the_live_table_is_reported_as_a_fallback_by_gaits_status_and_run() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.flash");
    let image = format!("virtual:{}", path.display());
    let (old, _) = named_table(dir.path(), "old.dbgt", 30, "tripod-slow");
    let (new, new_bytes) = named_table(dir.path(), "new.dbgt", 40, "tripod-fwd");
    ok(dir.path(), &["upload", "--table", &old, "--port", &image]);
    ok(dir.path(), &["upload", "--table", &new, "--port", &image]);
    let out = ok(dir.path(), &["gaits", "--port", &image]);
    assert!(out.contains("slot 0: \"tripod-fwd\""), "{out}");
    assert!(!out.contains("FELL BACK"), "{out}");

    // Find the live table in the store file by its bytes and flip one byte in its slices.
    let mut store = std::fs::read(&path).unwrap();
    let at = store
        .windows(new_bytes.len())
        .position(|w| w == new_bytes)
        .expect("the uploaded table is in the store file");
    store[at + 200] ^= 0x01;
    std::fs::write(&path, &store).unwrap();

    let crc = protocol::GaitTable::parse(&new_bytes).unwrap().crc();
    let out = ok(dir.path(), &["gaits", "--port", &image]);
    let line = out.lines().find(|l| l.starts_with("slot 0:")).unwrap();
    assert!(line.starts_with("slot 0: \"tripod-slow\""), "{out}");
    assert!(
        line.contains(&format!(
            "FELL BACK: the newer copy \"tripod-fwd\" (seq 2, CRC {crc:#010x}) failed its CRC check and was lost"
        )),
        "{out}"
    );
    assert!(out.starts_with("store damaged: slot 0 fell back"), "{out}");

    let out = ok(dir.path(), &["status", "--port", &image]);
    assert!(out.contains("store     damaged: slot 0 fell back"), "{out}");

    let out = ok(
        dir.path(),
        &["run", "--slot", "0", "--steps", "1", "--port", &image],
    );
    assert!(out.contains("slot 0: \"tripod-slow\""), "{out}");
    assert!(
        out.contains("WARNING slot 0: FELL BACK: the newer copy \"tripod-fwd\""),
        "{out}"
    );

    // A new upload clears the mark.
    ok(dir.path(), &["upload", "--table", &new, "--port", &image]);
    let out = ok(dir.path(), &["gaits", "--port", &image]);
    assert!(out.contains("slot 0: \"tripod-fwd\""), "{out}");
    assert!(
        !out.contains("FELL BACK") && !out.contains("damaged"),
        "{out}"
    );
}

#[test]
fn a_store_file_of_random_bytes_reads_as_damaged_not_empty() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.flash");
    let image = format!("virtual:{}", path.display());
    let out = ok(dir.path(), &["gaits", "--port", &image]);
    assert!(out.lines().all(|l| l.ends_with(": empty")), "{out}");
    let len = std::fs::metadata(&path).unwrap().len() as usize;
    // xorshift32 with a fixed seed: the same bytes every run.
    let mut x = 0x9E37_79B9u32;
    let junk: Vec<u8> = (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    std::fs::write(&path, &junk).unwrap();
    let out = ok(dir.path(), &["gaits", "--port", &image]);
    assert!(
        out.starts_with("store damaged: no readable record in any slot"),
        "{out}"
    );
    assert!(!out.contains("empty"), "{out}");
    assert!(out.contains("slot 0: DAMAGED: no readable record"), "{out}");
    let d = run(
        dir.path(),
        &strings(&["run", "--slot", "0", "--steps", "1", "--port", &image]),
    );
    assert!(!d.status.success());
    assert!(
        d.stderr.contains("slot 0 holds no readable gait"),
        "{}",
        d.stderr
    );
}
