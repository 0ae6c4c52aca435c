//! A virtual strain board served on a pseudo-terminal (`dbot sim-strain`). Like the Arduino
//! Mega, which resets when its port is opened, the board starts afresh (banner, calibration) each
//! time a client opens the port: the server holds no fd of the slave, so the master sees a
//! hang-up while no client has it open and the hang-up clears on an open.

use std::fs::File;
use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsFd;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use nix::poll::{PollFd, PollFlags, PollTimeout, poll};

use super::virtual_board::{Ended, VirtualStrainBoard};
use crate::bus::pty::{LinkedPty, PtyError};

/// Time from a client's open to the banner: the client sets raw mode first (an Arduino Mega's
/// bootloader takes about 2 s; shorter here so tests run quickly).
pub const BOOT_DELAY: Duration = Duration::from_millis(200);

/// A virtual strain board on a pseudo-terminal.
#[derive(Debug)]
pub struct StrainPtyServer {
    pty: LinkedPty,
    board: VirtualStrainBoard,
}

impl StrainPtyServer {
    /// Opens a pseudo-terminal linked at `link`.
    pub fn open(board: VirtualStrainBoard, link: &Path) -> Result<Self, PtyError> {
        let mut pty = LinkedPty::open(link)?;
        pty.close_slave();
        Ok(Self { pty, board })
    }

    pub fn slave_path(&self) -> &str {
        self.pty.slave_path()
    }

    /// Serves one client session after another until `stop` is set or a hang-up fault ends the
    /// board (returned as [`Ended::HungUp`]); `log` hears how each session ended.
    pub fn serve(
        &mut self,
        stop: &AtomicBool,
        mut log: impl FnMut(&Ended),
    ) -> Result<Ended, PtyError> {
        while !stop.load(Ordering::Relaxed) {
            if !client_present(&self.pty.master)? {
                std::thread::sleep(Duration::from_millis(20));
                continue;
            }
            std::thread::sleep(BOOT_DELAY);
            let mut end = MasterEnd(&self.pty.master);
            let ended = self.board.serve(&mut end, stop)?;
            log(&ended);
            match ended {
                Ended::HostGone => {}
                Ended::Stopped | Ended::HungUp(_) => return Ok(ended),
            }
        }
        Ok(Ended::Stopped)
    }
}

/// Whether a client has the slave open (no hang-up on the master).
fn client_present(master: &File) -> Result<bool, PtyError> {
    let mut fds = [PollFd::new(master.as_fd(), PollFlags::POLLIN)];
    match poll(&mut fds, PollTimeout::from(20u16)) {
        Ok(_) => {}
        Err(nix::Error::EINTR) => return Ok(false),
        Err(e) => return Err(PtyError::Poll(e)),
    }
    let ev = fds[0].revents().unwrap_or(PollFlags::empty());
    Ok(!ev.contains(PollFlags::POLLHUP))
}

/// The master as the board's byte stream: reads wait at most 1 ms (then `TimedOut`), and a
/// hang-up (the client closed the port) reads as end of file.
struct MasterEnd<'a>(&'a File);

impl Read for MasterEnd<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let mut fds = [PollFd::new(self.0.as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, PollTimeout::from(1u16)) {
            Ok(_) => {}
            Err(nix::Error::EINTR) => return Err(ErrorKind::Interrupted.into()),
            Err(e) => return Err(std::io::Error::from(e)),
        }
        let ev = fds[0].revents().unwrap_or(PollFlags::empty());
        if ev.contains(PollFlags::POLLIN) {
            return match (&mut &*self.0).read(buf) {
                Err(e) if e.raw_os_error() == Some(nix::libc::EIO) => Ok(0),
                r => r,
            };
        }
        if ev.contains(PollFlags::POLLHUP) {
            return Ok(0);
        }
        Err(ErrorKind::TimedOut.into())
    }
}

impl Write for MasterEnd<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        (&mut &*self.0).write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
