//! docs/usage.md's transcript of the board commands ("What the board commands print") is what
//! those commands print today: each `$ dbot ...` line is run, in order, on a fresh virtual robot
//! set up as the page says, and its output must be the lines below it, word for word (the virtual
//! robot runs on simulated time, so the figures repeat).

use crate::cli_support::{in_dir, stdout};
use std::path::Path;

/// The transcript block: (command words after `dbot`, the lines it printed).
fn transcript() -> Vec<(String, Vec<String>)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/usage.md");
    let text = std::fs::read_to_string(path).unwrap();
    let start = text
        .find("What the board commands print")
        .expect("docs/usage.md: the board commands' transcript");
    let block = text[start..]
        .split("```text\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a text block after it");
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for line in block.lines() {
        match line.strip_prefix("$ dbot ") {
            Some(cmd) => out.push((cmd.to_owned(), Vec::new())),
            None => out
                .last_mut()
                .expect("the block starts with a command")
                .1
                .push(line.to_owned()),
        }
    }
    out
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let o = in_dir(dir).args(args).output().unwrap();
    assert!(
        o.status.success(),
        "dbot {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    stdout(&o)
}

#[test]
fn the_usage_guides_board_transcript_is_what_the_commands_print() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The set-up the page names: the README's plan's table in slot 1 of a new virtual robot.
    ok(d, &["plan", "--out", "plan"]);
    ok(d, &["table", "--plan", "plan", "--out", "gait.dbgt"]);
    let port = ["--port", "virtual:lab.flash"];
    let mut upload = vec!["upload", "--table", "gait.dbgt", "--slot", "1", "--create"];
    upload.extend(port);
    ok(d, &upload);
    let steps = transcript();
    assert!(steps.len() >= 5, "{steps:?}");
    for (cmd, expected) in steps {
        let mut args: Vec<&str> = cmd.split_whitespace().collect();
        args.extend(port);
        let o = in_dir(d).args(&args).output().unwrap();
        // What a person sees: stdout, then stderr (a refusal's words).
        let printed = format!("{}{}", stdout(&o), String::from_utf8_lossy(&o.stderr));
        let printed: Vec<&str> = printed.lines().collect();
        assert_eq!(printed, expected, "$ dbot {cmd}");
    }
}
