//! `dbot gaits`: what each gait slot of the board holds.

use crate::args::board::BoardArgs;

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
        for slot in s.board.gaits()? {
            match slot.gait {
                None => println!("slot {}: empty", slot.slot),
                Some(g) => println!(
                    "slot {}: {}",
                    slot.slot,
                    crate::common::gait_summary::describe(&g)
                ),
            }
        }
        s.close()
    }
}
