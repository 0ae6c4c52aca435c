//! The virtual robot's flash as a file, so that `dbot upload` and a later `dbot run` in another
//! process see the same gait store (the run state, like a board's RAM, does not survive).

use std::path::{Path, PathBuf};

use embedded_storage::nor_flash::NorFlash;
use firmware::store::FlashWindow;

use super::flash::{FLASH_SECTORS, VirtualFlash};

/// Why the image could not be read or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    #[error("{path}: cannot read the virtual robot's flash image: {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: cannot write the virtual robot's flash image: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Read-only, in use by another process, or in a directory where its lock cannot be made.
    #[error("the virtual robot's flash image: {0}")]
    File(#[from] crate::files::FileError),
    #[error("{path}: {len} bytes is not a flash image of this virtual robot ({expected} bytes)")]
    Size {
        path: PathBuf,
        len: usize,
        expected: usize,
    },
}

/// Bytes of an image.
pub const IMAGE_LEN: usize = FLASH_SECTORS * firmware::store::nor_double::SECTOR;

/// How long a command waits for another one using the same image before it gives up.
pub const LOCK_WAIT: std::time::Duration = std::time::Duration::from_secs(30);

/// Opens the image at `path` for one command: refuses a read-only file (it could not be saved,
/// and a rename would replace it anyway), takes the image's lock so that commands on the same
/// image run one after another (each loads the flash the previous one saved; without it the last
/// to exit overwrote an upload made meanwhile), then loads it. Hold the lock until after [`save`].
pub fn open(path: &Path) -> Result<(VirtualFlash, crate::files::FileLock), ImageError> {
    crate::files::check_writable(path)?;
    let lock = crate::files::lock_beside(path, LOCK_WAIT, |lock| {
        // The library prints nothing else; a command that seems to hang must say why.
        eprintln!(
            "{}: in use by another dbot (lock {}): waiting up to {} s",
            path.display(),
            lock.display(),
            LOCK_WAIT.as_secs()
        );
    })?;
    Ok((load(path)?, lock))
}

/// The flash stored at `path`, or an erased flash when there is no file yet.
pub fn load(path: &Path) -> Result<VirtualFlash, ImageError> {
    let mut flash = VirtualFlash::new(FLASH_SECTORS);
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(flash),
        Err(source) => {
            return Err(ImageError::Read {
                path: path.to_owned(),
                source,
            });
        }
    };
    if bytes.len() != IMAGE_LEN {
        return Err(ImageError::Size {
            path: path.to_owned(),
            len: bytes.len(),
            expected: IMAGE_LEN,
        });
    }
    // Programming an erased flash with the image reproduces it bit for bit (0xFF stays erased).
    flash
        .write(0, &bytes)
        .expect("an image of the flash's own size programs an erased flash");
    Ok(flash)
}

/// Writes `flash` to `path` through [`crate::files::write_atomically`]: a crash or a kill leaves
/// the old image, the file keeps its permissions, a read-only file is refused. (The scratch name
/// is derived from the whole file name: `path.with_extension("tmp")` would be the image itself
/// for `robot.tmp`, and shared by `robot.flash` and `robot.img`.)
pub fn save(path: &Path, flash: &VirtualFlash) -> Result<(), ImageError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| ImageError::Write {
            path: path.to_owned(),
            source,
        })?;
    }
    Ok(crate::files::write_bytes_atomically(path, flash.window())?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_save_that_fails_leaves_the_previous_image_even_when_named_like_a_scratch_file() {
        // `robot.tmp`: the old scratch name (`with_extension("tmp")`) was the image itself, so a
        // save cut short destroyed the image it was replacing.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("robot.tmp");
        let mut a = VirtualFlash::new(FLASH_SECTORS);
        a.write(0, &[1, 2, 3, 4]).unwrap();
        save(&path, &a).unwrap();
        let mut b = VirtualFlash::new(FLASH_SECTORS);
        b.write(0, &[9, 9, 9, 9]).unwrap();
        // The scratch file is the OS's to name now (`board::files`), so it can no longer be the
        // image. A save refused (the image made read-only: refused up front whoever runs it,
        // root too) names the image, leaves it A, whole, and leaves no scratch file.
        use std::os::unix::fs::PermissionsExt as _;
        let perms = |mode| std::fs::Permissions::from_mode(mode);
        std::fs::set_permissions(&path, perms(0o444)).unwrap();
        let e = save(&path, &b).unwrap_err();
        assert!(e.to_string().contains("robot.tmp"), "{e}");
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), IMAGE_LEN);
        assert_eq!(&bytes[..5], &[1, 2, 3, 4, 0xFF]);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        std::fs::set_permissions(&path, perms(0o644)).unwrap();
        save(&path, &b).unwrap();
        assert_eq!(&std::fs::read(&path).unwrap()[..4], &[9, 9, 9, 9]);
    }
}
