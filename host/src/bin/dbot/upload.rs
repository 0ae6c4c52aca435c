//! `dbot upload`: sends a step table to a gait slot, with a progress bar, verification, and a
//! report of what the slot held before.

use std::path::PathBuf;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};
use protocol::GaitSummary;

use crate::board_args::BoardArgs;

/// Upload a step table into a gait slot of the board (verified after the upload).
#[derive(Debug, clap::Args)]
#[group(id = "source", required = true, multiple = false)]
pub struct Args {
    /// Step table file (as written by `dbot table`).
    #[arg(long, group = "source")]
    pub table: Option<PathBuf>,
    /// Plan directory (as written by `dbot plan`); the step table is built from it first.
    #[arg(long, group = "source")]
    pub plan: Option<PathBuf>,
    /// Gait slot to fill (default: the setup file's slot, else 0).
    #[arg(long)]
    pub slot: Option<u8>,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let table = match (&self.table, &self.plan) {
            (Some(path), _) => std::fs::read(path)
                .with_context(|| format!("reading the step table {}", path.display()))?,
            (None, Some(dir)) => bail!(
                "{}: building a step table from a plan is `dbot table --plan DIR --out FILE` \
                 (dynamics), not wired into `dbot upload` in this build; run it and pass --table FILE",
                dir.display()
            ),
            (None, None) => bail!("give --table FILE or --plan DIR"),
        };
        protocol::GaitTable::parse(&table).with_context(|| {
            format!(
                "{} is not a valid step table",
                self.table
                    .as_deref()
                    .unwrap_or(std::path::Path::new("?"))
                    .display()
            )
        })?;
        let mut s = self.board.connect()?;
        let slot = self.slot.or(s.setup.slot).unwrap_or(0);
        let bar = ProgressBar::new(table.len() as u64).with_style(
            ProgressStyle::with_template("uploading {bar:40} {bytes}/{total_bytes} {msg}")
                .expect("template is valid"),
        );
        let report = s
            .board
            .upload(slot, &table, |sent, _| bar.set_position(u64::from(sent)))
            .with_context(|| format!("uploading into slot {slot}"));
        bar.finish_and_clear();
        let report = report?;
        println!(
            "slot {slot}: {} ({} bytes in {} chunks, verified: header and CRC {:#010x} read back)",
            describe(&report.stored),
            report.bytes,
            report.chunks,
            report.stored.crc
        );
        match report.replaced {
            None => println!("  the slot was empty"),
            Some(old) if old == report.stored => println!("  replaced an identical table"),
            Some(old) => println!("  replaced: {}", describe(&old)),
        }
        s.close()
    }
}

/// One line about a stored gait: name, shape, timing, CRC.
pub fn describe(g: &GaitSummary) -> String {
    let h = &g.header;
    format!(
        "\"{}\" {} joints x {} slices, step {:.3} s, duty {:.2}, CRC {:#010x}",
        h.name_str().unwrap_or("(name not UTF-8)"),
        h.joint_count,
        h.slice_count,
        f64::from(h.step_period_us) * 1e-6,
        f64::from(h.duty) * 1e-4,
        g.crc
    )
}
