//! The rules of `board::files` (docs/reliability.md, "Files"; issue 30 item 7): a symbolic link
//! is followed and its file replaced (the link stays), a link to nothing and a file with several
//! names are refused, two paths to one file take one lock, and the scratch file is the OS's,
//! beside the target with its extension, and gone after a failed write.

use std::os::unix::fs::symlink;
use std::time::Duration;

use board::files::{FileError, lock_beside, write_atomically, write_bytes_atomically};

fn names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_symbolic_link_is_followed_and_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("data");
    std::fs::create_dir(&real).unwrap();
    let target = real.join("store.flash");
    std::fs::write(&target, b"old").unwrap();
    let link = dir.path().join("store.flash");
    symlink(&target, &link).unwrap();
    write_bytes_atomically(&link, b"new").unwrap();
    assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
    assert_eq!(std::fs::read(&target).unwrap(), b"new");
    // The scratch file was made beside the real file, and is gone.
    assert_eq!(names(&real), ["store.flash"]);
    // A link to nothing is refused, naming the link.
    let dangling = dir.path().join("gone.csv");
    symlink(dir.path().join("nowhere/gone.csv"), &dangling).unwrap();
    let e = write_bytes_atomically(&dangling, b"x").unwrap_err();
    assert!(matches!(e, FileError::DanglingLink { .. }), "{e}");
    assert!(e.to_string().contains("gone.csv"), "{e}");
}

#[test]
fn a_file_with_two_names_is_refused_and_both_keep_their_data() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.json");
    let b = dir.path().join("b.json");
    std::fs::write(&a, b"old").unwrap();
    std::fs::hard_link(&a, &b).unwrap();
    let e = write_bytes_atomically(&a, b"new").unwrap_err();
    assert!(matches!(e, FileError::HardLink { links: 2, .. }), "{e}");
    assert!(e.to_string().contains("a.json"), "{e}");
    assert_eq!(std::fs::read(&a).unwrap(), b"old");
    assert_eq!(std::fs::read(&b).unwrap(), b"old");
}

#[test]
fn two_paths_to_one_file_take_one_lock() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("robots");
    std::fs::create_dir(&sub).unwrap();
    let file = sub.join("robot.flash");
    std::fs::write(&file, b"image").unwrap();
    let link = dir.path().join("robot.flash");
    symlink(&file, &link).unwrap();
    let held = lock_beside(&file, Duration::ZERO, |_| {}).unwrap();
    // Through a link, and through `..`: the same lock, so the second holder is refused.
    for other in [link.clone(), sub.join("../robots/robot.flash")] {
        let e = lock_beside(&other, Duration::ZERO, |_| {}).unwrap_err();
        assert!(
            matches!(e, FileError::Busy { .. }),
            "{}: {e}",
            other.display()
        );
    }
    drop(held);
    lock_beside(&link, Duration::ZERO, |_| {}).unwrap();
}

#[test]
fn the_scratch_file_is_beside_the_target_with_its_extension_and_removed_on_failure() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("angles.png");
    let mut seen = None;
    let e = write_atomically(&p, |s| {
        seen = Some(s.to_owned());
        std::fs::write(s, b"half")?;
        Err("plot failed".into())
    })
    .unwrap_err();
    assert!(e.to_string().contains("angles.png") && e.to_string().contains("plot failed"));
    let seen = seen.unwrap();
    assert_eq!(seen.parent(), Some(dir.path()));
    assert_eq!(seen.extension().unwrap(), "png");
    assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
    // A new file gets the mode a plain create gives (0666 less the umask), not the scratch's 0600.
    write_bytes_atomically(&p, b"png").unwrap();
    use std::os::unix::fs::PermissionsExt as _;
    let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
    let plain = dir.path().join("plain");
    std::fs::write(&plain, b"x").unwrap();
    let want = std::fs::metadata(&plain).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, want);
}
