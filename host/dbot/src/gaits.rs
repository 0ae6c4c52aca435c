//! `dbot gaits`: what each gait slot of the board holds, and what a damaged slot lost.

use crate::args::board::BoardArgs;
use board::slot_health;

/// List the board's gait slots.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot gaits
  dbot gaits --port virtual:lab.flash")]
pub struct Args {
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let mut s = self.board.connect()?;
        let slots = s.board.gaits()?;
        if let Some(line) = slot_health::store_line(&slots) {
            println!("{line}");
        }
        for slot in &slots {
            println!("{}", slot_health::slot_line(slot));
        }
        s.close()
    }
}
