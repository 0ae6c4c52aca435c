//! Running `dbot` as a process for the CLI tests: in a directory of its own (no setup file from
//! `DBOT_CONFIG`, that directory as the config home), optionally on the virtual robot whose flash
//! is `robot.flash` there, and what it printed as text; and a server process (`dbot sim-strain`,
//! `dbot sim-bus`) waited for until its link appears and killed when dropped.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// `dbot` to be run in `dir`, with no setup file and `dir` as its config home.
pub fn in_dir(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dbot"));
    c.current_dir(dir)
        .env_remove("DBOT_CONFIG")
        .env("XDG_CONFIG_HOME", dir);
    c
}

/// `dbot ARGS --port virtual:DIR/robot.flash --create` run in `dir`: each test starts with no
/// store, the first command creates it.
pub fn on_virtual(dir: &Path, args: &[&str]) -> Output {
    in_dir(dir)
        .args(args)
        .arg("--port")
        .arg(format!("virtual:{}", dir.join("robot.flash").display()))
        .arg("--create")
        .output()
        .unwrap()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Standard output then standard error.
pub fn text(o: &Output) -> String {
    format!("{}{}", stdout(o), stderr(o))
}

/// A server process, killed when dropped.
pub struct Server(pub Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts `c` (its standard output dropped) and waits until every one of `links` appears, for at
/// most `within`; `what` names the server in the failure.
pub fn serve(mut c: Command, links: &[&Path], within: Duration, what: &str) -> Server {
    let child = c.stdout(Stdio::null()).spawn().unwrap();
    let until = Instant::now() + within;
    while links.iter().any(|l| std::fs::symlink_metadata(l).is_err()) {
        assert!(Instant::now() < until, "{what} never made {links:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
    Server(child)
}
