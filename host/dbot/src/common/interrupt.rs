//! Ctrl-C (SIGINT) and SIGTERM for the commands that move the robot or write a recording.
//!
//! Only commands that check [`requested`] install the handler ([`catch`]): the others keep the
//! default action (the process ends at once; their outputs go through scratch files, so nothing
//! is half-written). The first signal only sets a flag, so the command can stop the robot at the
//! end of its step, finish its files and exit non-zero saying so; a second one ends the process
//! at once (exit 130), for a user who will not wait. While a walk may be under way and the board
//! has not yet been asked to stop ([`hold`] .. [`release`]), the second signal waits for that
//! request: a user pressing Ctrl-C twice in a row must not leave the robot walking.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use anyhow::Context as _;
use nix::sys::signal::{SaFlags, SigAction, SigHandler, SigSet, Signal, sigaction};

/// Signals received since [`catch`].
static RECEIVED: AtomicUsize = AtomicUsize::new(0);

/// Whether a second signal may end the process at once (see [`hold`]).
static MAY_EXIT: AtomicBool = AtomicBool::new(true);

/// Exit status of a process ended by a second Ctrl-C (128 + SIGINT, as a shell reports it).
const EXIT_INTERRUPTED: i32 = 130;

extern "C" fn on_signal(_: nix::libc::c_int) {
    if RECEIVED.fetch_add(1, Ordering::SeqCst) >= 1 && MAY_EXIT.load(Ordering::SeqCst) {
        const MSG: &[u8] = b"\ninterrupted twice: exiting now\n";
        // SAFETY: write(2) and _exit(2) are async-signal-safe; MSG is a valid buffer.
        unsafe {
            nix::libc::write(2, MSG.as_ptr().cast(), MSG.len());
            nix::libc::_exit(EXIT_INTERRUPTED);
        }
    }
}

/// From now on SIGINT and SIGTERM set the flag [`requested`] instead of ending the process.
pub fn catch() -> anyhow::Result<()> {
    let handler = SigAction::new(
        SigHandler::Handler(on_signal),
        // Restart interrupted reads and writes: the command notices the flag at its next check.
        SaFlags::SA_RESTART,
        SigSet::empty(),
    );
    for sig in [Signal::SIGINT, Signal::SIGTERM] {
        // SAFETY: the handler only touches an atomic and calls async-signal-safe functions.
        unsafe { sigaction(sig, &handler) }.context("cannot install the Ctrl-C handler")?;
    }
    Ok(())
}

/// Whether Ctrl-C (or SIGTERM) arrived since [`catch`].
pub fn requested() -> bool {
    RECEIVED.load(Ordering::SeqCst) > 0
}

/// From now on a second signal does not end the process until [`release`]: the robot may be
/// walking and the board has not been asked to stop yet.
pub fn hold() {
    MAY_EXIT.store(false, Ordering::SeqCst);
}

/// The board has been asked to stop (or nothing moves): a second signal ends the process at once
/// again, and if it already came, the process ends now.
pub fn release() {
    MAY_EXIT.store(true, Ordering::SeqCst);
    if RECEIVED.load(Ordering::SeqCst) >= 2 {
        eprintln!(
            "interrupted twice: the board was asked to stop at the end of the step; exiting now"
        );
        std::process::exit(EXIT_INTERRUPTED);
    }
}
