//! `dbot upload`: sends a step table to a gait slot, with a progress bar, verification, and a
//! report of what the slot held before. Ctrl-C before the commit aborts the upload (the slot keeps
//! its table) and exits non-zero; a killed upload never commits, so the board keeps it too.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use board::link::LinkError;
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::board::BoardArgs;
use crate::common::gait_summary::describe;
use crate::common::interrupt;

/// Upload a step table into a gait slot of the board (verified after the upload).
///
/// Ctrl-C before the upload commits aborts it: the slot keeps its previous table.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  dbot upload --table walk.dbgt --slot 1
  dbot upload --plan out/walk --slot 2 --port virtual:lab.flash --create")]
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
    #[command(flatten)]
    pub feasibility: crate::feasibility_args::FeasibilityArgs,
}

impl Args {
    pub fn run(self) -> anyhow::Result<()> {
        let table = match (&self.table, &self.plan) {
            (Some(path), _) => std::fs::read(path)
                .with_context(|| format!("reading the step table {}", path.display()))?,
            (None, Some(dir)) => table_from_plan_dir(dir, &self.feasibility)?,
            (None, None) => bail!("give --table FILE or --plan DIR"),
        };
        protocol::GaitTable::parse(&table).with_context(|| match (&self.table, &self.plan) {
            (Some(p), _) => format!("{} is not a valid step table", p.display()),
            (None, p) => format!(
                "the step table built from {} is not valid",
                p.as_deref().unwrap_or(Path::new("?")).display()
            ),
        })?;
        interrupt::catch()?;
        let mut s = self.board.connect()?;
        let slot = self.slot.or(s.setup.slot).unwrap_or(0);
        let bar = ProgressBar::new(table.len() as u64).with_style(
            ProgressStyle::with_template("uploading {bar:40} {bytes}/{total_bytes} {msg}")
                .expect("template is valid"),
        );
        let report = s.board.upload_unless(
            slot,
            &table,
            |sent, _| bar.set_position(u64::from(sent)),
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

/// The step table of a plan directory written by `dbot plan`: its plan.json names the model, the
/// stepping parameters and the dynamics options, so the plan and its inverse dynamics are solved
/// again (deterministically) and checked against the recorded slice count and period.
fn table_from_plan_dir(
    dir: &Path,
    feasibility: &crate::feasibility_args::FeasibilityArgs,
) -> anyhow::Result<Vec<u8>> {
    let path = dir.join("plan.json");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).with_context(|| format!("{}: not JSON", path.display()))?;
    let field = |name: &str| {
        json.get(name).with_context(|| {
            format!(
                "{}: no `{name}` field (written by `dbot plan`?)",
                path.display()
            )
        })
    };
    let model_name = json
        .get("model_source")
        .or_else(|| json.get("model"))
        .and_then(|v| v.as_str())
        .with_context(|| format!("{}: no `model_source` or `model` field", path.display()))?;
    let model = crate::spring_args::SpringArgs::from_json(json.get("spring_args"))?
        .apply(crate::common::model_spec::load_model(model_name)?)?;
    let params: planner::gait::StepParams = serde_json::from_value(field("parameters")?.clone())
        .with_context(|| {
            format!(
                "{}: `parameters` are not stepping parameters",
                path.display()
            )
        })?;
    let d = json.get("dynamics").with_context(|| {
        format!(
            "{}: no `dynamics` (planned with --no-dynamics?): the table needs torques",
            path.display()
        )
    })?;
    let flag = |k: &str| d.get(k).and_then(|v| v.as_bool()).unwrap_or(false);
    let args = crate::args::dynamics::DynamicsArgs {
        no_dynamics: false,
        friction_cone: flag("friction_cone"),
        push_only: flag("push_only"),
        mu: d.get("mu").and_then(|v| v.as_f64()).unwrap_or(0.5),
        torque_limits: flag("torque_limits_enforced"),
        parallel: true,
    };
    let plan = planner::plan::plan(&model, &params)
        .with_context(|| format!("re-planning {}", path.display()))?;
    if let Some(n) = json.get("slices").and_then(|v| v.as_u64())
        && n as usize != plan.slices()
    {
        bail!(
            "{}: {} slices recorded, re-planning gives {}",
            path.display(),
            n,
            plan.slices()
        );
    }
    let dynamics = args.solve(&plan)?.context("inverse dynamics")?;
    let torque = planner::dynamics::output::torque_rows(&dynamics.cycle);
    let check = planner::plan::feasibility::check(&plan.model, &plan.q, Some(&torque), plan.dt);
    feasibility.enforce(&check, &format!("plan {}", dir.display()))?;
    let (table, _) = crate::common::step_table::step_table(&plan, &dynamics)?;
    eprintln!(
        "built the step table from {} ({} slices, period {:.3} s, re-solved)",
        path.display(),
        plan.slices(),
        plan.period_s
    );
    Ok(table)
}
