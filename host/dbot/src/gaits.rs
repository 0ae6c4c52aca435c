//! `dbot gaits`: what each gait slot of the board holds, and what a damaged slot lost.

use crate::args::board::BoardArgs;
use board::slot_health;

/// Runs the command on the board `board` names.
pub fn run(board: BoardArgs) -> anyhow::Result<()> {
    let mut s = board.connect()?;
    let slots = s.board.gaits()?;
    if let Some(line) = slot_health::store_line(&slots) {
        println!("{line}");
    }
    for slot in &slots {
        println!("{}", slot_health::slot_line(slot));
    }
    s.close()
}
