//! Checks that the bench's port can be a serial port before it is opened, so that a mistyped
//! path says what it is instead of the terminal layer's "Not a typewriter" (ENOTTY): `dbot dxl`
//! and Python's `dbot.Bench` alike, since the bench checks before it opens its port.

use std::os::unix::fs::FileTypeExt as _;
use std::path::Path;

use super::BenchError;

/// Fails with what `port` is when it cannot be a serial port: missing, a directory, a regular file,
/// or a device that is not a terminal (such as /dev/null).
pub fn check_serial_path(port: &Path) -> Result<(), BenchError> {
    let shown = port.display();
    let not = |message: String| BenchError::NotSerialPort {
        port: shown.to_string(),
        message,
    };
    let meta = std::fs::metadata(port).map_err(|_| {
        not(format!("{shown}: no such serial port (a U2D2 is usually /dev/ttyUSB0; `dbot sim-bus --link PATH` serves virtual servos at PATH)"))
    })?;
    let ft = meta.file_type();
    if ft.is_dir() {
        return Err(not(format!("{shown} is a directory, not a serial port")));
    }
    if ft.is_file() {
        return Err(not(format!(
            "{shown} is a regular file, not a serial port (a U2D2 is usually /dev/ttyUSB0)"
        )));
    }
    if ft.is_char_device() {
        let f = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(port)
            .map_err(|e| not(format!("cannot open {shown}: {e}")))?;
        if !nix::unistd::isatty(&f).unwrap_or(false) {
            return Err(not(format!(
                "{shown} is a device but not a serial port (not a terminal)"
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dev_null_a_file_a_directory_and_a_missing_path_are_named() {
        let e = check_serial_path(Path::new("/dev/null")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "/dev/null is a device but not a serial port (not a terminal)"
        );
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("notes.txt");
        std::fs::write(&file, "x").unwrap();
        let e = check_serial_path(&file).unwrap_err();
        assert!(
            e.to_string()
                .contains("is a regular file, not a serial port"),
            "{e}"
        );
        let e = check_serial_path(dir.path()).unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
        let e = check_serial_path(&dir.path().join("ttyUSB9")).unwrap_err();
        assert!(e.to_string().contains("no such serial port"), "{e}");
    }
}
