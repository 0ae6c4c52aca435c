//! The identification's report: `report.md` (per joint the estimates with their standard
//! deviations, what was not identified and why, and recorded against replayed before and after
//! in numbers) and one plot per recording (`replay-<trial>.png`: recorded, replayed before and
//! after, per joint).

use std::fmt::Write;
use std::path::Path;

use super::Identification;
use crate::error::{Context, Result};

/// Writes the report of `id` into `dir` (created), returning the files written.
pub fn write_report(id: &Identification, dir: &Path) -> Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut files = Vec::new();
    for (b, a) in id.before.iter().zip(&id.after) {
        let path = dir.join(format!("replay-{}.png", sanitise(&b.trial)));
        let panels: Vec<report::replay::Panel> = b
            .joints
            .iter()
            .zip(&a.joints)
            .map(|(jb, ja)| report::replay::Panel {
                title: jb.joint.clone(),
                recorded: jb.q_recorded.clone(),
                curves: vec![
                    ("before".to_owned(), jb.q_replayed.clone()),
                    ("after".to_owned(), ja.q_replayed.clone()),
                ],
            })
            .collect();
        report::replay::plot_panels(&path, &format!("{}: position, rad", b.trial), &b.t, &panels)
            .map_err(|e| crate::LabError::invalid(format!("plotting {}: {e}", path.display())))?;
        files.push(path);
    }
    let path = dir.join("report.md");
    std::fs::write(&path, markdown(id)).with_context(|| format!("writing {}", path.display()))?;
    files.push(path);
    Ok(files)
}

fn sanitise(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The report's text.
pub fn markdown(id: &Identification) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Identification: {}\n", id.model.name);
    let _ = writeln!(
        s,
        "Optimiser: Levenberg-Marquardt (levenberg-marquardt 0.15), ended {}{}; {} replays in \
         all. Standard deviations from the Jacobian at the point kept.\n",
        id.termination,
        if id.refinement.is_empty() {
            ""
        } else {
            ", then per joint Nelder-Mead (argmin 0.11) from where it ended"
        },
        id.replays
    );
    if !id.refinement.is_empty() {
        let _ = writeln!(
            s,
            "## Refinement (Nelder-Mead per joint)\n\n| joint | cost after Levenberg-Marquardt | \
             after Nelder-Mead | replays | kept |\n|---|---|---|---|---|"
        );
        for r in &id.refinement {
            let _ = writeln!(s, "| {} |", refinement_cells(r).join(" | "));
        }
        let _ = writeln!(
            s,
            "\nCost: the joint's squared residuals (position per tick, velocity per 4 units of \
             0.229 rev/min) summed over the trials that move it.\n"
        );
    }
    let _ = writeln!(
        s,
        "## Estimates\n\n| joint | field | start | fitted | sd | note |\n|---|---|---|---|---|---|"
    );
    for e in &id.estimates {
        let _ = writeln!(
            s,
            "| {} | {} | {:.5} | {:.5} {} | {} | {} |",
            e.joint,
            e.field,
            e.start,
            e.value,
            e.unit,
            e.sd.map_or("-".to_owned(), |v| format!("{v:.2e}")),
            e.why.as_deref().unwrap_or("")
        );
    }
    let _ = writeln!(s, "\n## Not identified\n");
    for (f, why) in &id.not_identified {
        let _ = writeln!(s, "- `{f}`: {why}");
    }
    let _ = writeln!(s, "\n## Recorded against replayed\n");
    for (b, a) in id.before.iter().zip(&id.after) {
        let _ = writeln!(s, "Before (the model given):\n\n```\n{}```\n", b.table());
        let _ = writeln!(s, "After (the fitted model):\n\n```\n{}```\n", a.table());
    }
    s
}

/// One joint's refinement as cells: the joint, its cost before and after, the replays, the
/// outcome. The report's table and the command's summary both show these.
fn refinement_cells(r: &super::refine::JointRefinement) -> [String; 5] {
    [
        r.joint.clone(),
        format!("{:.1}", r.cost_before),
        format!("{:.1}", r.cost_after),
        r.replays.to_string(),
        (if r.kept { "refined" } else { "as before" }).to_owned(),
    ]
}

/// Makes the folder the fitted model `out` goes into (with its parents) and refuses an `out`
/// that cannot be replaced (`board::files::check_writable`, as the write itself would): called
/// before a fit too, so that such a location fails at once and not after the minutes of fitting
/// (`dbot identify`, `dbot.identify`).
pub fn prepare_out(out: &Path) -> Result<()> {
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| {
            format!(
                "--out {}: making its folder {}",
                out.display(),
                dir.display()
            )
        })?;
    }
    board::files::check_writable(out).with_context(|| format!("--out {}", out.display()))
}

/// Writes the fitted model of `id` to `out` (TOML, atomically) and its report into the folder
/// beside it, `<out without .toml>-report/`; returns what to print: the files and, per
/// recording, the position RMS before and after.
pub fn write_outputs(id: &Identification, out: &Path) -> Result<String> {
    let notes = format!(
        "Identified (lab::identify) from: {}. Each fitted joint's values are its servo_dynamics \
         overrides, a fitted ground friction is foot_friction; see the report beside this file.",
        id.before
            .iter()
            .map(|r| r.trial.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let text = planner::model::to_toml_string(&id.model, &notes, &|_| String::new());
    prepare_out(out)?;
    board::files::write_bytes_atomically(out, text.as_bytes())
        .with_context(|| format!("writing {}", out.display()))?;
    let stem = out.with_extension("");
    let dir = std::path::PathBuf::from(format!("{}-report", stem.display()));
    let files = write_report(id, &dir)?;
    let mut s = format!("fitted model: {}\n", out.display());
    for f in files {
        let _ = writeln!(s, "report: {}", f.display());
    }
    for (b, a) in id.before.iter().zip(&id.after) {
        let _ = writeln!(
            s,
            "{}: position RMS {:.2} mrad before, {:.2} mrad after",
            b.trial,
            b.position_rms_rad() * 1e3,
            a.position_rms_rad() * 1e3
        );
    }
    for r in &id.refinement {
        let [joint, before, after, replays, outcome] = refinement_cells(r);
        let _ = writeln!(
            s,
            "{joint}: refinement cost {before} -> {after} ({replays} replays, {outcome})"
        );
    }
    if let Some(f) = id.friction.as_ref().filter(|f| f.why.is_none()) {
        let _ = writeln!(
            s,
            "ground friction (foot_friction): {:.3} (sd {:.1e}; started at {:.2})",
            f.value,
            f.sd.unwrap_or(f64::NAN),
            f.start
        );
    }
    for (f, _) in &id.not_identified {
        let _ = writeln!(s, "not identified: {f} (why: report.md)");
    }
    let _ = writeln!(
        s,
        "load readings now calibrated (fitted gain and offset) for {} joint(s)",
        id.estimates
            .iter()
            .filter(|e| e.field == "load_gain")
            .count()
    );
    Ok(s)
}

#[cfg(test)]
mod tests {
    #[test]
    fn an_out_that_cannot_be_written_is_refused_before_the_fit_and_a_missing_folder_is_made() {
        let dir = tempfile::tempdir().unwrap();
        let nested = dir.path().join("a/b/fitted.toml");
        super::prepare_out(&nested).unwrap();
        assert!(dir.path().join("a/b").is_dir());
        // A folder where the file should go: the write would fail after the fit.
        let e = super::prepare_out(dir.path().join("a").as_path()).unwrap_err();
        assert!(e.to_string().contains("--out"), "{e}");
    }
}
