//! Bus settings a real robot survives (`dbot set --baud/--rate`, Python `Board.set_bus`). The
//! servos keep their own baud (the Baud Rate register, address 8, in EEPROM) whatever the board's
//! UART does, so a baud change of the board alone strands them: the board then hears nothing.
//! A baud change is therefore made and then verified: the board reads every servo of its joint map
//! at the new baud for a few cycles (its Read of the present positions, which faults a servo that
//! misses `miss_limit` replies); if one does not answer, the board is put back on the baud its
//! servos answer at and the change is refused, naming the servo and the command that moves the
//! servos first (`dbot dxl setup --new-baud`, through a U2D2; Python `dbot.Bench`).

use std::time::Duration;

use protocol::RunState;

use super::RuleError;
use crate::link::{Board, Transport};

/// Bus cycles the board is given at the new baud before its servos are checked: the firmware's
/// miss limit (3 missed replies make a `ServoMissing` fault) and three more for the cycles that
/// straddle the switch.
pub const VERIFY_CYCLES: u32 = 6;

/// Sets the bus baud (bit/s) and cycle rate (Hz). A change of baud is verified as the module
/// says, and refused (the board back on its old baud and rate, its fault cleared) when a servo
/// does not answer at the new one.
pub fn set_bus<T: Transport>(
    board: &mut Board<T>,
    baud: u32,
    cycle_hz: u16,
) -> Result<(), RuleError> {
    let before = board.settings()?;
    if baud == before.baud {
        board.set_bus(baud, cycle_hz)?;
        return Ok(());
    }
    if before.joints.is_empty() {
        return Err(RuleError::BaudUnverifiable { baud });
    }
    board.set_bus(baud, cycle_hz)?;
    let cycle_us = 1_000_000 / u64::from(cycle_hz.max(1));
    board.wait(Duration::from_micros(u64::from(VERIFY_CYCLES) * cycle_us))?;
    let status = board.status()?;
    if status.state != RunState::Fault {
        return Ok(());
    }
    // Back to where the servos answer, then out of the fault the switch caused.
    board.set_bus(before.baud, before.cycle_hz)?;
    board.clear_fault()?;
    Err(RuleError::BaudNotFollowed {
        from: before.baud,
        to: baud,
        joint: status.fault.and_then(|f| f.joint),
    })
}
