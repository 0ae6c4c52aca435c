//! `dbot upload`: sends a step table to a gait slot, with a progress bar, verification, and a
//! report of what the slot held before. Ctrl-C before the commit aborts the upload (the slot keeps
//! its table) and exits non-zero; a killed upload never commits, so the board keeps it too.

use std::path::PathBuf;

use anyhow::{Context, bail};
use board::link::LinkError;
use indicatif::{ProgressBar, ProgressStyle};
use planner::plan_dir;

use crate::args::board::BoardArgs;
use crate::common::interrupt;
use board::slot_health::describe;

/// Upload a step table into a gait slot of the board (verified after the upload).
///
/// Ctrl-C before the upload commits aborts it: the slot keeps its previous table.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot upload --table walk.dbgt --slot 1
  dbot upload --plan out/walk --slot 2 --port virtual:lab.flash --create")]
#[group(id = "source", required = true, multiple = false)]
pub struct Args {
    /// Step table file (as written by `dbot table`), checked by the same rules before the board
    /// is touched: a table the servos cannot follow (one built with --allow-infeasible) needs
    /// --allow-infeasible here too, a stiffness a servo's P gain cannot hold is refused.
    #[arg(long, group = "source")]
    pub table: Option<PathBuf>,
    /// Plan directory (as written by `dbot plan` or `dbot demo`); the step table is built from it
    /// first, as `dbot table --plan` builds it (same bytes, same name and CRC).
    #[arg(long, group = "source")]
    pub plan: Option<PathBuf>,
    #[command(flatten)]
    pub slot: crate::args::board::GaitSlotArgs,
    #[command(flatten)]
    pub board: BoardArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        // A plan is built under the rules (slot capacity, servo feasibility unless overridden)
        // before the board is touched; a table file is checked by the same rules with the same
        // override (a table built with --allow-infeasible needs it again here).
        let overrides = self.slot.feasibility.overrides();
        let checked = match (&self.table, &self.plan) {
            (Some(path), _) => {
                let bytes = std::fs::read(path)
                    .with_context(|| format!("reading the step table {}", path.display()))?;
                protocol::GaitTable::parse(&bytes)
                    .with_context(|| format!("{} is not a valid step table", path.display()))?;
                let setup = self.board.setup()?;
                let model = crate::common::model_spec::load_model(
                    setup.model.as_deref().unwrap_or("drosophibot2"),
                )?;
                board::rules::build::table_bytes(
                    bytes,
                    &format!("step table {}", path.display()),
                    &model,
                    overrides,
                )?
            }
            (None, Some(dir)) => {
                let plan = plan_dir::read(dir)?;
                board::rules::build::plan_dir_table(&plan, None, overrides)?
            }
            (None, None) => bail!("give --table FILE or --plan DIR"),
        };
        crate::feasibility_args::warn(checked.warning());
        let table = checked.bytes();
        interrupt::catch()?;
        let mut s = self.board.connect()?;
        let slot = self.slot.slot(&s.setup);
        let bar = ProgressBar::new(table.len() as u64).with_style(
            ProgressStyle::with_template("uploading {bar:40} {bytes}/{total_bytes} {msg}")
                .expect("template is valid"),
        );
        // For tests: DBOT_TEST_HOLD_AFTER_CHUNK=N holds the upload after its Nth chunk until a
        // signal comes, so a Ctrl-C or a kill lands mid-upload whatever the machine's load.
        let hold: Option<u32> = std::env::var("DBOT_TEST_HOLD_AFTER_CHUNK")
            .ok()
            .and_then(|v| v.parse().ok());
        let mut chunks = 0;
        let progress = |sent, _| {
            bar.set_position(u64::from(sent));
            chunks += 1;
            if hold == Some(chunks) {
                eprintln!("held after chunk {chunks}");
                while !interrupt::requested() {
                    std::thread::sleep(std::time::Duration::from_millis(5));
                }
            }
        };
        let report = board::rules::upload::upload_checked(
            &mut s.board,
            slot,
            &checked,
            progress,
            interrupt::requested,
        );
        bar.finish_and_clear();
        if let Err(e @ LinkError::UploadInterrupted { .. }) = report {
            // The aborted session ends cleanly (the virtual robot keeps its flash as it is now).
            s.close()?;
            bail!("interrupted: {e}");
        }
        let report = report.with_context(|| format!("uploading into slot {slot}"))?;
        let before = match report.replaced {
            None => "  the slot was empty".to_owned(),
            Some(old) if old == report.stored => "  replaced an identical table".to_owned(),
            Some(old) => format!("  replaced: {}", describe(&old)),
        };
        // The board has committed the table; the virtual robot stores it only when its image is
        // saved, at close. Success is said once the data is stored, not before.
        s.close()?;
        println!(
            "slot {slot}: {} ({} bytes in {} chunks, verified: header and CRC {:#010x} read back)",
            describe(&report.stored),
            report.bytes,
            report.chunks,
            report.stored.crc
        );
        println!("{before}");
        Ok(())
    }
}
