//! Serves a [`VirtualChain`] on a pseudo-terminal so that any Dynamixel client (the Python SDK,
//! `dbot dxl`, DYNAMIXEL Wizard through a serial bridge) can talk to it.
//!
//! The slave side is put in raw mode and its path is symlinked at the requested link path; the
//! master side stays open for as long as the server runs (the `/dev/pts/N` node disappears when
//! it closes). Replies are paced at wall-clock wire time: each servo waits its Return Delay Time,
//! then the bytes are written and the server waits 10 bit times per byte at the client's baud.
//! The client's baud is read from the terminal settings it made (Linux `TCGETS2`), so a servo whose
//! Baud Rate register differs from it does not answer, as on a real bus; when the client set no
//! rate the server's own baud is used.

use dynamixel::parser::Parser;
use dynamixel::sim::VirtualChain;
use nix::poll::{PollFd, PollFlags, PollTimeout, poll};
use nix::pty::openpty;
use nix::sys::termios::{SetArg, cfmakeraw, tcgetattr, tcsetattr};
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsFd, AsRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Errors of the pty server.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PtyError {
    #[error("cannot create a pseudo-terminal")]
    Open(#[source] nix::Error),
    #[error("cannot put the pseudo-terminal {slave} in raw mode")]
    Raw { slave: String, source: nix::Error },
    #[error("{link} exists and is not a symlink; refusing to replace it")]
    LinkOccupied { link: PathBuf },
    #[error("cannot create the symlink {link} -> {slave}")]
    Link {
        link: PathBuf,
        slave: String,
        source: std::io::Error,
    },
    #[error("pseudo-terminal I/O failed")]
    Io(#[from] std::io::Error),
    #[error("waiting on the pseudo-terminal failed")]
    Poll(#[source] nix::Error),
}

/// One request the server answered, for its log.
#[derive(Debug, Clone, PartialEq)]
pub struct Served {
    /// Seconds since the server started.
    pub at_s: f64,
    pub id: u8,
    pub instruction: u8,
    pub request_len: usize,
    /// IDs that replied, in wire order.
    pub replied: Vec<u8>,
    /// IDs that would have replied but have the no-reply fault.
    pub silent: Vec<u8>,
    pub baud: u32,
}

/// A pseudo-terminal in raw mode whose slave path is symlinked at a link path; the link is
/// removed when it is dropped. The master is the server's end.
#[derive(Debug)]
pub struct LinkedPty {
    pub master: File,
    slave: Option<OwnedFd>,
    slave_path: String,
    link: PathBuf,
}

impl LinkedPty {
    /// Opens a pseudo-terminal, raw mode, and links its slave path at `link`.
    pub fn open(link: &Path) -> Result<Self, PtyError> {
        let pty = openpty(None, None).map_err(PtyError::Open)?;
        let slave_path = nix::unistd::ttyname(pty.slave.as_fd())
            .map_err(PtyError::Open)?
            .to_string_lossy()
            .into_owned();
        let raw = |e| PtyError::Raw {
            slave: slave_path.clone(),
            source: e,
        };
        let mut t = tcgetattr(pty.slave.as_fd()).map_err(raw)?;
        cfmakeraw(&mut t);
        tcsetattr(pty.slave.as_fd(), SetArg::TCSANOW, &t).map_err(raw)?;
        match std::fs::symlink_metadata(link) {
            Ok(m) if m.file_type().is_symlink() => std::fs::remove_file(link)?,
            Ok(_) => {
                return Err(PtyError::LinkOccupied {
                    link: link.to_path_buf(),
                });
            }
            Err(_) => {}
        }
        std::os::unix::fs::symlink(&slave_path, link).map_err(|source| PtyError::Link {
            link: link.to_path_buf(),
            slave: slave_path.clone(),
            source,
        })?;
        Ok(Self {
            master: File::from(pty.master),
            slave: Some(pty.slave),
            slave_path,
            link: link.to_path_buf(),
        })
    }

    /// The slave's path (`/dev/pts/N`).
    pub fn slave_path(&self) -> &str {
        &self.slave_path
    }

    /// Closes the server's own hold on the slave, so that the master sees a hang-up (POLLHUP,
    /// reads fail with EIO) whenever no client has the port open: how a server can tell a
    /// client's open, as a USB device sees its port opened.
    pub fn close_slave(&mut self) {
        self.slave = None;
    }
}

impl Drop for LinkedPty {
    fn drop(&mut self) {
        // Remove our link only if it still points at our terminal.
        if std::fs::read_link(&self.link).is_ok_and(|t| t == Path::new(&self.slave_path)) {
            let _ = std::fs::remove_file(&self.link);
        }
    }
}

/// A chain served on a pseudo-terminal.
#[derive(Debug)]
pub struct PtyServer {
    // Its slave is kept open so the master never sees a hang-up between clients.
    pty: LinkedPty,
    chain: VirtualChain,
    baud: u32,
}

impl PtyServer {
    /// Opens a pseudo-terminal, raw mode, and links its slave path at `link`.
    pub fn open(chain: VirtualChain, baud: u32, link: &Path) -> Result<Self, PtyError> {
        Ok(Self {
            pty: LinkedPty::open(link)?,
            chain,
            baud,
        })
    }

    pub fn slave_path(&self) -> &str {
        self.pty.slave_path()
    }

    pub fn chain_mut(&mut self) -> &mut VirtualChain {
        &mut self.chain
    }

    /// The baud the client set on its end, or the server's default.
    fn client_baud(&self) -> u32 {
        self.pty
            .slave
            .as_ref()
            .and_then(termios2_speed)
            .unwrap_or(self.baud)
    }

    /// Serves until `stop` is set, calling `log` for every request answered or ignored.
    pub fn serve(
        &mut self,
        stop: &AtomicBool,
        mut log: impl FnMut(&Served),
    ) -> Result<(), PtyError> {
        let start = Instant::now();
        let mut last_physics = Instant::now();
        let mut parser: Parser<1024> = Parser::new();
        let mut last_byte = Instant::now();
        let mut buf = [0u8; 512];
        while !stop.load(Ordering::Relaxed) {
            let mut fds = [PollFd::new(self.pty.master.as_fd(), PollFlags::POLLIN)];
            let ready = match poll(&mut fds, PollTimeout::from(50u16)) {
                Ok(n) => n,
                Err(nix::Error::EINTR) => continue,
                Err(e) => return Err(PtyError::Poll(e)),
            };
            if ready == 0 {
                continue;
            }
            let n = match self.pty.master.read(&mut buf) {
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                // No client has the slave open right now.
                Err(e) if e.raw_os_error() == Some(nix::libc::EIO) => {
                    std::thread::sleep(Duration::from_millis(10));
                    continue;
                }
                Err(e) => return Err(e.into()),
            };
            // A servo drops a half-received packet after a silence (e-manual 1.5 ms; generous here
            // because a USB/pty client may split one packet across writes).
            if last_byte.elapsed() > Duration::from_millis(20) {
                parser.reset();
            }
            last_byte = Instant::now();
            let mut data = &buf[..n];
            while !data.is_empty() {
                let k = parser.feed(data);
                data = &data[k..];
                while let Some(ev) = parser.next_frame() {
                    let Ok(frame) = ev else { continue };
                    if frame.instruction == dynamixel::instruction::STATUS {
                        continue;
                    }
                    self.chain.step(last_physics.elapsed().as_secs_f64());
                    last_physics = Instant::now();
                    let baud = self.client_baud();
                    let planned = self.chain.handle(&frame, baud);
                    let mut served = Served {
                        at_s: start.elapsed().as_secs_f64(),
                        id: frame.id,
                        instruction: frame.instruction,
                        request_len: frame.params.len() + 10,
                        replied: Vec::new(),
                        silent: Vec::new(),
                        baud,
                    };
                    let byte_time = Duration::from_nanos(10_000_000_000 / baud as u64);
                    // An absolute schedule, so that a late wake-up on a busy machine delays one
                    // reply instead of adding up over a 22-servo Sync Read.
                    let mut due = Instant::now();
                    for r in planned {
                        due += Duration::from_micros(r.delay_us as u64);
                        match r.bytes {
                            Some(bytes) => {
                                sleep_until(due);
                                self.pty.master.write_all(&bytes)?;
                                due += byte_time * bytes.len() as u32;
                                served.replied.push(r.id);
                            }
                            None => served.silent.push(r.id),
                        }
                    }
                    sleep_until(due);
                    log(&served);
                }
            }
        }
        Ok(())
    }
}

/// Sleeps until `t` with sub-millisecond accuracy: OS sleep for the bulk, a spin for the rest.
fn sleep_until(t: Instant) {
    let now = Instant::now();
    if t <= now {
        return;
    }
    if t - now > Duration::from_micros(500) {
        std::thread::sleep(t - now - Duration::from_micros(300));
    }
    while Instant::now() < t {
        std::hint::spin_loop();
    }
}

/// The output speed a client set on the terminal, via `TCGETS2` (arbitrary rates such as 1 Mbit/s
/// set with `BOTHER`, as serialport-rs does, are visible there and not through `cfgetospeed`).
#[cfg(target_os = "linux")]
fn termios2_speed(fd: &OwnedFd) -> Option<u32> {
    let mut t2 = std::mem::MaybeUninit::<nix::libc::termios2>::zeroed();
    // SAFETY: TCGETS2 writes one `termios2` through the pointer; the fd is an open tty.
    let rc = unsafe { nix::libc::ioctl(fd.as_raw_fd(), nix::libc::TCGETS2, t2.as_mut_ptr()) };
    if rc != 0 {
        return None;
    }
    // SAFETY: the ioctl succeeded and filled the struct.
    let t2 = unsafe { t2.assume_init() };
    let speed = t2.c_ospeed;
    // A fresh pty reports 38400 until a client sets a rate: treat that as "not set".
    (speed != 0 && speed != 38_400).then_some(speed)
}

#[cfg(not(target_os = "linux"))]
fn termios2_speed(_fd: &OwnedFd) -> Option<u32> {
    None
}
