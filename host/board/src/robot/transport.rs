//! The virtual robot behind the [`Transport`] seam. Time passes only while the host waits for bytes,
//! in simulated time: a reply timeout of 2 s is 2 s of the robot's life, not of the host's.
//!
//! For tests, the link can be cut after a number of host bytes or at a simulated time, the way a
//! USB cable is pulled: the robot (and its flash) carries on, the host sees the board vanish.

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::board::VirtualRobot;
use super::image::{self, ImageError};
use super::servos::{PlannedLoads, ServoDynamics};
use crate::link::{Transport, TransportError};

/// Writes a transport's flash to its image file.
type SaveFn<S> = fn(&mut VirtualTransport<S>) -> Result<(), ImageError>;

/// A link to an in-process [`VirtualRobot`] (whose servos any [`ServoDynamics`] moves, e.g. the
/// physics crate's MuJoCo body), optionally backed by a flash image file (planned loads only).
#[derive(Debug)]
pub struct VirtualTransport<S: ServoDynamics = PlannedLoads> {
    robot: VirtualRobot<S>,
    name: String,
    image: Option<PathBuf>,
    /// Writes the flash back to `image` at shutdown (set with the image).
    save_at_shutdown: Option<SaveFn<S>>,
    /// Held from load to the last save: one command at a time on an image.
    image_lock: Option<crate::files::FileLock>,
    cut_after_sent: Option<usize>,
    cut_at_us: Option<u64>,
    sent: usize,
    closed: bool,
}

impl<S: ServoDynamics> VirtualTransport<S> {
    /// A link to `robot`.
    pub fn new(robot: VirtualRobot<S>) -> Self {
        Self::named(robot, "virtual")
    }

    /// A link to `robot` called `name` in messages.
    pub fn named(robot: VirtualRobot<S>, name: &str) -> Self {
        Self {
            robot,
            name: name.to_owned(),
            image: None,
            save_at_shutdown: None,
            image_lock: None,
            cut_after_sent: None,
            cut_at_us: None,
            sent: 0,
            closed: false,
        }
    }

    pub fn robot(&self) -> &VirtualRobot<S> {
        &self.robot
    }

    pub fn robot_mut(&mut self) -> &mut VirtualRobot<S> {
        &mut self.robot
    }

    pub fn into_robot(self) -> VirtualRobot<S> {
        self.robot
    }

    /// The link drops once the host has sent `bytes` more bytes (the send that crosses the limit
    /// delivers its bytes up to it and fails).
    pub fn cut_after_sent(&mut self, bytes: usize) {
        self.cut_after_sent = Some(self.sent + bytes);
    }

    /// The link drops when the robot's clock reaches `t_us`.
    pub fn cut_at_us(&mut self, t_us: u64) {
        self.cut_at_us = Some(t_us);
    }

    fn closed_error(&self) -> TransportError {
        TransportError::Closed {
            reason: format!(
                "{}: link cut at t = {:.3} s",
                self.name,
                self.robot.now_us() as f64 * 1e-6
            ),
        }
    }
}

impl VirtualTransport {
    /// A robot that boots from the flash image at `path` (an erased flash if the file does not
    /// exist yet); [`Self::save`] writes its flash back there.
    pub fn with_image(path: &Path) -> Result<Self, ImageError> {
        let (flash, lock) = image::open(path)?;
        let mut t = Self::new(VirtualRobot::with_flash(flash));
        t.name = format!("virtual:{}", path.display());
        t.image = Some(path.to_owned());
        t.image_lock = Some(lock);
        t.save_at_shutdown = Some(Self::save);
        Ok(t)
    }

    /// Writes the robot's flash to its image file, if it has one. The robot reboots from that
    /// flash afterwards (its run state is lost, as at power-off).
    pub fn save(&mut self) -> Result<(), ImageError> {
        let Some(path) = self.image.clone() else {
            return Ok(());
        };
        let flash = std::mem::take(&mut self.robot).into_flash();
        let result = image::save(&path, &flash);
        self.robot = VirtualRobot::with_flash(flash);
        result
    }
}

impl<S: ServoDynamics + std::fmt::Debug> Transport for VirtualTransport<S> {
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        if self.closed {
            return Err(self.closed_error());
        }
        let allowed = self.cut_after_sent.map_or(bytes.len(), |limit| {
            limit.saturating_sub(self.sent).min(bytes.len())
        });
        self.robot.receive(&bytes[..allowed]);
        self.sent += allowed;
        if allowed < bytes.len() || self.cut_after_sent == Some(self.sent) {
            self.closed = true;
            return Err(self.closed_error());
        }
        Ok(())
    }

    fn recv(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, TransportError> {
        // Rounded up to the robot's whole microseconds: a timeout shorter than one (what is left
        // of a deadline between two ticks) still lets time reach it, or the caller's loop on
        // `now() < deadline` would wait forever.
        let timeout_us = u64::try_from(timeout.as_nanos().div_ceil(1000)).unwrap_or(u64::MAX);
        let deadline = self.robot.now_us().saturating_add(timeout_us);
        loop {
            if self.closed {
                return Err(self.closed_error());
            }
            if self.robot.pending() > 0 {
                return Ok(self.robot.take(buf));
            }
            let next = self.robot.next_cycle_us();
            if let Some(cut) = self.cut_at_us
                && cut <= next.min(deadline)
            {
                self.robot.run_until(cut);
                self.closed = true;
                continue;
            }
            if next > deadline {
                self.robot.run_until(deadline);
                return Ok(0);
            }
            self.robot.cycle();
        }
    }

    fn name(&self) -> &str {
        &self.name
    }

    fn now(&self) -> Duration {
        Duration::from_micros(self.robot.now_us())
    }

    fn shutdown(&mut self) -> Result<(), TransportError> {
        let Some(save) = self.save_at_shutdown else {
            return Ok(());
        };
        save(self).map_err(|e| TransportError::Io(std::io::Error::other(e.to_string())))
    }
}
