//! A pseudo-terminal whose far end is a byte stream: the emulated board's USB CDC-ACM link shows up
//! as `/dev/pts/N`, so `dbot --port /dev/pts/N` talks to it exactly as to `/dev/ttyACM0`.
//!
//! The slave side is put in raw mode (no echo, no line editing, no CR/LF translation) and one slave
//! descriptor stays open here, so the master never reads EIO while no client has the port open.
//! Two threads copy bytes between the master and the stream.

use anyhow::{Context, Result};
use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
use nix::pty::openpty;
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsFd, AsRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A pty bridged to a stream; dropping it stops the copying.
#[derive(Debug)]
pub struct PtyBridge {
    path: PathBuf,
    _slave: OwnedFd,
    stop: Arc<AtomicBool>,
}

impl PtyBridge {
    /// Opens a pty and copies between its master and `stream` (both directions) until dropped.
    pub fn new<S>(stream: S) -> Result<Self>
    where
        S: Read + Write + Send + 'static + TryCloneStream,
    {
        let pty = openpty(None, None).context("openpty failed")?;
        let mut termios = tcgetattr(pty.slave.as_fd()).context("tcgetattr on the pty")?;
        cfmakeraw(&mut termios);
        tcsetattr(pty.slave.as_fd(), SetArg::TCSANOW, &termios).context("tcsetattr on the pty")?;
        let path = std::fs::read_link(format!("/proc/self/fd/{}", pty.slave.as_raw_fd()))
            .context("cannot find the pty's device path")?;
        let stop = Arc::new(AtomicBool::new(false));
        let master = File::from(pty.master);
        let mut to_stream = stream.try_clone_stream()?;
        let mut from_stream = stream;
        let mut master_w = master.try_clone().context("dup of the pty master")?;
        let stop_r = stop.clone();
        std::thread::spawn(move || {
            let mut master = master;
            let mut buf = [0u8; 4096];
            while !stop_r.load(Ordering::Relaxed) {
                let mut fds = [PollFd::new(master.as_fd(), PollFlags::POLLIN)];
                match poll(&mut fds, PollTimeout::from(100u16)) {
                    Ok(0) => continue,
                    Ok(_) => {}
                    Err(_) => break,
                }
                match master.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => {
                        if to_stream.write_all(&buf[..n]).is_err() {
                            break;
                        }
                    }
                }
            }
        });
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            loop {
                match from_stream.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => {
                        if master_w.write_all(&buf[..n]).is_err() {
                            break;
                        }
                    }
                }
            }
        });
        Ok(Self {
            path,
            _slave: pty.slave,
            stop,
        })
    }

    /// The device path to open, e.g. `/dev/pts/7`.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for PtyBridge {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// Streams that can be split into a reading and a writing handle.
pub trait TryCloneStream: Sized {
    /// A second handle on the same stream.
    fn try_clone_stream(&self) -> Result<Self>;
}

impl TryCloneStream for std::os::unix::net::UnixStream {
    fn try_clone_stream(&self) -> Result<Self> {
        self.try_clone().context("cannot clone the Unix socket")
    }
}
