//! Stopping a walk: the one stop path of every command and binding that starts one (`dbot run`,
//! `dbot record --play`, Python's `Board.stop`), so all stop the same way and say the same.
//! Walking, the board finishes its step; ramping to the first slice, it holds where the ramp got
//! to (firmware `safety`); streaming, it holds the last setpoint; standing or idle, there is
//! nothing to stop.

use protocol::{ProtocolError, RunState};

use crate::link::{Board, LinkError, Transport};

/// What a stop request found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stopped {
    /// Walking: the board finishes the step it is in, then stands.
    AtEndOfStep,
    /// Ramping to the gait's first slice: the board stands where the ramp got to (no step walked).
    RampHeld,
    /// Following streamed setpoints: the board left streaming, holding the last setpoint.
    StreamingEnded,
    /// Not walking (standing, idle, booting, in a fault): nothing to stop.
    NotWalking,
}

impl Stopped {
    /// What the stop did, for a message.
    pub fn describe(self) -> &'static str {
        match self {
            Stopped::AtEndOfStep => "the walk was stopped at the end of its step",
            Stopped::RampHeld => {
                "the ramp to the gait's first slice was stopped where it got to (no step walked)"
            }
            Stopped::StreamingEnded => "streaming was ended, holding the last setpoint",
            Stopped::NotWalking => "the robot was not walking",
        }
    }
}

/// Asks the board to stop walking ([`Stopped`] says how it does). A board that refuses because it
/// is not walking (booting, in a fault) has nothing to stop; any other failure is returned.
pub fn stop_walk<T: Transport>(board: &mut Board<T>) -> Result<Stopped, LinkError> {
    let before = board.status()?.state;
    match board.stop() {
        Ok(())
        | Err(LinkError::Device {
            error: ProtocolError::WrongState { .. },
            ..
        })
        // The link's name for a refusal in state Fault (it looks the fault up).
        | Err(LinkError::Faulted { .. }) => {}
        Err(e) => return Err(e),
    }
    let after = board.status()?.state;
    Ok(match (before, after) {
        (_, RunState::Stopping) => Stopped::AtEndOfStep,
        (RunState::Ramping, _) => Stopped::RampHeld,
        // The walk ended between the two looks (its last step, or the ramp ended and the stop
        // then came while walking): either way the board stands after its step.
        (RunState::Walking | RunState::Stopping, _) => Stopped::AtEndOfStep,
        (RunState::Streaming, _) => Stopped::StreamingEnded,
        // Boot, Idle, Standing, Fault, and any state a newer firmware adds (`RunState` is
        // `#[non_exhaustive]`).
        _ => Stopped::NotWalking,
    })
}
