//! The device log: every state change and every safety fault of the controller, one line each,
//! logged with defmt over RTT (`probe-rs run` shows them; the HIL tests decode them from the
//! emulator's RAM). The controller calls [`transition`] wherever its state changes, so this file
//! is the one place that decides what is logged and at which level.
//!
//! The defmt calls exist only in the image (feature `defmt`, which is on by default, on the
//! RP2040): a host build has no global logger to link them against. Host tests read the same
//! calls back from a per-thread trail instead ([`trail`]).

use crate::safety::{Event, State};

/// What moved the controller from one state to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Cause {
    /// An event of the state machine (a host command, the bus loop, a fault).
    Event(Event),
    /// A gait with other servo IDs was selected: the controller looks for its servos (Idle to Boot).
    NewJointMap,
    /// The faulted servo's Hardware Error Status was read: the fault now carries its bits.
    ErrorBits,
}

/// Logs the move from `from` to `to`. Called with `from == to` only for a fault that changed
/// nothing (the first fault stays the one reported): such a fault is logged once per state, not
/// again while its joint goes on reporting the same kind of fault every bus cycle.
pub fn transition(from: State, to: State, cause: Cause) {
    let kept_fault = match cause {
        Cause::Event(Event::Fault(reason)) if from == to => Some(reason),
        _ if from == to => return,
        _ => None,
    };
    let new = match kept_fault {
        // Not logged yet in this state, and not the very fault the state holds.
        Some(reason) => !seen::insert(reason),
        None => {
            seen::clear();
            if let State::Safe(reason) = to {
                seen::insert(reason);
            }
            true
        }
    };
    if new {
        emit(from, to, cause, kept_fault.is_some());
    }
}

/// One log line: faults and entering Safe or EStop at warn, other changes at info.
fn emit(from: State, to: State, cause: Cause, kept_fault: bool) {
    #[cfg(all(feature = "defmt", target_os = "none"))]
    match (kept_fault, to) {
        (true, _) => defmt::warn!("fault {} while {}: the first fault stays", cause, from),
        (false, State::Safe(_) | State::EStop) => {
            defmt::warn!("state {} -> {} on {}", from, to, cause)
        }
        (false, _) => defmt::info!("state {} -> {} on {}", from, to, cause),
    }
    #[cfg(test)]
    trail::push(trail::Entry { from, to, cause });
    let _ = (from, to, cause, kept_fault);
}

/// Logs a copy of a gait slot that the store found damaged at mount and did not use: the slot fell
/// back to the older table (seq `current`) or, with no valid copy left, is empty. At warn: the board
/// will play a gait other than the one last uploaded.
pub fn store_copy_lost(slot: u8, lost: crate::store::lost::LostCopy, current: Option<u32>) {
    #[cfg(all(feature = "defmt", target_os = "none"))]
    match current {
        Some(seq) => defmt::warn!(
            "gait slot {}: fell back to seq {}, the newer copy {} was lost",
            slot,
            seq,
            lost
        ),
        None => defmt::warn!("gait slot {}: no valid copy, damaged data {}", slot, lost),
    }
    let _ = (slot, lost, current);
}

/// The faults logged since the last state change, one bit per kind and joint. The board has one
/// controller, so one set is enough (host tests: one per thread).
mod seen {
    use crate::safety::SafeReason;

    const KINDS: usize = 5;

    /// Which word and bit stand for `reason`.
    fn slot(reason: SafeReason) -> (usize, u32) {
        let (kind, joint) = match reason {
            SafeReason::ServoError { joint, .. } => (0, joint),
            SafeReason::ServoMissing { joint, .. } => (1, joint),
            SafeReason::ServoStuck { joint, .. } => (2, joint),
            SafeReason::SetpointTimeout => (3, 0),
            SafeReason::Watchdog => (4, 0),
        };
        // MAX_JOINTS is 32: a joint index always fits a word.
        (kind, 1 << (joint % 32))
    }

    #[cfg(not(test))]
    static SEEN: [core::sync::atomic::AtomicU32; KINDS] =
        [const { core::sync::atomic::AtomicU32::new(0) }; KINDS];

    #[cfg(test)]
    std::thread_local! {
        static SEEN: [core::cell::Cell<u32>; KINDS] = const { [const { core::cell::Cell::new(0) }; KINDS] };
    }

    /// Marks `reason` as logged; true if it already was.
    #[cfg(not(test))]
    pub(super) fn insert(reason: SafeReason) -> bool {
        use core::sync::atomic::Ordering::Relaxed;
        let (kind, bit) = slot(reason);
        // Load and store (thumbv6m has no atomic read-modify-write); the controller is behind a
        // mutex, so nothing else writes in between.
        let old = SEEN[kind].load(Relaxed);
        SEEN[kind].store(old | bit, Relaxed);
        old & bit != 0
    }

    #[cfg(test)]
    pub(super) fn insert(reason: SafeReason) -> bool {
        let (kind, bit) = slot(reason);
        let old = SEEN.with(|s| s[kind].replace(s[kind].get() | bit));
        old & bit != 0
    }

    /// Forgets every fault (the state changed).
    pub(super) fn clear() {
        #[cfg(not(test))]
        for w in &SEEN {
            w.store(0, core::sync::atomic::Ordering::Relaxed);
        }
        #[cfg(test)]
        SEEN.with(|s| s.iter().for_each(|w| w.set(0)));
    }
}

/// What [`transition`] logged on this thread, for host tests.
#[cfg(test)]
pub mod trail {
    use std::cell::RefCell;
    use std::vec::Vec;

    use super::Cause;
    use crate::safety::State;

    /// One logged line.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub struct Entry {
        pub from: State,
        pub to: State,
        pub cause: Cause,
    }

    std::thread_local! {
        static TRAIL: RefCell<Vec<Entry>> = const { RefCell::new(Vec::new()) };
    }

    pub(super) fn push(e: Entry) {
        TRAIL.with(|t| t.borrow_mut().push(e));
    }

    /// The lines logged since the last call.
    pub fn take() -> Vec<Entry> {
        TRAIL.with(|t| core::mem::take(&mut *t.borrow_mut()))
    }
}

#[cfg(test)]
#[path = "device_log_tests.rs"]
mod tests;
