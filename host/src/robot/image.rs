//! The virtual robot's flash as a file, so that `dbot upload` and a later `dbot run` in another
//! process see the same gait store (the run state, like a board's RAM, does not survive).

use std::path::{Path, PathBuf};

use embedded_storage::nor_flash::NorFlash;
use firmware::store::FlashWindow;

use super::board::{FLASH_SECTORS, VirtualFlash};

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
    #[error("{path}: {len} bytes is not a flash image of this virtual robot ({expected} bytes)")]
    Size {
        path: PathBuf,
        len: usize,
        expected: usize,
    },
}

/// Bytes of an image.
pub const IMAGE_LEN: usize = FLASH_SECTORS * firmware::store::nor_double::SECTOR;

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

/// Writes `flash` to `path` (through a temporary file, so a crash leaves the old image).
pub fn save(path: &Path, flash: &VirtualFlash) -> Result<(), ImageError> {
    let err = |source| ImageError::Write {
        path: path.to_owned(),
        source,
    };
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(err)?;
    }
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, flash.window()).map_err(err)?;
    std::fs::rename(&tmp, path).map_err(err)
}
