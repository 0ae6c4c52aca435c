//! `phase_torques.csv`: every experiment's per-slice statistics ([`PhaseRow`]), the one file the
//! figures and the docs/validation.md block are drawn from. Numbers carry 5 decimals (0.01 mN m,
//! finer than the 1 mN m of the step table's torques) and are read back before anything uses
//! them, so a block rendered right after a run equals one rendered later from the file.

use std::path::Path;

use crate::bail;
use crate::error::{Context, Result};

use super::experiment::PhaseRow;

pub const FILE: &str = "phase_torques.csv";
const HEADER: &str = "experiment,joint,slice,slices,stance,planned_nm,mean_nm,sd_nm,samples";

pub fn write(path: &Path, rows: &[PhaseRow]) -> Result<()> {
    let mut s = String::from(HEADER);
    s.push('\n');
    for r in rows {
        s += &format!(
            "{},{},{},{},{},{:.5},{:.5},{:.5},{}\n",
            r.experiment,
            r.joint,
            r.slice,
            r.slices,
            u8::from(r.stance),
            r.planned_nm,
            r.mean_nm,
            r.sd_nm,
            r.n
        );
    }
    std::fs::write(path, s).with_context(|| format!("writing {}", path.display()))
}

pub fn read(path: &Path) -> Result<Vec<PhaseRow>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(HEADER) {
        bail!("{}: line 1 is not the header `{HEADER}`", path.display());
    }
    lines
        .enumerate()
        .map(|(i, line)| {
            let at = || format!("{} line {}", path.display(), i + 2);
            let f: Vec<&str> = line.split(',').collect();
            if f.len() != 9 {
                bail!("{}: {} fields, expected 9", at(), f.len());
            }
            let num = |k: usize, name: &str| -> Result<f64> {
                f[k].parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .with_context(|| format!("{}: field {name} `{}` is not a number", at(), f[k]))
            };
            let int = |k: usize, name: &str| -> Result<usize> {
                f[k].parse::<usize>()
                    .with_context(|| format!("{}: field {name} `{}` is not a count", at(), f[k]))
            };
            Ok(PhaseRow {
                experiment: f[0].to_owned(),
                joint: f[1].to_owned(),
                slice: int(2, "slice")?,
                slices: int(3, "slices")?,
                stance: int(4, "stance")? == 1,
                planned_nm: num(5, "planned_nm")?,
                mean_nm: num(6, "mean_nm")?,
                sd_nm: num(7, "sd_nm")?,
                n: int(8, "samples")?,
            })
        })
        .collect()
}
