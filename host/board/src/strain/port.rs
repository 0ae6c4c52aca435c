//! Opening the strain board by name: a serial device path, or `virtual` (a virtual strain board
//! in this process, on a socket pair, paced like the real one), and the check that the strain
//! port is not the servo board's.

use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use super::error::StrainError;
use super::source::{Constant, Shared};
use super::virtual_board::VirtualStrainBoard;

/// A byte stream to a strain board.
pub trait StrainIo: Read + Write + Send {}
impl<T: Read + Write + Send> StrainIo for T {}

/// The port name of the in-process virtual strain board.
pub const VIRTUAL: &str = "virtual";

/// Opens `name`: `virtual`, or a serial port's path.
pub fn open(name: &str) -> Result<Box<dyn StrainIo>, StrainError> {
    open_fed(name, None)
}

/// [`open`], the virtual board's gauges reading `feed` when given (else zero strain).
pub fn open_fed(name: &str, feed: Option<Shared>) -> Result<Box<dyn StrainIo>, StrainError> {
    if name == VIRTUAL {
        let source: Box<dyn super::source::StrainSource> = match feed {
            Some(f) => Box::new(f),
            None => Box::new(Constant(0.0)),
        };
        return open_virtual(VirtualStrainBoard::new(source, Vec::new(), true)).map_err(|source| {
            StrainError::Open {
                port: name.to_owned(),
                source,
            }
        });
    }
    Ok(Box::new(super::driver::open_serial(name)?))
}

/// `board` served on a socket pair in a thread of its own; the thread ends when the returned end
/// is dropped.
pub fn open_virtual(mut board: VirtualStrainBoard) -> std::io::Result<Box<dyn StrainIo>> {
    let (host, mut dev) = UnixStream::pair()?;
    host.set_read_timeout(Some(Duration::from_millis(20)))?;
    dev.set_read_timeout(Some(Duration::from_millis(1)))?;
    std::thread::spawn(move || {
        let never = AtomicBool::new(false);
        let _ = board.serve(&mut dev, &never);
    });
    Ok(Box::new(host))
}

/// Refuses a strain port that is the servo board's port `servo` (the same path, or two names
/// of the same device). The virtual strain board is never the servo board.
pub fn check_not_servo_port(strain: &str, servo: &str) -> Result<(), StrainError> {
    // `virtual` names two different things: the in-process strain board and the virtual robot.
    let same = strain != VIRTUAL
        && (strain == servo
            || matches!(
                (Path::new(strain).canonicalize(), Path::new(servo).canonicalize()),
                (Ok(a), Ok(b)) if a == b
            ));
    if same {
        return Err(StrainError::ServoPort {
            port: strain.to_owned(),
        });
    }
    Ok(())
}
