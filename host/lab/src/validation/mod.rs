//! docs/validation.md's run results. The document's prose stays hand written; every figure it
//! quotes from a run sits in a block between `<!-- generated: NAME -->` and
//! `<!-- end generated -->`, and every plot it shows is a PNG next to it (`validation/NAME.png`):
//! [`update`] fills the blocks and writes the plots, or compares both with a fresh run (a test
//! runs `dbot validate --check`, so the document cannot drift from the code). Timings (the
//! `performance` block) are compared as ratios, see [`same_up_to_timing`].
//!
//! The part between `<!-- physics:begin -->` and `<!-- physics:end -->` belongs to another
//! generator ([`crate::paper_robot::block`]) and is kept byte for byte; writing adds an empty pair
//! at the end when it is missing.

pub mod blocks;
pub mod springs;
pub mod strain;
pub mod strain_walking;
pub mod timing;
pub mod trials;
pub mod turning;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use board::files::write_bytes_atomically;

use crate::bail;
use crate::error::{Context, Result};

const OPEN: &str = "<!-- generated: ";
const CLOSE: &str = "<!-- end generated -->";
const PHYSICS_BEGIN: &str = "<!-- physics:begin -->";
const PHYSICS_END: &str = "<!-- physics:end -->";
/// Blocks of timings, compared as ratios.
const TIMED: [&str; 1] = ["performance"];
/// Two timings within this factor of each other match.
const TIMING_RATIO: f64 = 3.0;

/// What [`update`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Generated blocks and plots, counted.
    pub blocks: usize,
    pub plots: usize,
    /// The blocks and plots (`validation/NAME.png`) that differ from a fresh run.
    pub stale: Vec<String>,
}

/// Runs everything the document quotes (or only `part` of it: its blocks and plots, the others
/// left as they are) and compares it with `doc`; with `write`, fills the document's blocks in place
/// and writes its plots to `validation/` beside it. The comparison's plots (megabytes) go to
/// `plots`, else to a scratch directory removed afterwards.
pub fn update(
    doc: &Path,
    write: bool,
    plots: Option<&Path>,
    part: Option<blocks::Part>,
) -> Result<Outcome> {
    let text =
        std::fs::read_to_string(doc).with_context(|| format!("reading {}", doc.display()))?;
    let scratch = std::env::temp_dir().join(format!(
        "dbot-validate-{}-{}",
        std::process::id(),
        part.map_or("all", blocks::Part::name)
    ));
    let plots_dir = plots.unwrap_or(&scratch);
    let generated = match part {
        Some(part) => blocks::generate_part(part, plots_dir),
        None => blocks::generate(plots_dir),
    };
    let _ = std::fs::remove_dir_all(&scratch);
    let generated = generated?;
    let (new, mut stale) = fill_with(&text, &generated.blocks, part.is_some())
        .with_context(|| doc.display().to_string())?;
    let plot_dir: PathBuf = doc.parent().unwrap_or(Path::new(".")).join("validation");
    for (name, bytes) in &generated.plots {
        let f = plot_dir.join(name);
        if std::fs::read(&f).ok().as_ref() != Some(bytes) {
            stale.push(format!("validation/{name}"));
            if write {
                std::fs::create_dir_all(&plot_dir)
                    .with_context(|| format!("creating {}", plot_dir.display()))?;
                write_bytes_atomically(&f, bytes)?;
            }
        }
    }
    if write {
        write_bytes_atomically(doc, new.as_bytes())?;
    }
    Ok(Outcome {
        blocks: generated.blocks.len(),
        plots: generated.plots.len(),
        stale,
    })
}

/// Replaces every block's body outside the physics part; returns the new text and the names of
/// blocks whose body changed (a missing physics part counts as `physics markers`).
pub fn fill(text: &str, blocks: &BTreeMap<&str, String>) -> Result<(String, Vec<String>)> {
    fill_with(text, blocks, false)
}

/// [`fill`]; with `partial`, a block the map does not hold is kept as it is (a part's check).
fn fill_with(
    text: &str,
    blocks: &BTreeMap<&str, String>,
    partial: bool,
) -> Result<(String, Vec<String>)> {
    let mut stale = Vec::new();
    let (outside, physics, after) = match (text.find(PHYSICS_BEGIN), text.find(PHYSICS_END)) {
        (Some(b), Some(e)) if b < e => {
            let end = e + PHYSICS_END.len();
            (&text[..b], &text[b..end], &text[end..])
        }
        (None, None) => {
            stale.push("physics markers".to_string());
            (text, "", "")
        }
        _ => bail!("`{PHYSICS_BEGIN}` and `{PHYSICS_END}` must both be there, in that order"),
    };
    let mut seen = Vec::new();
    let mut out = fill_part(outside, blocks, partial, &mut seen, &mut stale)?;
    if physics.is_empty() {
        if !out.ends_with('\n') {
            out.push('\n');
        }
        out += &format!("\n{PHYSICS_BEGIN}\n{PHYSICS_END}\n");
    } else {
        out += physics;
        out += &fill_part(after, blocks, partial, &mut seen, &mut stale)?;
    }
    for name in blocks.keys() {
        if !seen.iter().any(|s| s == name) {
            bail!("block `{name}` is missing (add `{OPEN}{name} -->` ... `{CLOSE}`)");
        }
    }
    Ok((out, stale))
}

/// Fills the generated blocks of one part of the document.
fn fill_part(
    text: &str,
    blocks: &BTreeMap<&str, String>,
    partial: bool,
    seen: &mut Vec<String>,
    stale: &mut Vec<String>,
) -> Result<String> {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(OPEN) {
        let after = &rest[i + OPEN.len()..];
        let end_name = after
            .find("-->")
            .context("unterminated generated-block marker")?;
        let name = after[..end_name].trim().to_string();
        let body_start = i + OPEN.len() + end_name + 3;
        let close = rest[body_start..]
            .find(CLOSE)
            .with_context(|| format!("block `{name}` has no `{CLOSE}`"))?;
        let old = &rest[body_start..body_start + close];
        let Some(fresh) = blocks.get(name.as_str()) else {
            if !partial || blocks::Part::of_block(&name).is_none() {
                bail!("block `{name}` is not one dbot validate generates");
            }
            let end = body_start + close + CLOSE.len();
            out += &rest[..end];
            rest = &rest[end..];
            continue;
        };
        let fresh = format!("\n{}\n", fresh.trim_end());
        let same = if TIMED.contains(&name.as_str()) {
            same_up_to_timing(old, &fresh)
        } else {
            old == fresh
        };
        if !same {
            stale.push(name.clone());
        }
        out += &rest[..body_start];
        out += &fresh;
        out += CLOSE;
        rest = &rest[body_start + close + CLOSE.len()..];
        seen.push(name);
    }
    out += rest;
    Ok(out)
}

/// Whether two timing blocks agree: the same text around the numbers, and, when both were measured
/// with the same build profile, every number within [`TIMING_RATIO`] of the other's (a debug
/// build's timings say nothing about a release build's, so across profiles only the text counts).
pub fn same_up_to_timing(old: &str, fresh: &str) -> bool {
    let split = |s: &str| {
        let mut words = String::new();
        let mut numbers = Vec::new();
        let mut num = String::new();
        for c in s.chars() {
            if c.is_ascii_digit() || (c == '.' && !num.is_empty()) {
                num.push(c);
            } else {
                if !num.is_empty() {
                    numbers.push(num.trim_end_matches('.').parse::<f64>().unwrap_or(f64::NAN));
                    words.push('#');
                    num.clear();
                }
                words.push(c);
            }
        }
        if !num.is_empty() {
            numbers.push(num.parse::<f64>().unwrap_or(f64::NAN));
            words.push('#');
        }
        let profile = ["debug build", "release build"]
            .into_iter()
            .find(|p| words.contains(p));
        let words = words
            .replace("debug build", "PROFILE")
            .replace("release build", "PROFILE");
        (words, numbers, profile)
    };
    let (wa, na, pa) = split(old);
    let (wb, nb, pb) = split(fresh);
    if wa != wb || na.len() != nb.len() {
        return false;
    }
    pa != pb
        || na
            .iter()
            .zip(&nb)
            .all(|(a, b)| a == b || (a / b <= TIMING_RATIO && b / a <= TIMING_RATIO))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timings_match_within_a_factor_of_three_of_the_same_profile_only() {
        let a = "| x | 1.28 ms |\n(release build, 51 runs)";
        assert!(same_up_to_timing(
            a,
            "| x | 3.70 ms |\n(release build, 51 runs)"
        ));
        // 1.28 x 3 = 3.84 ms: 3.90 is over.
        assert!(!same_up_to_timing(
            a,
            "| x | 3.90 ms |\n(release build, 51 runs)"
        ));
        // Another build profile: only the text around the numbers is compared.
        assert!(same_up_to_timing(
            a,
            "| x | 40.00 ms |\n(debug build, 5 runs)"
        ));
        assert!(!same_up_to_timing(
            a,
            "| y | 40.00 ms |\n(debug build, 5 runs)"
        ));
    }

    #[test]
    fn the_physics_part_is_kept_and_added_when_missing() {
        let blocks: BTreeMap<&str, String> = [("a", "new".to_string())].into();
        let doc = format!(
            "x\n{OPEN}a -->\nold\n{CLOSE}\n{PHYSICS_BEGIN}\n{OPEN}p -->\nmine\n{CLOSE}\n{PHYSICS_END}\ny\n"
        );
        let (out, stale) = fill(&doc, &blocks).unwrap();
        assert_eq!(stale, vec!["a".to_string()]);
        assert!(out.contains(&format!("{OPEN}a -->\nnew\n{CLOSE}")));
        // The physics part's own block is neither filled nor refused.
        assert!(out.contains(&format!(
            "{PHYSICS_BEGIN}\n{OPEN}p -->\nmine\n{CLOSE}\n{PHYSICS_END}\ny\n"
        )));
        let (out, stale) = fill(&format!("x\n{OPEN}a -->\nnew\n{CLOSE}\n"), &blocks).unwrap();
        assert_eq!(stale, vec!["physics markers".to_string()]);
        assert!(out.ends_with(&format!("\n{PHYSICS_BEGIN}\n{PHYSICS_END}\n")));
    }

    #[test]
    fn a_parts_check_keeps_the_other_parts_blocks_and_refuses_a_block_no_part_lists() {
        // The sweep part's block against a document that also holds the plans part's `weight`.
        let blocks: BTreeMap<&str, String> = [("sweep", "new".to_string())].into();
        let doc = format!(
            "{OPEN}weight -->\nold weight\n{CLOSE}\n{OPEN}sweep -->\nold\n{CLOSE}\n{PHYSICS_BEGIN}\n{PHYSICS_END}\n"
        );
        let (out, stale) = fill_with(&doc, &blocks, true).unwrap();
        assert_eq!(stale, vec!["sweep".to_string()]);
        assert!(out.contains(&format!("{OPEN}weight -->\nold weight\n{CLOSE}")));
        assert!(out.contains(&format!("{OPEN}sweep -->\nnew\n{CLOSE}")));
        // The whole check refuses the block it does not generate; so does a part's, for a name
        // no part lists.
        let e = fill(&doc, &blocks).unwrap_err().to_string();
        assert!(
            e.contains("block `weight` is not one dbot validate generates"),
            "{e}"
        );
        let doc = format!("{OPEN}nobodys -->\nx\n{CLOSE}\n{PHYSICS_BEGIN}\n{PHYSICS_END}\n");
        let e = fill_with(&doc, &blocks, true).unwrap_err().to_string();
        assert!(
            e.contains("block `nobodys` is not one dbot validate generates"),
            "{e}"
        );
    }
}
