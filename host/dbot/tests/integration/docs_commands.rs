//! Every `--example NAME` and `--bench NAME` that the docs and bench/run.sh give to reproduce a
//! figure names a target that exists (issue #19, item 12): bench/run.sh built the removed
//! `bench_schur` example and failed for every reader. `bench/run.sh --quick` in scripts/test.sh
//! then runs them; this test says which name is stale without building anything.

use std::path::Path;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
const CRATES: [&str; 11] = [
    "host/planner",
    "host/lab",
    "host/board",
    "host/report",
    "host/dbot",
    "host/physics",
    "dynamixel",
    "protocol",
    "firmware",
    "hil-tests",
    "python",
];

/// `(file, kind, name)` of every `--example NAME` / `--bench NAME` in `text`.
fn targets<'a>(file: &'a str, text: &'a str) -> Vec<(&'a str, &'static str, String)> {
    let mut v = Vec::new();
    for (flag, kind) in [("--example ", "examples"), ("--bench ", "benches")] {
        for (at, _) in text.match_indices(flag) {
            let name: String = text[at + flag.len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
                .collect();
            if !name.is_empty() {
                v.push((file, kind, name));
            }
        }
    }
    v
}

#[test]
fn every_example_and_bench_the_docs_name_exists() {
    let mut files = vec!["bench/run.sh".to_owned(), "README.md".to_owned()];
    for dir in ["docs", "hil-tests", "python"] {
        for e in std::fs::read_dir(Path::new(ROOT).join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "md") {
                files.push(format!(
                    "{dir}/{}",
                    p.file_name().unwrap().to_string_lossy()
                ));
            }
        }
    }
    let mut checked = 0;
    for f in &files {
        let text = std::fs::read_to_string(Path::new(ROOT).join(f)).unwrap();
        for (file, kind, name) in targets(f, &text) {
            let found = CRATES.iter().any(|c| {
                Path::new(ROOT)
                    .join(c)
                    .join(kind)
                    .join(format!("{name}.rs"))
                    .is_file()
            });
            assert!(
                found,
                "{file} names `{kind}` target `{name}`, which no crate has"
            );
            checked += 1;
        }
    }
    // bench_export, the dynamics, ik and cycle benches at least.
    assert!(
        checked >= 4,
        "only {checked} targets found: the search is broken"
    );
}

#[test]
fn the_target_search_finds_what_it_should() {
    let t = targets(
        "x",
        "cargo build -p host --example bench_schur --example a_b\n`--bench cycle`",
    );
    let names: Vec<_> = t.iter().map(|(_, k, n)| (*k, n.as_str())).collect();
    assert_eq!(
        names,
        [
            ("examples", "bench_schur"),
            ("examples", "a_b"),
            ("benches", "cycle")
        ]
    );
}
