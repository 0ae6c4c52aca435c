//! Telemetry records of the bus loop and the bounded queue that carries them to the link: when the
//! host is slow or absent the queue drops the newest record and counts it, so the bus loop never
//! waits for the host.

use heapless::Deque;

use crate::playback::MAX_JOINTS;
use crate::safety::State;

/// Per-joint flag bits: the protocol's own, so a record's flags go on the link as they are.
pub use protocol::feedback_flags as flags;

/// One joint in a record. Positions in servo ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointSample {
    /// The goal this cycle's Sync Write carried (the held goal when it wrote none).
    pub commanded: i32,
    pub present: i32,
    /// Present Velocity, 0.229 rev/min.
    pub velocity: i32,
    /// Present Load (MX-28, 0.1 %) or Present Current (MX-64).
    pub load: i16,
    /// Status error byte of the reply (0 when none).
    pub error: u8,
    pub flags: u8,
}

/// What one bus cycle saw.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Record {
    /// Start of the cycle, microseconds on the controller's clock.
    pub time_us: u64,
    pub cycle: u32,
    pub state: State,
    /// Steps completed by playback.
    pub step: u32,
    /// Slice the goals were interpolated from.
    pub slice: u16,
    /// A streaming cycle (sent as proprioception): the setpoint its Sync Write carried.
    pub setpoint: Option<SetpointStamp>,
    pub joint_count: u8,
    pub joints: [JointSample; MAX_JOINTS],
    /// Duration of the bus transaction.
    pub cycle_us: u32,
    /// Counters since boot.
    pub timeouts: u32,
    pub crc_errors: u32,
    pub overruns: u32,
    /// The perturbation platform's servo, while one is set up and checked.
    pub platform: Option<PlatformSample>,
    /// Each joint's servo's last heat and supply reading (zeros: not read yet).
    pub health: [protocol::ServoHealth; MAX_JOINTS],
}

/// The platform servo in a record. Positions in servo ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlatformSample {
    pub id: u8,
    /// The goal this cycle's Sync Write carried (the held goal when it wrote none).
    pub goal: u16,
    pub present: u16,
    /// `NO_REPLY`, `CRC_ERROR` of its last reply.
    pub flags: u8,
}

/// A bounded queue that drops instead of blocking.
#[derive(Debug)]
pub struct DropQueue<T, const N: usize> {
    items: Deque<T, N>,
    dropped: u32,
}

impl<T, const N: usize> Default for DropQueue<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T, const N: usize> DropQueue<T, N> {
    pub const fn new() -> Self {
        Self {
            items: Deque::new(),
            dropped: 0,
        }
    }

    /// Queues `item`, or drops it (and counts) when the queue is full. True if queued.
    pub fn push(&mut self, item: T) -> bool {
        match self.items.push_back(item) {
            Ok(()) => true,
            Err(_) => {
                self.dropped = self.dropped.wrapping_add(1);
                false
            }
        }
    }

    pub fn pop(&mut self) -> Option<T> {
        self.items.pop_front()
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Items dropped since creation.
    pub fn dropped(&self) -> u32 {
        self.dropped
    }
}

/// The setpoint a streaming cycle writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SetpointStamp {
    /// The host's sequence number (0 before the first setpoint of the session: the standing goals).
    pub seq: u32,
    /// Cycles the setpoint has been applied, this one included (1 = new since the last cycle).
    pub age: u16,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_queue_drops_the_newest_and_counts_it() {
        let mut q = DropQueue::<u32, 3>::new();
        for i in 0..5 {
            assert_eq!(q.push(i), i < 3);
        }
        assert_eq!(q.dropped(), 2);
        assert_eq!(q.pop(), Some(0));
        assert!(q.push(9));
        let rest: Vec<u32> = core::iter::from_fn(|| q.pop()).collect();
        assert_eq!(rest, [1, 2, 9]);
        assert_eq!(q.dropped(), 2);
    }
}
