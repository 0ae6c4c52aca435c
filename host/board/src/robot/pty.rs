//! A virtual robot served on a pseudo-terminal as its USB port (`dbot sim-bus --physics`): the
//! firmware library's board and whatever moves its servos (the physics robot's body) behind a
//! `/dev/pts/N` linked at a path, so any client of the board's link (`dbot record --port PATH`,
//! Python's `Board`) opens it as it opens `/dev/ttyACM0`, and a second process can serve another
//! device of the same body beside it (its strain board).
//!
//! Simulated time is paced to the wall clock: the robot runs a bus cycle at a time and the server
//! sleeps while the simulation is ahead of the time since it started (never behind it by choice:
//! a machine too slow to keep up runs it as fast as it can). It runs whether or not a client has
//! the port open, as the board does on its USB power; what it sends while no client listens, or
//! more than the terminal's buffer holds for a client that does not read, is dropped.

use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use nix::poll::{PollFd, PollFlags, PollTimeout, poll};

use super::{ServoDynamics, VirtualTransport};
use crate::bus::pty::{LinkedPty, PtyError};
use crate::link::Transport;

/// The simulated time a step of the server advances at most, and so the latency it adds.
const STEP: Duration = Duration::from_millis(1);

/// A virtual robot on a pseudo-terminal.
#[derive(Debug)]
pub struct RobotPtyServer<S: ServoDynamics + std::fmt::Debug> {
    pty: LinkedPty,
    transport: VirtualTransport<S>,
}

impl<S: ServoDynamics + std::fmt::Debug> RobotPtyServer<S> {
    /// Opens a pseudo-terminal linked at `link` for `transport`'s robot.
    pub fn open(transport: VirtualTransport<S>, link: &Path) -> Result<Self, PtyError> {
        let mut pty = LinkedPty::open(link)?;
        pty.close_slave();
        // Writes never wait for a client that does not read (or has gone): see `serve`.
        let flags = nix::fcntl::fcntl(pty.master.as_fd(), nix::fcntl::FcntlArg::F_GETFL)
            .map_err(PtyError::Poll)?;
        let flags = nix::fcntl::OFlag::from_bits_truncate(flags) | nix::fcntl::OFlag::O_NONBLOCK;
        nix::fcntl::fcntl(pty.master.as_fd(), nix::fcntl::FcntlArg::F_SETFL(flags))
            .map_err(PtyError::Poll)?;
        Ok(Self { pty, transport })
    }

    pub fn slave_path(&self) -> &str {
        self.pty.slave_path()
    }

    /// The robot served.
    pub fn transport(&self) -> &VirtualTransport<S> {
        &self.transport
    }

    /// Runs the robot and carries the link's bytes both ways until `stop` is set.
    pub fn serve(&mut self, stop: &AtomicBool) -> Result<(), PtyError> {
        let start = Instant::now();
        let t0 = self.transport.now();
        let mut buf = vec![0u8; 4096];
        while !stop.load(Ordering::Relaxed) {
            let client = self.read_client(&mut buf)?;
            let n = self
                .transport
                .recv(&mut buf, STEP)
                .map_err(|e| PtyError::Io(std::io::Error::other(e.to_string())))?;
            if n > 0 && client {
                self.write_client(&buf[..n]);
            }
            let ahead = (self.transport.now() - t0).saturating_sub(start.elapsed());
            if !ahead.is_zero() {
                std::thread::sleep(ahead);
            }
        }
        Ok(())
    }

    /// Writes what the robot sent to the client; what the terminal cannot take now (a client
    /// that stopped reading, or went away between the poll and the write) is dropped.
    fn write_client(&mut self, mut bytes: &[u8]) {
        while !bytes.is_empty() {
            match (&self.pty.master).write(bytes) {
                Ok(0) | Err(_) => return,
                Ok(k) => bytes = &bytes[k..],
            }
        }
    }

    /// Hands what the client wrote to the robot; whether a client has the port open.
    fn read_client(&mut self, buf: &mut [u8]) -> Result<bool, PtyError> {
        let mut fds = [PollFd::new(self.pty.master.as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, PollTimeout::ZERO) {
            Ok(_) => {}
            Err(nix::Error::EINTR) => return Ok(true),
            Err(e) => return Err(PtyError::Poll(e)),
        }
        let ev = fds[0].revents().unwrap_or(PollFlags::empty());
        if ev.contains(PollFlags::POLLIN) {
            match (&self.pty.master).read(buf) {
                Ok(n) if n > 0 => self
                    .transport
                    .send(&buf[..n])
                    .map_err(|e| PtyError::Io(std::io::Error::other(e.to_string())))?,
                Ok(_) => return Ok(false),
                Err(e) if e.raw_os_error() == Some(nix::libc::EIO) => return Ok(false),
                Err(e) => return Err(PtyError::Io(e)),
            }
            return Ok(true);
        }
        Ok(!ev.contains(PollFlags::POLLHUP))
    }
}
