//! The excitation trials' files (`dbot excite`): one step table per trial of
//! `planner::excitation`, built under the board's rules
//! (`board::rules::build::excitation_table`), as `DIR/NAME.dbgt`, and `DIR/excitation.json`
//! (what each joint does when). Each file is written atomically.

use std::fmt::Write;
use std::path::Path;

use planner::excitation::{ExcitationKind, ExcitationOptions, excitation};
use planner::model::Model;

use crate::error::{Context, Result};

/// Writes the excitation of `kind` for `model` into `out` (created); returns one line per table
/// (its file, slices, period and size).
pub fn write_excitation(model: &Model, kind: ExcitationKind, out: &Path) -> Result<String> {
    let exc = excitation(model, kind, &ExcitationOptions::default())
        .with_context(|| format!("the {kind} excitation of the model {}", model.name))?;
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut said = String::new();
    for trial in &exc.trials {
        let table = board::rules::build::excitation_table(model, trial)?;
        let path = out.join(format!("{}.dbgt", trial.name));
        board::files::write_bytes_atomically(&path, table.bytes())
            .with_context(|| format!("writing {}", path.display()))?;
        let _ = writeln!(
            said,
            "{}: {} slices, period {:.1} s, {} bytes",
            path.display(),
            trial.slices(),
            trial.period_s(),
            table.bytes().len()
        );
    }
    let json = serde_json::to_string_pretty(&exc).context("excitation.json")?;
    let path = out.join("excitation.json");
    board::files::write_bytes_atomically(&path, json.as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(said)
}
