//! Writing user data so that it is never lost: the one atomic write every output of `dbot` and the
//! library goes through (recordings, trial records, exported models, the virtual robot's store).
//! A file is written to a scratch file the OS names beside it, synced, and renamed over the target
//! only once complete, so a kill, a full disk or a failed write leaves the previous file whole.
//! The rules (docs/reliability.md, "Files"): an existing file's permissions are kept; a read-only
//! file is refused, not replaced (a rename would replace it even so: the directory, not the file,
//! decides who may rename); a symbolic link is followed and the file it names is replaced (the
//! link stays); a file with several names (hard links) is refused; a folder is only ever renamed
//! to a name that does not exist ([`rename_new`]).
//!
//! Also an advisory lock beside a file, for stores that several processes may open at once: taken
//! beside the file a path really names, so two paths to one file share one lock.

use std::fs::{File, OpenOptions};
use std::os::unix::fs::{MetadataExt as _, PermissionsExt as _};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use nix::fcntl::{Flock, FlockArg};

/// The error a writer closure returns (anything: an I/O error, a plot backend's error).
pub type WriteError = Box<dyn std::error::Error + Send + Sync>;

/// Why a file could not be written or locked. Each names the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    #[error(
        "{path} is read-only (mode {mode:o}): refusing to replace it; make it writable \
         (chmod u+w) or choose another file"
    )]
    ReadOnly { path: PathBuf, mode: u32 },
    #[error("writing {path}: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: WriteError,
    },
    #[error("{path} is not a file name")]
    NotAFileName { path: PathBuf },
    #[error(
        "{path} has {links} names (hard links): replacing it would give only this name the new \
         data; copy it to a file of its own first"
    )]
    HardLink { path: PathBuf, links: u64 },
    #[error("{path} is a symbolic link to nothing: {source}")]
    DanglingLink {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} exists: refusing to put anything over it")]
    Exists { path: PathBuf },
    #[error(
        "{path} is in use by another process (it holds the lock {lock}); waited {waited_s:.0} s: \
         try again when it has finished"
    )]
    Busy {
        path: PathBuf,
        lock: PathBuf,
        waited_s: f64,
    },
    #[error("locking {path} (lock file {lock}): {source}")]
    Lock {
        path: PathBuf,
        lock: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The directory and file name of `path` (a bare name is in the current directory).
fn split(path: &Path) -> Result<(&Path, String), FileError> {
    let name = path
        .file_name()
        .ok_or_else(|| FileError::NotAFileName {
            path: path.to_owned(),
        })?
        .to_string_lossy()
        .into_owned();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Ok((dir, name))
}

/// The scratch file `write_atomically` writes `path` through: `.partial-NAME` beside it (same
/// extension, so a writer that picks its format from the name picks the same one).
pub fn scratch_of(path: &Path) -> Result<PathBuf, FileError> {
    let (dir, name) = split(path)?;
    Ok(dir.join(format!(".partial-{name}")))
}

/// Refuses an existing `path` that nobody may write (checked from the mode, so also for root,
/// for whom the kernel would not refuse), and one with several names (a hard link: a rename
/// would give only this name the new data, and its lock would not be the other names' lock).
pub fn check_writable(path: &Path) -> Result<(), FileError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.permissions().mode() & 0o222 == 0 => Err(FileError::ReadOnly {
            path: path.to_owned(),
            mode: m.permissions().mode() & 0o7777,
        }),
        Ok(m) if m.is_file() && m.nlink() > 1 => Err(FileError::HardLink {
            path: path.to_owned(),
            links: m.nlink(),
        }),
        Ok(m) if m.is_dir() => Err(FileError::NotAFileName {
            path: path.to_owned(),
        }),
        _ => Ok(()),
    }
}

/// The file an output path names: a symbolic link is followed to the file it points at (that
/// file is replaced, the link stays a link), and the folder is made absolute with `..` and links
/// resolved, so two paths to one file get one lock. A link that points nowhere is refused.
pub fn real_path(path: &Path) -> Result<PathBuf, FileError> {
    if path
        .symlink_metadata()
        .is_ok_and(|m| m.file_type().is_symlink())
    {
        return std::fs::canonicalize(path).map_err(|source| FileError::DanglingLink {
            path: path.to_owned(),
            source,
        });
    }
    let (dir, name) = split(path)?;
    Ok(match std::fs::canonicalize(dir) {
        Ok(d) => d.join(name),
        // A folder that does not exist yet: the write will say so, naming the path as given.
        Err(_) => path.to_owned(),
    })
}

/// Writes `path` by calling `write` on a scratch file the OS names in the same folder (with the
/// same extension, so a writer that picks its format from the name picks the same one), then
/// syncing it, giving it the permissions of the file it replaces, and renaming it over `path`.
/// On any failure the scratch file is removed and `path` is untouched. This is the one atomic
/// file write of every crate that can depend on this one.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), WriteError>,
) -> Result<(), FileError> {
    let path = &real_path(path)?;
    check_writable(path)?;
    let (dir, name) = split(path)?;
    let fail = |source: WriteError| FileError::Write {
        path: path.to_owned(),
        source,
    };
    let scratch = tempfile::Builder::new()
        .prefix(".partial-")
        .suffix(&format!("-{name}"))
        .tempfile_in(dir)
        .map_err(|e| fail(e.into()))?;
    let old_mode = std::fs::metadata(path)
        .ok()
        .map(|m| m.permissions().mode() & 0o7777);
    // Dropping `scratch` on an early return removes it.
    write(scratch.path()).map_err(fail)?;
    let file = File::open(scratch.path()).map_err(|e| fail(e.into()))?;
    file.sync_all().map_err(|e| fail(e.into()))?;
    let mode = old_mode.unwrap_or(0o666 & !umask());
    std::fs::set_permissions(scratch.path(), std::fs::Permissions::from_mode(mode))
        .map_err(|e| fail(e.into()))?;
    scratch.persist(path).map_err(|e| fail(e.error.into()))?;
    sync_dir(dir).map_err(|e| fail(e.into()))
}

/// The process's file mode creation mask (a new output gets the mode `File::create` would give).
fn umask() -> u32 {
    let old = nix::sys::stat::umask(nix::sys::stat::Mode::empty());
    nix::sys::stat::umask(old);
    old.bits()
}

/// A rename is durable only once its folder is synced.
fn sync_dir(dir: &Path) -> std::io::Result<()> {
    File::open(dir)?.sync_all()
}

/// Puts a complete scratch file (written by a caller that streams into [`scratch_of`]`(path)`,
/// such as the demo's recording) in place of `path`, as [`write_atomically`] does: synced, with
/// the replaced file's permissions, a read-only target refused. The scratch file is left as it
/// is on failure (it holds the only copy of the new data).
pub fn commit_scratch(path: &Path) -> Result<(), FileError> {
    check_writable(path)?;
    let scratch = scratch_of(path)?;
    let old_mode = std::fs::metadata(path)
        .ok()
        .map(|m| m.permissions().mode() & 0o7777);
    let done = || -> std::io::Result<()> {
        File::open(&scratch)?.sync_all()?;
        if let Some(mode) = old_mode {
            std::fs::set_permissions(&scratch, std::fs::Permissions::from_mode(mode))?;
        }
        std::fs::rename(&scratch, path)?;
        sync_dir(split(path).map_or(Path::new("."), |(d, _)| d))
    };
    done().map_err(|source| FileError::Write {
        path: path.to_owned(),
        source: source.into(),
    })
}

/// Renames `from` to `to` only if `to` does not exist (a folder is never merged into or put
/// over another), and syncs the folder.
pub fn rename_new(from: &Path, to: &Path) -> Result<(), FileError> {
    use nix::fcntl::{AT_FDCWD, RenameFlags, renameat2};
    let fail = |source: WriteError| FileError::Write {
        path: to.to_owned(),
        source,
    };
    renameat2(AT_FDCWD, from, AT_FDCWD, to, RenameFlags::RENAME_NOREPLACE).map_err(
        |e| match e {
            nix::errno::Errno::EEXIST | nix::errno::Errno::ENOTEMPTY => FileError::Exists {
                path: to.to_owned(),
            },
            e => fail(std::io::Error::from(e).into()),
        },
    )?;
    sync_dir(split(to)?.0).map_err(|e| fail(e.into()))
}

/// [`write_atomically`] for a file written from bytes in memory.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    write_atomically(path, |p| Ok(std::fs::write(p, bytes)?))
}

/// An exclusive advisory lock on a file, held by a lock file beside it (`.NAME.lock`: the file
/// itself is replaced by renames, so a lock on its inode would not outlive a save). Released
/// when dropped or when the process ends, however it ends.
#[derive(Debug)]
pub struct FileLock {
    _lock: Flock<File>,
    pub lock_path: PathBuf,
}

/// Takes the lock of `path`, waiting up to `wait` for another holder (calling `on_wait` once
/// when it has to wait). The lock file is created beside the file `path` really names
/// ([`real_path`]: links and `..` resolved), so every path to one file takes one lock, and a
/// directory where nothing can be written is refused here, before any work.
pub fn lock_beside(
    path: &Path,
    wait: Duration,
    on_wait: impl FnOnce(&Path),
) -> Result<FileLock, FileError> {
    let real = real_path(path)?;
    check_writable(&real)?;
    let (dir, name) = split(&real)?;
    let lock_path = dir.join(format!(".{name}.lock"));
    let lock_err = |source| FileError::Lock {
        path: path.to_owned(),
        lock: lock_path.clone(),
        source,
    };
    let mut file = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&lock_path)
        .map_err(lock_err)?;
    let started = Instant::now();
    let mut on_wait = Some(on_wait);
    loop {
        match Flock::lock(file, FlockArg::LockExclusiveNonblock) {
            Ok(lock) => {
                return Ok(FileLock {
                    _lock: lock,
                    lock_path,
                });
            }
            Err((f, nix::errno::Errno::EWOULDBLOCK)) => {
                if started.elapsed() >= wait {
                    return Err(FileError::Busy {
                        path: path.to_owned(),
                        lock: lock_path,
                        waited_s: wait.as_secs_f64(),
                    });
                }
                if let Some(tell) = on_wait.take() {
                    tell(&lock_path);
                }
                file = f;
                std::thread::sleep(Duration::from_millis(20));
            }
            Err((_, e)) => return Err(lock_err(e.into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_scratch() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        std::fs::write(&p, b"old").unwrap();
        let e = write_atomically(&p, |s| {
            std::fs::write(s, b"half")?;
            Err("disk full".into())
        })
        .unwrap_err();
        assert!(e.to_string().contains("a.csv") && e.to_string().contains("disk full"));
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert!(!scratch_of(&p).unwrap().exists());
    }

    #[test]
    fn permissions_are_kept_and_a_read_only_file_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("store.flash");
        std::fs::write(&p, b"old").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_bytes_atomically(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600);
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o444)).unwrap();
        let e = write_bytes_atomically(&p, b"newer").unwrap_err();
        assert!(matches!(e, FileError::ReadOnly { mode: 0o444, .. }), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
    }

    #[test]
    fn a_second_lock_waits_then_is_refused_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("robot.flash");
        let held = lock_beside(&p, Duration::ZERO, |_| {}).unwrap();
        let mut told = false;
        let e = lock_beside(&p, Duration::from_millis(100), |_| told = true).unwrap_err();
        assert!(told);
        assert!(matches!(e, FileError::Busy { .. }), "{e}");
        assert!(e.to_string().contains("robot.flash"), "{e}");
        drop(held);
        lock_beside(&p, Duration::ZERO, |_| {}).unwrap();
    }
}
