//! Test helper: runs `dbot sim-bus` in the background on a link in a temporary directory and
//! collects what it prints; the process is killed when the helper is dropped.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

pub struct SimBus {
    child: Child,
    // Held while the server runs: wall-clock tests of the pty server run one at a time, so that
    // two of them do not starve each other's servers on a small CI machine.
    _lock: nix::fcntl::Flock<std::fs::File>,
    _dir: tempfile::TempDir,
    link: PathBuf,
    log: Arc<Mutex<String>>,
}

impl SimBus {
    /// Starts `dbot sim-bus --servos N --baud B --return-delay RD` (RD in 2 us units).
    pub fn start(servos: u8, baud: u32, return_delay: u8) -> Self {
        let lock_path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dbot-sim-bus.lock");
        let file = std::fs::File::create(&lock_path).expect("create the sim-bus lock file");
        let _lock = nix::fcntl::Flock::lock(file, nix::fcntl::FlockArg::LockExclusive)
            .map_err(|(_, e)| e)
            .expect("lock the sim-bus lock file");
        let dir = tempfile::tempdir().expect("temp dir");
        let link = dir.path().join("bus");
        let mut child = Command::new(env!("CARGO_BIN_EXE_dbot"))
            .args([
                "sim-bus",
                "--servos",
                &servos.to_string(),
                "--baud",
                &baud.to_string(),
            ])
            .args(["--return-delay", &return_delay.to_string(), "--link"])
            .arg(&link)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn dbot sim-bus");
        let log = Arc::new(Mutex::new(String::new()));
        for stream in [
            Box::new(child.stdout.take().unwrap()) as Box<dyn std::io::Read + Send>,
            Box::new(child.stderr.take().unwrap()),
        ] {
            let log = log.clone();
            std::thread::spawn(move || {
                for line in BufReader::new(stream).lines().map_while(Result::ok) {
                    let mut l = log.lock().unwrap();
                    l.push_str(&line);
                    l.push('\n');
                }
            });
        }
        let t0 = Instant::now();
        while !link.exists() {
            if let Some(status) = child.try_wait().unwrap() {
                panic!("dbot sim-bus exited with {status}: {}", log.lock().unwrap());
            }
            assert!(
                t0.elapsed() < Duration::from_secs(20),
                "dbot sim-bus did not create {}",
                link.display()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        Self {
            child,
            _lock,
            _dir: dir,
            link,
            log,
        }
    }

    pub fn link(&self) -> &Path {
        &self.link
    }

    pub fn log(&self) -> String {
        self.log.lock().unwrap().clone()
    }
}

impl Drop for SimBus {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
