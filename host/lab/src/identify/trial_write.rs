//! A [`Recording`] written as a trial folder (trial.json and telemetry.csv, and strain.csv with
//! strain_baseline.csv when it has strain, the format
//! `board::trial::read_trial` reads; the telemetry without the later optional columns), so the
//! stand-in's recordings go through `dbot identify`, `dbot replay` and Python as a lab's do.
//! The trial.json says it is the stand-in's (port `stand-in`, firmware `0.0.0`, notes).

use std::fmt::Write;
use std::path::{Path, PathBuf};

use board::trial::{BoardSettings, FirmwareMeta, GaitMeta, Outcome, TrialMeta};
use planner::model::Model;

use super::recording::Recording;
use crate::error::{Context, Result};

/// Writes `rec` (of `model`'s joints) as the trial folder `parent/<rec.name>`; returns its path.
pub fn write_trial(rec: &Recording, model: &Model, parent: &Path) -> Result<PathBuf> {
    let dir = parent.join(&rec.name);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let header = &board::record::CSV_HEADER[..board::record::CSV_HEADER_BEFORE_PLATFORM];
    let mut csv = header.join(",") + "\n";
    for c in 0..rec.len() {
        for jt in &rec.joints {
            let map = model.joints[jt.joint].servo.expect("a servo joint");
            let torque = f64::from(map.sign)
                * f64::from(dynamixel::units::load_to_torque_nm(
                    map.model,
                    jt.load_raw[c],
                ));
            let _ = writeln!(
                csv,
                "{:.6},{c},0,0,{},,{:.6},{:.6},{:.6},{},{torque:.6},,0,0,10000",
                rec.t[c], jt.name, jt.goal[c], jt.q[c], jt.qd[c], jt.load_raw[c]
            );
        }
    }
    let meta = TrialMeta {
        format_version: board::trial::TRIAL_FORMAT,
        folder: rec.name.clone(),
        outcome: Outcome::Complete,
        fault: None,
        started: "1970-01-01T00:00:00Z".into(),
        host_version: env!("CARGO_PKG_VERSION").into(),
        command_line: vec!["lab::identify::stand_in".into()],
        port: "stand-in".into(),
        firmware: FirmwareMeta {
            version: "0.0.0".into(),
            protocol_version: 0,
            table_format_version: 0,
            build_id: 0,
        },
        settings: BoardSettings {
            bus_baud: 1_000_000,
            cycle_hz: 100,
            telemetry_every: 1,
            joints: Vec::new(),
        },
        gait: Some(GaitMeta {
            slot: None,
            name: rec.name.clone(),
            crc: 0,
            joints: rec.joints.len() as u8,
            slices: 1,
            step_period_s: rec.t.last().copied().unwrap_or(0.0),
            duty: 0.5,
        }),
        plan: None,
        direction: None,
        period_scale: None,
        steps: None,
        substrate: board::trial::Substrate::Unspecified,
        strain: rec.strain.is_some(),
        perturbation: None,
        notes: format!(
            "The stand-in robot's recording ({}), made by lab::identify::stand_in, not a board.",
            if rec.suspended {
                "suspended"
            } else {
                "standing"
            }
        ),
        joints: rec.joints.iter().map(|j| j.name.clone()).collect(),
        cycles: rec.len(),
        duration_s: rec.t.last().copied().unwrap_or(0.0),
        missing_records: 0,
        lost_records: Some(0),
    };
    let mut files = vec![
        (board::trial::TELEMETRY_CSV, csv),
        (board::trial::TRIAL_JSON, meta.to_json()),
    ];
    if let Some(s) = &rec.strain {
        let mut csv = format!("time_s,{}\n", s.names.join(","));
        for (t, row) in s.t.iter().zip(&s.counts) {
            let cells: Vec<String> = row.iter().map(f64::to_string).collect();
            let _ = writeln!(csv, "{t:.6},{}", cells.join(","));
        }
        files.push((board::strain::recorder::STRAIN_CSV, csv));
        let method = if s.baseline_first_sample {
            board::strain::baseline::BaselineMethod::FirstSample
        } else {
            board::strain::baseline::BaselineMethod::MeanOfUnloaded
        };
        let cells: Vec<String> = s.baseline.iter().map(f64::to_string).collect();
        files.push((
            board::strain::recorder::BASELINE_CSV,
            format!(
                "method,{}\n{},{}\n",
                s.names.join(","),
                method.name(),
                cells.join(",")
            ),
        ));
    }
    for (name, text) in files {
        let path = dir.join(name);
        board::files::write_bytes_atomically(&path, text.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(dir)
}
