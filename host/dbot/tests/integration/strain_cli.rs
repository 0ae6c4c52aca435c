//! `dbot strain` against `dbot sim-strain` on a pseudo-terminal: a good board, a gauge that will
//! not calibrate, a broken gauge, and the servo board's port (a `dbot sim-bus`) refused by name.
//! Expected words and numbers come from the protocol (`../shared/reference/lab-practice.md`):
//! legs LH, RH, LM, RM, LF, RF and gauges troch axial .. femur axial in the board's order.

use crate::cli_support;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

use cli_support::Server;

fn dbot() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dbot"))
}

/// Starts `dbot ARGS --link LINK` and waits for the link to appear.
fn serve(args: &[&str], link: &Path) -> Server {
    let mut c = dbot();
    c.args(args).arg("--link").arg(link);
    cli_support::serve(c, &[link], Duration::from_secs(60), "the server")
}

fn strain(link: &Path) -> Output {
    dbot()
        .args(["strain", "--seconds", "0.3", "--port"])
        .arg(link)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn link(dir: &tempfile::TempDir) -> PathBuf {
    dir.path().join("strain")
}

#[test]
fn a_good_virtual_board_calibrates_and_reads_its_baseline() {
    let dir = tempfile::tempdir().unwrap();
    let l = link(&dir);
    let _s = serve(&["sim-strain"], &l);
    let o = strain(&l);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}{err}");
    assert!(
        out.contains("calibrated: all 36 gauges trimmed into 300 +- 75 counts"),
        "{out}"
    );
    // No strain: every gauge reads the 300 counts calibration trimmed it to.
    let lf = out.lines().find(|l| l.starts_with("LF ")).unwrap();
    assert_eq!(
        lf.split_whitespace().skip(1).collect::<Vec<_>>(),
        ["300.00"; 6]
    );
}

#[test]
fn a_gauge_that_will_not_calibrate_is_named_with_its_value() {
    let dir = tempfile::tempdir().unwrap();
    let l = link(&dir);
    let _s = serve(
        &["sim-strain", "--fault", "no-calibrate:RM_femur_axial"],
        &l,
    );
    let o = strain(&l);
    let (out, err) = text(&o);
    assert!(!o.status.success());
    // RM is the board's leg 3, femur axial its gauge 5.
    assert!(
        out.contains(
            "would not calibrate: RM_femur_axial (board leg 3, gauge 5) (final value 980)"
        ),
        "{out}"
    );
    assert!(
        err.contains(&format!("{}: not every gauge is good", l.display())),
        "{err}"
    );
}

#[test]
fn a_broken_gauge_is_named_and_the_board_port_too() {
    let dir = tempfile::tempdir().unwrap();
    let l = link(&dir);
    let _s = serve(&["sim-strain", "--fault", "unplugged:LF_troch_axial"], &l);
    let o = strain(&l);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}");
    assert!(
        err.contains(&format!(
            "{}: calibration stopped for good: gauge LF_troch_axial (board leg 4, gauge 0) is \
             broken or unplugged",
            l.display()
        )),
        "{err}"
    );
}

#[test]
fn the_servo_boards_port_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let l = dir.path().join("dxl");
    let _s = serve(&["sim-bus", "--quiet"], &l);
    let o = strain(&l);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}");
    assert!(
        err.contains(&format!(
            "{}: no `Waiting on MATLAB...` banner within 5 s",
            l.display()
        )),
        "{err}"
    );
}
