//! A trial's README.md: what the lab's trial READMEs say (direction, substrate, step period,
//! strain yes/no, perturbation, notes), then the gait, board and host, then the telemetry
//! columns. Written from the same [`TrialMeta`] as trial.json, so the two cannot disagree.

use std::fmt::Write as _;

use protocol::Direction;

use super::meta::TrialMeta;
use crate::record::TELEMETRY_README;

/// A firmware build id as the README says it: the commit's first 8 hex digits, or that it is
/// unknown (0: a firmware built outside a git checkout).
fn build_words(id: u32) -> String {
    if id == 0 {
        "unknown".to_owned()
    } else {
        format!("{id:08x}")
    }
}

/// The README of the trial `meta` describes.
pub(super) fn readme(m: &TrialMeta) -> String {
    let mut s = String::new();
    let yes_no = |b: bool| if b { "yes" } else { "no" };
    let _ = writeln!(s, "# Trial {}\n", m.folder);
    let _ = writeln!(s, "- outcome: {}", m.outcome.name());
    if let Some(f) = &m.fault {
        let _ = writeln!(
            s,
            "- fault: {}{}{}",
            f.reason,
            f.joint_name
                .as_ref()
                .map_or(String::new(), |n| format!(" (joint {n})")),
            f.cycle
                .map_or(String::new(), |c| format!(", first seen in bus cycle {c}"))
        );
    }
    let _ = writeln!(s, "- started: {} (UTC)", m.started);
    let _ = writeln!(
        s,
        "- direction: {}",
        m.direction
            .map_or("not started by this command", Direction::name)
    );
    let _ = writeln!(s, "- substrate: {}", m.substrate.name());
    match (&m.gait, m.period_scale) {
        (Some(g), Some(k)) => {
            let _ = writeln!(
                s,
                "- step period: {:.3} s ({k:.3} x the planned {:.3} s)",
                g.step_period_s * k,
                g.step_period_s
            );
        }
        (Some(g), None) => {
            let _ = writeln!(s, "- step period: planned {:.3} s", g.step_period_s);
        }
        (None, _) => {
            let _ = writeln!(s, "- step period: unknown (no gait known)");
        }
    }
    let _ = writeln!(s, "- strain recorded: {}", yes_no(m.strain));
    let _ = writeln!(
        s,
        "- perturbation: {}",
        m.perturbation
            .as_ref()
            .map_or("none".to_owned(), |p| format!(
                "leg {} at step {}, platform{} {} -> {} ticks",
                p.leg,
                p.step,
                p.platform_id
                    .map_or(String::new(), |id| format!(" servo ID {id},")),
                p.rest,
                p.moved_to
            ))
    );
    let _ = writeln!(
        s,
        "- notes: {}",
        if m.notes.is_empty() { "-" } else { &m.notes }
    );
    let _ = writeln!(s, "\n## Gait, board, host\n");
    match &m.gait {
        Some(g) => {
            let _ = writeln!(
                s,
                "- gait: {} (CRC {:08x}), {} joints x {} slices, duty {:.2}{}",
                g.name,
                g.crc,
                g.joints,
                g.slices,
                g.duty,
                g.slot.map_or(String::new(), |k| format!(", slot {k}"))
            );
        }
        None => {
            let _ = writeln!(s, "- gait: unknown");
        }
    }
    if let Some(p) = &m.plan {
        let _ = writeln!(
            s,
            "- plan: {} (model {} from {}, model.toml CRC {})",
            p.dir, p.model, p.model_source, p.model_crc
        );
    }
    let _ = writeln!(
        s,
        "- firmware {} (protocol {}, build {}) on {}",
        m.firmware.version,
        m.firmware.protocol_version,
        build_words(m.firmware.build_id),
        m.port
    );
    let _ = writeln!(
        s,
        "- bus {} bit/s at {} Hz, telemetry every {} cycle(s); stiffness and limits per joint in trial.json",
        m.settings.bus_baud, m.settings.cycle_hz, m.settings.telemetry_every
    );
    let _ = writeln!(
        s,
        "- recorded {} bus cycles ({:.2} s of board time); {}",
        m.cycles,
        m.duration_s,
        crate::record::missing_words(m.missing_records, m.lost_records)
    );
    let _ = writeln!(
        s,
        "- host {}: `{}`\n",
        m.host_version,
        m.command_line.join(" ")
    );
    s.push_str(TELEMETRY_README);
    s
}
