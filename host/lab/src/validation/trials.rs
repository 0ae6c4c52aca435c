//! The blocks of docs/validation.md on the lab's trial conditions, from the physics robot walking
//! the paper's tripod: what a substrate changes (`substrates`) and what the perturbation platform
//! does to the perturbed leg's load (`perturbation`).

use std::fmt::Write;
use std::path::Path;

use planner::model::Leg;
use planner::terrain::Ground;

use crate::error::Result;
use crate::perturbation::walk_perturbed;
use crate::substrates::walk_on_substrates;
use crate::walk::tripod_table;

/// The `substrates` block: the tripod for two steps on each substrate.
pub fn substrates() -> Result<String> {
    let walks = walk_on_substrates(
        &tripod_table()?,
        &Ground::Flat,
        &physics::substrate::KNOWN,
        2,
    )?;
    let mut s = String::from(
        "The paper's tripod, two steps from power-on on `physics:flat+SUBSTRATE` (mu are ESTIMATES, docs/usage.md):\n\n\
         | substrate | mu | slip LF | LM | LH | RF | RM | RH | all feet | travel per step | largest F_t/F_n |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for w in &walks {
        let _ = write!(s, "| {} | {} |", w.substrate.name(), w.mu);
        for leg in Leg::ALL {
            let _ = write!(s, " {:.1} mm |", w.slip(leg) * 1e3);
        }
        let ratio = w.traction_max.iter().map(|(_, r)| *r).fold(0.0, f64::max);
        let _ = writeln!(
            s,
            " {:.1} mm | {:.1} mm | {:.2} |",
            w.total_slip_m() * 1e3,
            w.per_step_m * 1e3,
            ratio
        );
    }
    Ok(s)
}

/// The `perturbation` block (the lab's rise under RF in step 3 of 5) and its plot
/// (perturbation_load.png: the leg's load step by step, drawn in `plots_dir`), as PNG bytes.
pub fn perturbation(plots_dir: &Path) -> Result<(String, Vec<u8>)> {
    let perturb = crate::perturbation::lab_rise(Leg::RF, 3);
    let platform = perturb.setup;
    let w = walk_perturbed(&tripod_table()?, &Ground::Flat, perturb, 5)?;
    let mut s = format!(
        "The paper's tripod, five steps on `physics:flat`; the lab's platform (rest {}, rise {} ticks, profile velocity {}, {} cycles up) under {} at step {} (from 0); the platform's top rose {:.2} mm. The leg's foot normal force in the first {:.0} ms of each step:\n\n\
         | step | peak | mean |\n|---|---|---|\n",
        platform.rest,
        platform.rise,
        platform.profile_velocity,
        platform.hold_cycles,
        perturb.leg.name(),
        platform.step,
        w.platform_peak_m * 1e3,
        crate::perturbation::WINDOW_S * 1e3,
    );
    for st in &w.steps {
        let mark = if st.step == platform.step {
            " (perturbed)"
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "| {}{mark} | {:.2} N | {:.2} N |",
            st.step, st.peak_n, st.mean_n
        );
    }
    let hit = w.perturbed().map_or(0.0, |x| x.peak_n);
    let _ = writeln!(
        s,
        "\nPerturbed peak against the neighbouring steps' larger: {:+.0} %; the robot walked on ({}).",
        (hit / w.unperturbed_peak_n() - 1.0) * 100.0,
        match w.figures.verdict(0.01) {
            None => "no fall, no sag beyond 1 cm".to_owned(),
            Some(v) => v,
        }
    );
    let bars: Vec<report::perturbation::StepBar> = w
        .steps
        .iter()
        .map(|st| report::perturbation::StepBar {
            step: st.step,
            peak_n: st.peak_n,
            mean_n: st.mean_n,
        })
        .collect();
    std::fs::create_dir_all(plots_dir)?;
    let f = plots_dir.join("perturbation_load.png");
    report::perturbation::plot_step_loads(
        &f,
        perturb.leg.name(),
        crate::perturbation::WINDOW_S * 1e3,
        &bars,
        platform.step,
    )?;
    let png = std::fs::read(&f)?;
    Ok((s, png))
}
