//! No lost user data (issue #19, item 2), run as processes (the real `CARGO_BIN_EXE_dbot`) on the
//! virtual robot's store file: a recording that records nothing does not replace a good one; a
//! read-only store is refused and kept with its mode; a store keeps its permissions; a command
//! that ran beside an upload does not undo it on exit; a store in a directory where nothing can
//! be written is refused before anything says "verified".

use crate::board_fakes;
use std::os::unix::fs::PermissionsExt as _;
use std::path::Path;
use std::time::Duration;

use board_fakes::cli::{Done, fails_naming, run, spawn, strings, table, tree, wait_for};

/// `dbot upload --table TABLE [--slot SLOT] --port IMAGE`, run in `dir`.
fn upload(dir: &Path, table: &str, slot: Option<&str>, image: &str) -> Done {
    let mut args = vec!["upload", "--table", table];
    if let Some(slot) = slot {
        args.extend(["--slot", slot]);
    }
    args.extend(["--port", image]);
    run(dir, &strings(&args))
}

fn mode(p: &Path) -> u32 {
    std::fs::metadata(p).unwrap().permissions().mode() & 0o777
}

fn chmod(p: &Path, mode: u32) {
    std::fs::set_permissions(p, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// The `gaits` line of `slot` of the store `image`.
fn slot_line(dir: &Path, image: &str, slot: u8) -> String {
    let d = run(dir, &strings(&["gaits", "--port", image]));
    assert!(d.status.success(), "gaits: {}", d.stderr);
    let head = format!("slot {slot}:");
    d.stdout
        .lines()
        .find(|l| l.starts_with(&head))
        .unwrap_or_else(|| panic!("no {head} in {}", d.stdout))
        .to_owned()
}

#[test]
fn record_every_0_into_a_good_recording_is_refused_and_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let image = format!("virtual:{}", dir.path().join("robot.flash").display());
    // 0.6 s: an MX-28 follows it (4.17 rad/s), as a table file must.
    let t = table(dir.path(), "g.dbgt", 40, 0.6);
    let d = upload(dir.path(), &t, None, &image);
    assert!(d.status.success(), "{}", d.stderr);
    let rec = dir.path().join("rec");
    let record = |every: &str| {
        strings(&[
            "record",
            "--out",
            rec.to_str().unwrap(),
            "--play",
            "0",
            "--steps",
            "1",
            "--every",
            every,
            "--port",
            &image,
        ])
    };
    let d = run(dir.path(), &record("4"));
    assert!(d.status.success(), "{}", d.stderr);
    let good = tree(&rec);
    // Before: exit 0 and a telemetry.csv of the header alone beside the old angles.png.
    let d = run(dir.path(), &record("0"));
    assert!(
        !d.status.success(),
        "record --every 0 succeeded: {}",
        d.stdout
    );
    assert!(d.stderr.contains("every"), "{}", d.stderr);
    assert_eq!(tree(&rec), good, "the good recording was changed");
}

#[test]
fn a_read_only_store_is_refused_and_kept_with_its_mode() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.flash");
    let image = format!("virtual:{}", path.display());
    let a = table(dir.path(), "a.dbgt", 20, 0.5);
    let b = table(dir.path(), "b.dbgt", 30, 0.6);
    let d = upload(dir.path(), &a, None, &image);
    assert!(d.status.success(), "{}", d.stderr);
    let before = std::fs::read(&path).unwrap();
    chmod(&path, 0o444);
    // Before: the upload succeeded and the file came back 0644 with the new gait.
    let d = upload(dir.path(), &b, None, &image);
    fails_naming(
        &d,
        "upload into a read-only store",
        &["robot.flash", "read-only"],
    );
    assert!(!d.stdout.contains("verified"), "{}", d.stdout);
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(mode(&path), 0o444);
}

#[test]
fn a_store_keeps_its_permissions() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robot.flash");
    let image = format!("virtual:{}", path.display());
    let a = table(dir.path(), "a.dbgt", 20, 0.5);
    let d = upload(dir.path(), &a, None, &image);
    assert!(d.status.success(), "{}", d.stderr);
    chmod(&path, 0o600);
    let d = upload(dir.path(), &a, Some("1"), &image);
    assert!(d.status.success(), "{}", d.stderr);
    // Before: every save made a new file with the default mode (0644).
    assert_eq!(mode(&path), 0o600);
}

#[test]
fn a_command_beside_an_upload_does_not_undo_it() {
    let dir = tempfile::tempdir().unwrap();
    let image = format!("virtual:{}", dir.path().join("robot.flash").display());
    let walk = table(dir.path(), "walk.dbgt", 100, 1.0);
    let new = table(dir.path(), "new.dbgt", 50, 0.5);
    let d = upload(dir.path(), &walk, None, &image);
    assert!(d.status.success(), "{}", d.stderr);
    let empty = slot_line(dir.path(), &image, 1);
    // A walk holds the store (it saves on exit); an upload into slot 1 is started during it.
    // Before: the upload saved first, then the walk saved the flash it had loaded at its start,
    // and the verified upload was gone. The order is made, not slept into: the upload starts once
    // the walk has announced its gait (the store is open, its lock held), the walk is stopped
    // (Ctrl-C) only once the upload says it waits for that lock.
    let walking = spawn(
        dir.path(),
        "walk",
        &strings(&["run", "--slot", "0", "--steps", "1000", "--port", &image]),
        None,
    );
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap_or_default();
    wait_for("the walk's announcement", Duration::from_secs(60), || {
        read("walk.stdout").contains("playing 1000 steps")
    });
    let up = spawn(
        dir.path(),
        "up",
        &strings(&["upload", "--table", &new, "--slot", "1", "--port", &image]),
        None,
    );
    wait_for(
        "the upload waiting for the walk",
        Duration::from_secs(25),
        || read("up.stderr").contains("in use by another dbot"),
    );
    assert!(
        !read("up.stdout").contains("verified"),
        "the upload went ahead of the walk"
    );
    walking.signal(nix::sys::signal::Signal::SIGINT);
    let w = walking.wait();
    assert!(w.stderr.contains("interrupted"), "run: {}", w.stderr);
    let u = up.wait();
    assert!(u.status.success(), "upload: {}", u.stderr);
    assert!(u.stdout.contains("verified"), "{}", u.stdout);
    let now = slot_line(dir.path(), &image, 1);
    assert_ne!(
        now, empty,
        "the verified upload into slot 1 was lost: {now}"
    );
    assert!(now.contains("50 slices"), "{now}");
}

#[test]
fn a_store_in_a_directory_nobody_may_write_is_refused_before_any_success() {
    // Root writes anywhere: the command runs as `nobody` (uid 65534), as the board tests do.
    // SAFETY: geteuid has no preconditions and cannot fail.
    let root = unsafe { nix::libc::geteuid() } == 0;
    let uid = root.then_some(65_534);
    let dir = tempfile::tempdir().unwrap();
    let store = dir.path().join("store");
    std::fs::create_dir(&store).unwrap();
    let path = store.join("robot.flash");
    let image = format!("virtual:{}", path.display());
    let a = table(dir.path(), "a.dbgt", 20, 0.5);
    let d = upload(dir.path(), &a, None, &image);
    assert!(d.status.success(), "{}", d.stderr);
    let before = std::fs::read(&path).unwrap();
    chmod(dir.path(), 0o755);
    chmod(Path::new(&a), 0o644);
    chmod(&path, 0o666);
    chmod(&store, 0o555);
    let probe = spawn(dir.path(), "probe", &strings(&["--version"]), uid).wait();
    assert!(
        probe.status.success(),
        "dbot cannot run as uid 65534 here: {}",
        probe.stderr
    );
    // Before: "slot 1: ... verified ..." on stdout, then exit 1 with nothing saved.
    let d = spawn(
        dir.path(),
        "ro-dir",
        &strings(&["upload", "--table", &a, "--slot", "1", "--port", &image]),
        uid,
    )
    .wait();
    fails_naming(&d, "upload into a read-only directory", &["robot.flash"]);
    assert!(!d.stdout.contains("verified"), "{}", d.stdout);
    chmod(&store, 0o755);
    assert_eq!(std::fs::read(&path).unwrap(), before);
}
