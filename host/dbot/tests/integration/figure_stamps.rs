//! The figures in docs/ that the test command does not regenerate (each takes minutes: a full
//! identification, a learning run) are stamped in `docs/figures.toml` with the command that makes
//! them and two CRC-64s: of the sources they were made from (`inputs`, files or folders) and of
//! the figure files themselves. When the code moves past a figure (a source it depends on
//! changes) or a figure changes without a new stamp, this test fails naming the figure and the
//! command that regenerates it. After regenerating, `DBOT_RESTAMP=1` rewrites the stamps.
//!
//! Every other figure in docs/ is compared with a fresh run by its own test (`validation_doc`,
//! `paper_robot`); `every_figure_in_docs_is_checked_by_a_test` makes sure no figure is left out.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const STAMPS: &str = "docs/figures.toml";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[derive(Debug, Clone, serde::Deserialize)]
struct Stamp {
    name: String,
    command: String,
    figures: Vec<String>,
    inputs: Vec<String>,
    inputs_crc64: String,
    figures_crc64: String,
}

#[derive(Debug, serde::Deserialize)]
struct Stamps {
    figure: Vec<Stamp>,
}

fn read_stamps(root: &Path) -> Vec<Stamp> {
    let text = std::fs::read_to_string(root.join(STAMPS)).expect(STAMPS);
    toml::from_str::<Stamps>(&text)
        .unwrap_or_else(|e| panic!("{STAMPS}: {e}"))
        .figure
}

/// Build products that live beside the sources and are not committed (.gitignore): Python's
/// byte code and the extension module maturin builds into the package.
fn built(name: &str) -> bool {
    name == "__pycache__" || name.ends_with(".pyc") || name.ends_with(".so")
}

/// Every committed file under `rel` (a file or a folder, relative to `root`), sorted, as repo
/// paths.
fn files_under(root: &Path, rel: &str) -> Vec<String> {
    let path = root.join(rel);
    assert!(path.exists(), "{STAMPS}: `{rel}` does not exist");
    if path.is_file() {
        return vec![rel.to_owned()];
    }
    let mut out = Vec::new();
    for e in std::fs::read_dir(&path).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if built(&name) {
            continue;
        }
        out.extend(files_under(root, &format!("{rel}/{name}")));
    }
    out.sort();
    out
}

/// CRC-64/XZ over each file's repo path and bytes, in path order: it changes when any file is
/// added, removed, renamed or edited (a change detector, not a signature).
fn crc64(root: &Path, rels: &[String]) -> String {
    let mut paths: Vec<String> = rels.iter().flat_map(|r| files_under(root, r)).collect();
    paths.sort();
    paths.dedup();
    let crc = crc::Crc::<u64>::new(&crc::CRC_64_XZ);
    let mut d = crc.digest();
    for p in &paths {
        let bytes = std::fs::read(root.join(p)).unwrap();
        d.update(p.as_bytes());
        d.update(&(bytes.len() as u64).to_le_bytes());
        d.update(&bytes);
    }
    format!("{:016x}", d.finalize())
}

/// What is wrong with one stamp, if anything.
fn stale(root: &Path, s: &Stamp) -> Option<String> {
    let inputs = crc64(root, &s.inputs);
    let figures = crc64(root, &s.figures);
    let mut why = Vec::new();
    if inputs != s.inputs_crc64 {
        why.push(format!(
            "the code it was made from has changed (inputs {inputs}, stamped {})",
            s.inputs_crc64
        ));
    }
    if figures != s.figures_crc64 {
        why.push(format!(
            "its files changed without a new stamp (figures {figures}, stamped {})",
            s.figures_crc64
        ));
    }
    (!why.is_empty()).then(|| {
        format!(
            "{STAMPS}: figure `{}` ({}): {}; regenerate it with `{}`, then restamp with \
             `DBOT_RESTAMP=1 cargo nextest run -p dbot -E 'test(/figure_stamps::/)'`",
            s.name,
            s.figures.join(", "),
            why.join("; "),
            s.command
        )
    })
}

fn toml_list(items: &[String]) -> String {
    let quoted: Vec<String> = items.iter().map(|i| format!("{i:?}")).collect();
    format!("[{}]", quoted.join(", "))
}

/// Rewrites `docs/figures.toml` with fresh CRCs, keeping its header comment.
fn restamp(root: &Path, stamps: &[Stamp]) {
    let text = std::fs::read_to_string(root.join(STAMPS)).unwrap();
    let mut out: String = text
        .lines()
        .take_while(|l| l.starts_with('#') || l.is_empty())
        .map(|l| format!("{l}\n"))
        .collect();
    for s in stamps {
        let _ = write!(
            out,
            "[[figure]]\nname = {:?}\ncommand = {:?}\nfigures = {}\ninputs = {}\ninputs_crc64 = {:?}\nfigures_crc64 = {:?}\n\n",
            s.name,
            s.command,
            toml_list(&s.figures),
            toml_list(&s.inputs),
            crc64(root, &s.inputs),
            crc64(root, &s.figures),
        );
    }
    std::fs::write(root.join(STAMPS), out.trim_end().to_owned() + "\n").unwrap();
}

#[test]
fn stamped_figures_are_as_new_as_the_code_they_were_made_from() {
    let root = root();
    let stamps = read_stamps(&root);
    if std::env::var_os("DBOT_RESTAMP").is_some() {
        restamp(&root, &stamps);
    }
    let stamps = read_stamps(&root);
    let problems: Vec<String> = stamps.iter().filter_map(|s| stale(&root, s)).collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_changed_source_or_figure_makes_its_stamp_stale() {
    // A copy of one stamp's inputs and figures in a scratch tree: fresh, then a source edited,
    // then (restored) a figure edited; each named for what changed.
    let root = root();
    let mut s = read_stamps(&root)
        .into_iter()
        .next()
        .expect("at least one stamp");
    let dir = tempfile::tempdir().unwrap();
    let copy = |rel: &str| {
        for f in files_under(&root, rel) {
            let to = dir.path().join(&f);
            std::fs::create_dir_all(to.parent().unwrap()).unwrap();
            std::fs::copy(root.join(&f), to).unwrap();
        }
    };
    s.inputs.iter().chain(&s.figures).for_each(|r| copy(r));
    s.inputs_crc64 = crc64(dir.path(), &s.inputs);
    s.figures_crc64 = crc64(dir.path(), &s.figures);
    assert_eq!(stale(dir.path(), &s), None, "the copy matches its stamp");

    let source = files_under(dir.path(), &s.inputs[0])[0].clone();
    let original = std::fs::read(dir.path().join(&source)).unwrap();
    std::fs::write(dir.path().join(&source), [&original[..], b"\n"].concat()).unwrap();
    let e = stale(dir.path(), &s).expect("an edited source is caught");
    assert!(e.contains("the code it was made from has changed"), "{e}");
    assert!(e.contains(&s.command), "{e}");
    std::fs::write(dir.path().join(&source), &original).unwrap();

    let figure = files_under(dir.path(), &s.figures[0])[0].clone();
    std::fs::write(dir.path().join(figure), b"not the figure").unwrap();
    let e = stale(dir.path(), &s).expect("an edited figure is caught");
    assert!(e.contains("its files changed without a new stamp"), "{e}");
}

#[test]
fn every_figure_in_docs_is_checked_by_a_test() {
    // The figures compared with a fresh run by other tests, and the stamped ones: together every
    // picture under docs/.
    let root = root();
    let checked_elsewhere = ["docs/validation", "docs/paper-robot"];
    let stamped: BTreeSet<String> = read_stamps(&root)
        .into_iter()
        .flat_map(|s| s.figures)
        .flat_map(|f| files_under(&root, &f))
        .collect();
    let pictures = files_under(&root, "docs")
        .into_iter()
        .filter(|f| f.ends_with(".png") || f.ends_with(".gif") || f.ends_with(".svg"));
    let unchecked: Vec<String> = pictures
        .filter(|f| !stamped.contains(f) && !checked_elsewhere.iter().any(|d| f.starts_with(d)))
        .collect();
    assert!(
        unchecked.is_empty(),
        "figures in docs/ that no test regenerates or stamps: {unchecked:?} (stamp them in {STAMPS})"
    );
}
